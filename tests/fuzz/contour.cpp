// Fuzz target: one contour (.con), Contour::parse.
#include "runtime/files/Contours.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto c = lcjit::runtime::Contour::parse(lcjit::fuzz::text(data, size), "fuzz.con");
  lcjit::fuzz::check(c, "fuzz.con");
  return 0;
}
