// A design's drawn shapes as runtime::Geometry (DesignGeometry.h).
#include "runtime/cfdg/DesignGeometry.h"

#include <cmath>

namespace lcjit::runtime::cfdg {

Geometry geometryOf(const Expansion& e, const Framing& f, const ExpandOptions& o, int circleSides) {
  Geometry g;
  auto vertex = [&](const Affine& m, double x, double y, int32_t colour) {
    m.apply(x, y);
    MeshVertex v;
    v.position = V3f(float(x), float(y), 0.f);
    v.normal = V3f(0.f, 0.f, 0.f);  // unlit: the shape's own colour
    v.color = colour;
    g.vertices.push_back(v);
    return uint32_t(g.vertices.size() - 1);
  };
  auto byte = [](double v) { return uint8_t(std::lround(std::fmin(std::fmax(v, 0.0), 1.0) * 255.0)); };
  const double h = 0.5 / std::cos(3.14159265358979323846 / 6.0);
  for (const FinishedShape& s : e.shapes) {
    if (s.shape == 3 || !drawn(s, f, o))
      continue;  // FILL covers the picture, not a place: not a shape of the scene
    const std::array<double, 4>& rgba = e.colours[s.colour];
    const int32_t colour = rgbColor(byte(rgba[0]), byte(rgba[1]), byte(rgba[2]));
    const Affine& m = s.transform;
    // Counter-clockwise seen from +z: the front faces the default view.
    const bool flipped = m.determinant() < 0;
    auto triangle = [&](uint32_t a, uint32_t b, uint32_t c) {
      g.indices.insert(g.indices.end(), {a, flipped ? c : b, flipped ? b : c});
    };
    if (s.shape == 1) {
      uint32_t a = vertex(m, -0.5, -0.5, colour), b = vertex(m, 0.5, -0.5, colour), c = vertex(m, 0.5, 0.5, colour),
               d = vertex(m, -0.5, 0.5, colour);
      triangle(a, b, c);
      triangle(a, c, d);
    } else if (s.shape == 2) {
      triangle(vertex(m, -0.5, -h / 2.0, colour), vertex(m, 0.5, -h / 2.0, colour), vertex(m, 0.0, h, colour));
    } else {
      uint32_t centre = vertex(m, 0, 0, colour), first = 0, previous = 0;
      for (int k = 0; k <= circleSides; ++k) {
        double a = 2.0 * 3.14159265358979323846 * (k % circleSides) / circleSides;
        uint32_t v = k == circleSides ? first : vertex(m, 0.5 * std::cos(a), 0.5 * std::sin(a), colour);
        if (k == 0) first = v;
        else triangle(centre, previous, v);
        previous = v;
      }
    }
  }
  if (!g.indices.empty()) g.runs.push_back({0, uint32_t(g.indices.size()), -1, PolygonFill::Solid});
  return g;
}

}  // namespace lcjit::runtime::cfdg
