// The turtle's drawing (see Turtle.h): each predefined shape becomes triangles, segments, discs
// or labels in the Geometry, with lpfg's placement rules, and grows lpfg's bounding box.
#include <algorithm>
#include <cmath>

#include "runtime/ModelGuard.h"
#include "runtime/turtle/Shapes.h"
#include "runtime/turtle/Turtle.h"

namespace lcjit::runtime {
namespace {

// A surface's divisions: the turtle's (SetUPrecision & co.) if set, else the surface's own, else
// lpfg's default.
int precision(int turtle, int own = 0) { return turtle ? turtle : own ? own : kDefaultSurfaceDivisions; }

constexpr float kEpsilon = 1e-5f;
constexpr float kPi = 3.14159265358979323846f;

V3f cross(V3f a, V3f b) { return a % b; }

}  // namespace

MeshVertex Turtle::vertex(V3f p, V3f n, float u, float v) const {
  MeshVertex m;
  m.position = p;
  m.normal = n;
  m.uv = V2f(u, v);
  m.color = state_.color;
  return m;
}

int Turtle::circleSides() const {
  return std::min(state_.contourSides > 0 ? state_.contourSides : view_->contourSides, kMaxDrawnRingSides);
}

// Samples per generalized-cylinder ring, lpfg's rule (Contour::drawDivisions): ContourSides(n)
// gives n points (n-1 sides: lpfg's quirk, kept for the same picture), else the contour file's
// `samples:`, else the view file's `contour sides:` + 1.
int Turtle::cylinderDivisions(int contour) const {
  if (setup_.contours)
    if (const Contour* c = setup_.contours->get(contour))
      return std::min(c->drawDivisions(state_.contourSides, view_->contourSides), kMaxDrawnRingSides + 1);
  return std::min(state_.contourSides > 0 ? state_.contourSides : view_->contourSides + 1, kMaxDrawnRingSides + 1);
}

CylinderPoint Turtle::cylinderHere() const {
  const TurtleState& t = state_;
  return CylinderPoint{t.position, t.heading, t.left, t.up, t.width, t.widthUp, t.contour, t.contour2, t.blend};
}

// Contour `id` sampled at `divisions` points (a closed contour's last point repeats its first).
// Id 0 and unknown ids give lpfg's default circle: point i = (sin 2πi/n, cos 2πi/n), i.e.
// starting on +U and turning towards +L.
const ContourSamples& Turtle::ring(int contour, int divisions) {
  auto key = std::make_pair(contour, divisions);
  auto it = rings_.find(key);
  if (it != rings_.end()) return it->second;
  const Contour* c = setup_.contours ? setup_.contours->get(contour) : nullptr;
  ContourSamples s = c ? c->sampled(divisions) : Contour::defaultCircle().sampled(divisions);
  return rings_.emplace(key, std::move(s)).first->second;
}

void Turtle::drawSegment(const TurtleState& before, float length) {
  TurtleState& t = state_;
  switch (view_->lineStyle) {
    case LineStyle::Pixel:
      out_->addSegment({before.position, t.position, t.width, t.color});
      break;
    case LineStyle::Polygon: {
      // A flat band facing the viewer, the turtle width wide (model units).
      V3f vn = setup_.viewDirection;
      V3f a = cross(before.heading, vn);
      if (a.Length() < kEpsilon) break;
      V3f s0 = a.Normalized() * (t.width / 2);
      V3f b = cross(t.heading, vn);
      V3f s1 = b.Length() < kEpsilon ? s0 : b.Normalized() * (t.width / 2);
      V3f n = -vn;
      out_->useTexture(-1);
      uint32_t i0 = out_->addVertex(vertex(before.position - s0, n));
      uint32_t i1 = out_->addVertex(vertex(before.position + s0, n));
      uint32_t i2 = out_->addVertex(vertex(t.position + s1, n));
      uint32_t i3 = out_->addVertex(vertex(t.position - s1, n));
      out_->addTriangle(i0, i2, i1);  // counter-clockwise as the viewer sees it
      out_->addTriangle(i0, i3, i2);
      break;
    }
    case LineStyle::Cylinder: {
      // A plain F: its own frustum in the current contour (a blend applies inside StartGC only).
      CylinderPoint a{before.position, before.heading, before.left, before.up, before.width, before.widthUp,
                      before.contour, before.contour, 0};
      CylinderPoint b = cylinderHere();
      b.contour2 = b.contour;
      b.blend = 0;
      drawFrustum(a, b, length, false);
      break;
    }
  }
}

// A frustum between two rings; each ring is the (blended) contour scaled by width/2 along L and
// widthUp/2 along U in its own frame. Texture v runs along the length (TextureVCoeff per unit).
// The ring of a cylinder point: the (blended) contour scaled by width/2 along L and widthUp/2
// along U in the point's own frame, texture u = i/(n−1) around and v as given.
void Turtle::ringVertices(const CylinderPoint& c, float v, std::vector<MeshVertex>& out) {
  int divisions = cylinderDivisions(c.contour);
  const ContourSamples* samples = &ring(c.contour, divisions);
  ContourSamples blended;
  if (c.blend > 0 && c.contour2 != c.contour) {
    blended = blendContours(*samples, ring(c.contour2, divisions), c.blend);
    samples = &blended;
  }
  size_t n = samples->points.size();
  for (size_t i = 0; i < n; ++i) {
    V3f q = samples->points[i], m = samples->normals[i];
    V3f p = c.position + c.left * (q.x * c.scaleP / 2) + c.up * (q.y * c.scaleQ / 2) + c.heading * q.z;
    V3f nn = c.left * m.x + c.up * m.y + c.heading * m.z;
    if (nn.Length() > 0) nn.Normalize();
    out.push_back(vertex(p, nn, n > 1 ? (float)i / (float)(n - 1) : 0, v));
  }
}

// A frustum between two rings. Texture v runs along the length (TextureVCoeff per unit) and
// wraps once past 1. `tapered cylinders: on` replaces the contour normals of a generalized
// cylinder by the faces' own.
void Turtle::drawFrustum(const CylinderPoint& a, const CylinderPoint& b, float length, bool inCylinder) {
  TurtleState& t = state_;
  float v0 = t.textureV;
  float v1 = v0 + (inCylinder && length == 0 ? t.textureVCoeff : length * t.textureVCoeff);
  std::vector<MeshVertex>& ra = ringA_;
  std::vector<MeshVertex>& rb = ringB_;
  ra.clear();
  rb.clear();
  ringVertices(a, v0, ra);
  ringVertices(b, v1, rb);
  t.textureV = v1 > 1 ? v1 - 1 : v1;
  size_t n = ra.size() < rb.size() ? ra.size() : rb.size();
  if (inCylinder && view_->taperedCylinders)
    for (size_t i = 0; i + 1 < n; ++i) {
      V3f g = (rb[i].position - ra[i].position) % (ra[i + 1].position - ra[i].position);
      if (g.Length() > 0) ra[i].normal = rb[i].normal = g.Normalized();
    }
  out_->useTexture(t.texture);
  uint32_t base = (uint32_t)out_->vertices.size();
  for (size_t i = 0; i < n; ++i) {
    out_->vertices.push_back(ra[i]);
    out_->vertices.push_back(rb[i]);
  }
  for (uint32_t i = 0; i + 1 < n; ++i) {
    uint32_t b0 = base + 2 * i, e0 = b0 + 1, b1 = b0 + 2, e1 = b0 + 3;
    out_->addTriangle(b0, e0, b1);
    out_->addTriangle(b1, e0, e1);
  }
}

void Turtle::extendAlongF(const TurtleState& before) {
  const TurtleState& t = state_;
  switch (view_->lineStyle) {
    case LineStyle::Pixel:
      extend(before.position);
      extend(t.position);
      break;
    case LineStyle::Polygon:
      for (const TurtleState* s : {&before, &t}) {
        extend(s->position + s->left * (0.5f * s->width));
        extend(s->position - s->left * (0.5f * s->width));
      }
      break;
    case LineStyle::Cylinder: {
      // Inside a generalized cylinder the start takes the width its last point had.
      VolumeState& v = volume_;
      if (!v.inCylinder) {
        v.width = before.width;
        v.widthUp = before.widthUp;
      }
      auto widen = [&](const TurtleState& s, float w, float wUp) {
        extend(s.position + s.left * 0.5f * w * v.leftPos);
        extend(s.position - s.left * 0.5f * w * v.leftNeg);
        extend(s.position + s.up * 0.5f * wUp * v.upPos);
        extend(s.position - s.up * 0.5f * wUp * v.upNeg);
      };
      widen(before, v.width, v.widthUp);
      widen(t, t.width, t.widthUp);
      if (v.inCylinder) {
        v.width = t.width;
        v.widthUp = t.widthUp;
      }
      break;
    }
  }
}

// An unknown id leaves the extent as it was, as in lpfg.
void Turtle::selectContourExtent(int id1, int id2, float blend) {
  static const Contour circle = Contour::defaultCircle();
  auto find = [&](int id) -> const Contour* {
    if (setup_.contours) return setup_.contours->get(id);
    return id == 0 ? &circle : nullptr;
  };
  const Contour* a = find(id1);
  const Contour* b = find(id2);
  if (!a || !b) return;
  V3f lo = (1.f - blend) * a->extentMin() + blend * b->extentMin();
  V3f hi = (1.f - blend) * a->extentMax() + blend * b->extentMax();
  VolumeState& v = volume_;
  v.leftPos = hi.x > 0.f ? hi.x : 0.f;
  v.leftNeg = lo.x < 0.f ? -lo.x : 0.f;
  v.upPos = hi.y > 0.f ? hi.y : 0.f;
  v.upNeg = lo.y < 0.f ? -lo.y : 0.f;
}

// `capped cylinders: on`: a fan from the ring's centroid. lpfg faces both caps back along the
// ring's heading (−H), the end cap included.
void Turtle::drawCap(const CylinderPoint& c) {
  std::vector<MeshVertex> r;
  ringVertices(c, 0, r);
  if (r.size() < 4) return;
  r.pop_back();  // the closing duplicate
  V3f centre(0, 0, 0);
  for (const MeshVertex& m : r) centre += m.position;
  centre /= (float)r.size();
  V3f n = -c.heading;
  out_->useTexture(-1);
  uint32_t mid = out_->addVertex(vertex(centre, n));
  uint32_t first = (uint32_t)out_->vertices.size();
  for (MeshVertex m : r) {
    m.normal = n;
    out_->addVertex(m);
  }
  for (uint32_t i = 0; i < r.size(); ++i) {
    uint32_t a = first + i, b = first + (i + 1) % (uint32_t)r.size();
    V3f g = (out_->vertices[a].position - centre) % (out_->vertices[b].position - centre);
    if (g * n >= 0) out_->addTriangle(mid, a, b);
    else out_->addTriangle(mid, b, a);
  }
}

void Turtle::startCylinder() {
  TurtleState& t = state_;
  if (view_->lineStyle != LineStyle::Cylinder) return;  // lpfg: generalized cylinders need cylinder lines
  if (t.cylinderOn && !t.cylinderInherited) return;
  t.cylinderOn = true;
  t.cylinderInherited = false;
  t.cylinder = cylinderHere();
  if (out_ && view_->cappedCylinders) drawCap(t.cylinder);
}

void Turtle::endCylinder() {
  TurtleState& t = state_;
  if (out_ && t.cylinderOn && view_->cappedCylinders) drawCap(t.cylinder);
  t.cylinderOn = t.cylinderInherited = false;
}

// Circle(r) & co.: a disc (or ring when inner > 0) in the HL plane facing U; front circles stay
// abstract discs that face the camera.
void Turtle::drawCircle(float r, bool front, float inner) {
  TurtleState& t = state_;
  if (inner < 0) inner = 0;
  if (front) {
    out_->addDisc({t.position, inner, r, t.color});
    extend(t.position - V3f(r, r, r));
    extend(t.position + V3f(r, r, r));
    return;
  }
  if (r <= 0) return;
  int n = circleSides();
  out_->useTexture(-1);
  auto at = [&](int k, float radius) {
    float a = 2 * kPi * (float)k / (float)n;
    return t.position + (t.left * -std::sin(a) + t.heading * std::cos(a)) * radius;
  };
  // Seen from +U the angle runs clockwise (H towards −L); triangles are wound so +U is the front.
  if (inner <= 0) {
    uint32_t c = out_->addVertex(vertex(t.position, t.up));
    uint32_t first = (uint32_t)out_->vertices.size();
    for (int k = 0; k < n; ++k) out_->addVertex(vertex(at(k, r), t.up));
    for (int k = 0; k < n; ++k) out_->addTriangle(c, first + (uint32_t)((k + 1) % n), first + (uint32_t)k);
  } else {
    uint32_t first = (uint32_t)out_->vertices.size();
    for (int k = 0; k < n; ++k) {
      out_->addVertex(vertex(at(k, inner), t.up));
      out_->addVertex(vertex(at(k, r), t.up));
    }
    for (int k = 0; k < n; ++k) {
      uint32_t i0 = first + 2 * k, o0 = i0 + 1, i1 = first + 2 * ((k + 1) % n), o1 = i1 + 1;
      out_->addTriangle(i0, i1, o0);
      out_->addTriangle(o0, i1, o1);
    }
  }
  extend(t.position + t.heading * r);
  extend(t.position - t.heading * r);
  extend(t.position + t.left * r);
  extend(t.position - t.left * r);
}

// A sphere as lpfg draws it (GLU): `contour sides` slices (at most kMaxDrawnSphereSlices), (sides+1)/2
// stacks, poles on world Z.
void Turtle::drawSphere(float r) {
  TurtleState& t = state_;
  if (r <= 0) return;
  int slices = std::min(circleSides(), kMaxDrawnSphereSlices), stacks = (slices + 1) / 2;
  if (stacks < 2) stacks = 2;
  out_->useTexture(-1);
  uint32_t first = (uint32_t)out_->vertices.size();
  for (int j = 0; j <= stacks; ++j) {
    ModelGuard::checkpoint();  // a stop asked for ends a big sphere here (never a forced jump)
    float rho = kPi * (float)j / (float)stacks;
    for (int i = 0; i <= slices; ++i) {
      float theta = 2 * kPi * (float)(i % slices) / (float)slices;
      V3f n(std::sin(rho) * std::sin(theta), std::sin(rho) * std::cos(theta), std::cos(rho));
      out_->addVertex(vertex(t.position + n * r, n, (float)i / (float)slices, 1 - (float)j / (float)stacks));
    }
  }
  uint32_t row = (uint32_t)slices + 1;
  for (int j = 0; j < stacks; ++j) {
    ModelGuard::checkpoint();
    for (int i = 0; i < slices; ++i) {
      uint32_t a = first + j * row + i, b = a + 1, c = a + row, d = c + 1;
      if (j > 0) out_->addTriangle(a, b, c);
      if (j < stacks - 1) out_->addTriangle(b, d, c);
    }
  }
  extend(t.position - V3f(r, r, r));
  extend(t.position + V3f(r, r, r));
}

void Turtle::drawRhombus(float a, float b) {
  TurtleState& t = state_;
  // lpfg's vertex order: clockwise seen from +U although the normal is U, so with two-sided
  // lighting the side facing U is lit as a back face (dark when the light is behind the viewer);
  // kept for the same picture.
  V3f p[4] = {t.position, t.position + t.heading * (a / 2) + t.left * (b / 2), t.position + t.heading * a,
              t.position + t.heading * (a / 2) - t.left * (b / 2)};
  out_->useTexture(-1);
  uint32_t first = (uint32_t)out_->vertices.size();
  for (V3f q : p) {
    out_->addVertex(vertex(q, t.up));
    extend(q);
  }
  out_->addTriangle(first, first + 1, first + 2);
  out_->addTriangle(first, first + 2, first + 3);
}

void Turtle::drawTriangle(float a, float b) {
  TurtleState& t = state_;
  V3f p[3] = {t.position + t.left * (a / 2), t.position + t.heading * b, t.position - t.left * (a / 2)};  // lpfg's order
  out_->useTexture(-1);
  uint32_t first = (uint32_t)out_->vertices.size();
  for (V3f q : p) {
    out_->addVertex(vertex(q, t.up));
    extend(q);
  }
  extend(t.position);
  out_->addTriangle(first, first + 1, first + 2);
}

namespace {

// Ear clipping of a simple polygon projected onto the plane normal to `n`; fills `tris` with
// index triples. Used for `concave polygons: on` (lpfg uses the GLU tessellator there).
void triangulateConcave(const std::vector<V3f>& pts, V3f n, std::vector<uint32_t>& tris) {
  V3f ax = std::fabs(n.x) < 0.9f ? V3f(1, 0, 0) : V3f(0, 1, 0);
  V3f u = cross(n, ax).Normalized(), v = cross(n, u);
  std::vector<V2f> q;
  for (V3f p : pts) q.push_back(V2f(p * u, p * v));
  std::vector<uint32_t> idx;
  for (uint32_t i = 0; i < q.size(); ++i) idx.push_back(i);
  double area = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    const V2f &a = q[i], &b = q[(i + 1) % q.size()];
    area += (double)a.x * b.y - (double)b.x * a.y;
  }
  float sign = area >= 0 ? 1.f : -1.f;
  auto crossZ = [](V2f a, V2f b, V2f c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); };
  size_t guard = 0;
  while (idx.size() > 3 && guard++ < pts.size() * pts.size()) {
    bool clipped = false;
    for (size_t i = 0; i < idx.size(); ++i) {
      uint32_t ia = idx[(i + idx.size() - 1) % idx.size()], ib = idx[i], ic = idx[(i + 1) % idx.size()];
      if (crossZ(q[ia], q[ib], q[ic]) * sign <= 0) continue;
      bool inside = false;
      for (uint32_t j : idx) {
        if (j == ia || j == ib || j == ic) continue;
        // Points on the ear's boundary block it too (a reflex vertex on the diagonal).
        if (crossZ(q[ia], q[ib], q[j]) * sign >= 0 && crossZ(q[ib], q[ic], q[j]) * sign >= 0 &&
            crossZ(q[ic], q[ia], q[j]) * sign >= 0) {
          inside = true;
          break;
        }
      }
      if (inside) continue;
      tris.insert(tris.end(), {ia, ib, ic});
      idx.erase(idx.begin() + (long)i);
      clipped = true;
      break;
    }
    if (!clipped) break;  // not simple: fall back to a fan of what is left
  }
  for (size_t i = 1; i + 1 < idx.size(); ++i) tris.insert(tris.end(), {idx[0], idx[i], idx[i + 1]});
}

}  // namespace

