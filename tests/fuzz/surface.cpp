// Fuzz target: the Bézier surface (.s), parseSurface, then every patch tessellated as the turtle
// draws it.
#include "runtime/files/Surfaces.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto s = lcjit::runtime::parseSurface(lcjit::fuzz::text(data, size), "fuzz.s");
  if (!lcjit::fuzz::check(s, "fuzz.s")) return 0;
  for (size_t k = 0; k < s->patches.size() && k < 8; ++k) (void)s->tessellate(k, 3, 4);
  (void)s->controlPoint(int(size % 40));
  return 0;
}
