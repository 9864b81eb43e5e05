// Fuzz target: the B-spline surface (`bsurface:` files), parseBSpline.
#include "runtime/files/BSplineSurfaces.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> warnings;
  lcjit::runtime::BSplineFile f = lcjit::runtime::parseBSpline(lcjit::fuzz::text(data, size), "fuzz.s", warnings);
  (void)f;
  return 0;
}
