// Fuzz target: the Bézier surface (.s), parseSurface.
#include "runtime/files/Surfaces.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto s = lcjit::runtime::parseSurface(lcjit::fuzz::text(data, size), "fuzz.s");
  lcjit::fuzz::check(s, "fuzz.s");
  return 0;
}