// EP: the polygon of the vertices recorded since SP (at least three), each with the turtle's
// U and colour at the time; a fan unless the view file asks for concave polygons.
void Turtle::endPolygon() {
  bool wasOn = polygonOn_;
  polygonOn_ = false;
  if (!wasOn || polygon_.size() < 3) {
    polygon_.clear();
    return;
  }
  if (view_->automaticNormals) {
    V3f n = cross(polygon_[1].position - polygon_[0].position, polygon_[2].position - polygon_[1].position);
    if (n.Length() > 0) n.Normalize();
    for (auto& v : polygon_) v.normal = n;
  }
  out_->useTexture(-1);
  uint32_t first = (uint32_t)out_->vertices.size();
  for (const auto& v : polygon_) {
    MeshVertex m;
    m.position = v.position;
    m.normal = v.normal;
    m.color = v.color;
    out_->addVertex(m);
  }
  std::vector<uint32_t> tris;
  if (view_->concavePolygons) {
    std::vector<V3f> pts;
    for (const auto& v : polygon_) pts.push_back(v.position);
    triangulateConcave(pts, polygon_[0].normal, tris);
  } else {
    for (uint32_t i = 1; i + 1 < polygon_.size(); ++i) tris.insert(tris.end(), {0, i, i + 1});
  }
  for (size_t i = 0; i + 2 < tris.size(); i += 3) out_->addTriangle(first + tris[i], first + tris[i + 1], first + tris[i + 2]);
  polygon_.clear();
}

