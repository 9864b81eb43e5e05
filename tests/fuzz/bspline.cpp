// Fuzz target: the B-spline surface (`bsurface:` files), parseBSpline, then the net sampled and
// meshed as the turtle draws it, refined and coarsened.
#include "runtime/files/BSplineSurfaces.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> warnings;
  lcjit::runtime::BSplineFile f = lcjit::runtime::parseBSpline(lcjit::fuzz::text(data, size), "fuzz.s", warnings);
  lcjit::runtime::BSplineNet& net = f.net;
  if (net.empty()) return 0;
  (void)lcjit::runtime::BSplineNet::mesh(net.sample(4, 3), 4, 3);
  if (net.rows() < 40 && net.columns() < 40) {
    net.refineRows();
    net.coarsenColumns();
    (void)net.point(3.5, 4);
  }
  return 0;
}
