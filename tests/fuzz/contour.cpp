// Fuzz target: one contour (.con), Contour::parse, then what the turtle and the curve functions do
// with it: resampling, points and normals along it, a scale and a recalculation.
#include "runtime/files/Contours.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto c = lcjit::runtime::Contour::parse(lcjit::fuzz::text(data, size), "fuzz.con");
  if (!lcjit::fuzz::check(c, "fuzz.con")) return 0;
  (void)c->sampled(c->drawDivisions(size % 40));
  c->setDivisions(int(size % 300));
  for (float t : {0.0f, 0.3f, 1.0f}) {
    (void)c->pointAt(t);
    (void)c->normalAt(t);
  }
  c->setControlPoint(int(size % 7), V3f(1, 2, 3));
  c->scale(V3f(2, 0.5f, 1));
  c->recalculate();
  return 0;
}