// ---- surfaces and meshes (manual §5.6, §7.1)

V3f Turtle::inFrame(V3f p, V3f scale) const {
  const TurtleState& t = state_;
  return t.position - t.left * (p.x * scale.x) + t.heading * (p.y * scale.y) + t.up * (p.z * scale.z);
}

// lpfg's box counts a surface's control points (or a mesh's box corners), not its tessellation.
void Turtle::addGrid(const PatchGrid& grid, bool world, V3f scale, int texture) {
  const TurtleState& t = state_;
  auto turn = [&](V3f n) -> V3f {
    if (world) return n;
    // Normals transform by the inverse scale.
    V3f m = -t.left * (scale.x != 0 ? n.x / scale.x : 0) + t.heading * (scale.y != 0 ? n.y / scale.y : 0) +
            t.up * (scale.z != 0 ? n.z / scale.z : 0);
    return m.Length() > 0 ? m.Normalized() : m;
  };
  out_->useTexture(texture);
  uint32_t first = (uint32_t)out_->vertices.size();
  for (size_t i = 0; i < grid.positions.size(); ++i) {
    if (i % 4096 == 0) ModelGuard::checkpoint();
    V3f p = world ? grid.positions[i] : inFrame(grid.positions[i], scale);
    V2f uv = i < grid.uvs.size() ? grid.uvs[i] : V2f();
    out_->addVertex(vertex(p, turn(grid.normals[i]), uv.x, uv.y));
  }
  for (size_t i = 0; i + 2 < grid.indices.size(); i += 3)
    out_->addTriangle(first + grid.indices[i], first + grid.indices[i + 1], first + grid.indices[i + 2]);
}

void Turtle::drawSurface(int id, V3f scale) {
  if (!setup_.shapes || id < 0 || id >= (int)setup_.shapes->surfaces.size()) return;  // lpfg: message, ignored
  const ShapeLibrary::Surface& s = setup_.shapes->surfaces[id];
  int u = precision(state_.uPrecision, s.sdiv), v = precision(state_.vPrecision, s.tdiv);
  for (size_t k = 0; k < s.surface.patches.size(); ++k) {
    ModelGuard::checkpoint();
    addGrid(s.surface.tessellate(k, u, v), false, scale * s.scale, state_.textureSet ? state_.texture : s.texture);
    for (const V3f& p : s.surface.patches[k].points) extend(inFrame(p, scale * s.scale));
  }
}

void Turtle::drawMesh(int id, V3f scale) {
  if (!setup_.shapes || id < 0 || id >= (int)setup_.shapes->meshes.size()) return;
  const ShapeLibrary::Mesh& m = setup_.shapes->meshes[id];
  PatchGrid grid;
  grid.positions = m.data.positions;
  grid.normals = m.data.normals;
  grid.uvs = m.data.uvs;
  grid.indices = m.data.indices;
  // A textured mesh takes the current texture instead of its own, as in lpfg.
  addGrid(grid, false, scale, m.texture >= 0 && state_.texture >= 0 ? state_.texture : m.texture);
  const V3f lo = m.data.boundsMin, hi = m.data.boundsMax;
  for (int c = 0; c < 8; ++c) extend(inFrame(V3f(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z), scale));
}

// lpfg's bounding box counts a B-spline surface's control points turned and scaled by the turtle
// but not moved to it: lpfg takes the translation from the wrong entries of its column-major
// matrix (zeros), so the surface counts as if drawn at the origin.
void Turtle::extendByNet(const BSplineNet& net, float scale) {
  const TurtleState& t = state_;
  for (int i = 0; i < net.rows(); ++i)
    for (int j = 0; j < net.columns(); ++j) {
      const BSplinePoint& p = net.at(i, j);
      extend(-t.left * (float(p.x) * scale) + t.heading * (float(p.y) * scale) + t.up * (float(p.z) * scale));
    }
}

// BSurface (manual §10.1), as lpfg draws it: at the turtle, scaled by the module (the view file's
// scale is not used), in the current colour, with its view-file texture (CurrentTexture does not
// apply; lpfg draws an id beyond the `texture:` lines untextured), vertices of the first draw's
// precision (ShapeLibrary::BSpline). It counts in the bounding box textured or not.
void Turtle::drawBSurface(int id, float scale) {
  if (!setup_.shapes || id < 0 || id >= (int)setup_.shapes->bsplines.size()) return;  // lpfg: message, ignored
  const ShapeLibrary::BSpline& b = setup_.shapes->bsplines[id];
  extendByNet(b.net, scale);
  int texture = b.texture < (int)view_->textures.size() ? b.texture : -1;
  int u = precision(state_.uPrecision, b.sdiv), v = precision(state_.vPrecision, b.tdiv);
  addGrid(BSplineNet::mesh(b.grid(u, v), u, v), false, V3f(scale, scale, scale), texture);
}

// DBSurfaceS/M: the record's net at the turtle, unscaled, untextured, at the turtle's precision.
void Turtle::drawDynamicBSurface(const float* points, int maxRows, int maxColumns, int rows, int columns) {
  BSplineNet net = bsplineFromRecord(points, maxRows, maxColumns, rows, columns);
  if (net.empty()) return;
  extendByNet(net, 1);
  int u = precision(state_.uPrecision), v = precision(state_.vPrecision);
  addGrid(BSplineNet::mesh(net.sample(u, v), u, v), false, V3f(1, 1, 1), -1);
}

// DSurface (turtle frame, no scaling) and DrawSurface (control points already in world space).
void Turtle::drawPatch(const V3tf (&points)[16], bool turtleFrame) {
  SurfaceObj patch;
  for (int i = 0; i < 16; ++i) patch.points[i] = points[i];
  int u = precision(state_.uPrecision), v = precision(state_.vPrecision);
  addGrid(tessellatePatch(patch, u, v), !turtleFrame, V3f(1, 1, 1), -1);
  for (const V3f& p : points) extend(turtleFrame ? inFrame(p, V3f(1, 1, 1)) : p);
}

}  // namespace lcjit::runtime
