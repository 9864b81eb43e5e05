// The terrain of the view file (see Terrain.h). Arithmetic follows lpfg's types and order
// (doubles for the terrain, floats for the camera point), so that the model functions give lpfg's
// bits.
#include "runtime/Terrain.h"

#include <cmath>

#include "runtime/files/Images.h"

namespace lcjit::runtime {

namespace {

// lpfg's test of a plane point against a triangle: the three sub-areas against the whole.
bool inside(double alpha, double beta, double gamma) {
  return alpha >= 0.0 && alpha <= 1.0 && beta >= 0.0 && beta <= 1.0 && gamma >= 0.0 && gamma <= 1.0;
}


// A strip's first four vertices, as offsets from the cell's corner (u, v): A B C D when the
// diagonal joins A and D, else B A D C.
struct Corner {
  int du, dv;
};
constexpr Corner kADiagonal[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
constexpr Corner kBDiagonal[4] = {{1, 0}, {0, 0}, {1, 1}, {0, 1}};

}  // namespace

Terrain::Terrain(const TerrainDeclaration& declaration, TerrainPatchFile file, bool wireframe)
    : declaration_(declaration), grids_(std::move(file.levels)), fileWidth_(file.width) {
  const int levels = (int)grids_.size();
  for (TerrainGrid& g : grids_)
    for (V3d& p : g.points) p *= (double)declaration_.scale;
  // Every coarser level's points are the next finer level's even ones (normals are kept).
  for (int l = levels - 1; l > 0; --l) {
    TerrainGrid& coarse = grids_[l - 1];
    const TerrainGrid& fine = grids_[l];
    for (int u = 0; u < coarse.numU; ++u)
      for (int v = 0; v < coarse.numV; ++v) coarse.points[coarse.at(u, v)] = fine.points[fine.at(2 * u, 2 * v)];
  }
  // R_l, from the width as read (lpfg scales the width after this).
  reach_.assign(levels, 0.0);
  if (levels >= 2) reach_[levels - 2] = std::sqrt(2.0) * (fileWidth_ / std::pow(2.0, (double)levels - 1));
  for (int l = levels - 3; l >= 0; --l)
    reach_[l] = std::sqrt(2.0) * (fileWidth_ / std::pow(2.0, (double)l + 1)) + reach_[l + 1];
  width_ = fileWidth_ * declaration_.scale;
  levels_.resize(levels);
  for (int l = 0; l < levels; ++l) {
    levels_[l].resize(size_t(1) << (2 * l));
    for (Patch& p : levels_[l]) p.mode = wireframe ? Wireframe : Shaded;
  }
  fill();
}

llvm::Expected<std::shared_ptr<Terrain>> Terrain::load(const TerrainDeclaration& declaration, const std::string& path,
                                                       bool wireframe) {
  auto file = loadTerrainPatches(path, declaration.levels);
  if (!file) return file.takeError();
  return std::make_shared<Terrain>(declaration, std::move(*file), wireframe);
}

Terrain::Node Terrain::child(Node n, int quadrant) {
  return {n.level + 1, 2 * n.row + (quadrant >> 1), 2 * n.col + (quadrant & 1)};
}

void Terrain::fill() {
  for (int l = 0; l < (int)levels_.size(); ++l) {
    const int side = 1 << l;
    for (int row = 0; row < side; ++row)
      for (int col = 0; col < side; ++col) loadPatch(levels_[l][size_t(row) * side + col], grids_[l], side, row, col);
  }
  measureExtent();
}

// A patch's share of its level's grid: columns (u) by `col`, rows (v) by `row`.
void Terrain::loadPatch(Patch& p, const TerrainGrid& grid, int patches, int row, int col) {
  p.numU = (grid.numU - 1) / patches + 1;
  p.numV = (grid.numV - 1) / patches + 1;
  const int u0 = (p.numU - 1) * col, v0 = (p.numV - 1) * row;
  const size_t n = size_t(p.numU) * size_t(p.numV);
  p.points.resize(n);
  p.normals.resize(n);
  p.uvs.resize(n);
  for (int i = 0; i < p.numU; ++i) {
    for (int j = 0; j < p.numV; ++j) {
      const int u = u0 + i, v = v0 + j;
      const V3d& q = grid.points[grid.at(u, v)];
      p.points[p.at(i, j)] = q;
      p.normals[p.at(i, j)] = grid.normals[grid.at(u, v)];
      p.uvs[p.at(i, j)] = V2d(((double)u * declaration_.uTiling) / ((double)grid.numU - 1.0),
                              ((double)v * declaration_.vTiling) / ((double)grid.numV - 1.0));
      if (i == 0 && j == 0) p.topLeft = p.bottomRight = q;
      // topLeft: lowest x and z, highest y; bottomRight: highest x and z, lowest y.
      if (q.x < p.topLeft.x) p.topLeft.x = q.x;
      if (q.z < p.topLeft.z) p.topLeft.z = q.z;
      if (q.x > p.bottomRight.x) p.bottomRight.x = q.x;
      if (q.z > p.bottomRight.z) p.bottomRight.z = q.z;
      if (q.y > p.topLeft.y) p.topLeft.y = q.y;
      if (q.y < p.bottomRight.y) p.bottomRight.y = q.y;
    }
  }
  p.midPoint = p.topLeft + 0.5 * (p.bottomRight - p.topLeft);
  p.maxHeight = p.topLeft.y;
  p.topLeft.y = p.midPoint.y;
  p.bottomRight.y = p.midPoint.y;
}

// ---- queries -----------------------------------------------------------------------------------

// The first patch down the tree (NW, NE, SW, SE) whose box holds the point in x and z: a finest
// one, or with `drawnCounts` the first one the last draw chose.
std::optional<Terrain::Node> Terrain::under(V3d point, Node n, bool drawnCounts) {
  const Patch& p = patch(n);
  if (!(p.topLeft.z <= point.z && p.bottomRight.z >= point.z && p.topLeft.x <= point.x && p.bottomRight.x >= point.x))
    return std::nullopt;
  if ((drawnCounts && p.drawn) || n.level == (int)levels_.size() - 1) return n;
  for (int quadrant : {0, 1, 2, 3})
    if (auto found = under(point, child(n, quadrant), drawnCounts)) return found;
  return std::nullopt;
}

bool Terrain::rayCast(V3f world, V3f& point, V3f& normal) {
  auto node = under(V3d(world), Node{0, 0, 0}, false);
  if (!node) return false;
  const Patch& p = patch(*node);
  world.y = (float)p.maxHeight;
  const V3d O(world.x, world.y, world.z), D(0.0, -1.0, 0.0);
  auto pt = [&](int u, int v) { return p.points[p.at(u, v)]; };
  auto nm = [&](int u, int v) { return p.normals[p.at(u, v)]; };
  for (int u = 0; u < p.numU - 1; ++u) {
    for (int v = 0; v < p.numV - 1; ++v) {
      // The cell's first triangle (u,v) (u,v+1) (u+1,v+1): its plane gives the point.
      V3d N = (nm(u, v) + nm(u, v + 1) + nm(u + 1, v + 1)) / 3.0;
      V3d A = pt(u, v), B = pt(u, v + 1), C = pt(u + 1, v + 1);
      double dist = -((O - A) * N) / (D * N);
      V3d P = O + dist * D;
      double S = 0.5 * ((A - B) % (A - C)).Length();
      double S1 = 0.5 * ((B - P) % (C - P)).Length();
      double S2 = 0.5 * ((P - C) % (P - A)).Length();
      double alpha = S1 / S, beta = S2 / S, gamma = 1 - alpha - beta;
      if (inside(alpha, beta, gamma)) {
        point = V3f(P);
        normal = V3f(N);
        return true;
      }
      // The second triangle (u,v) (u+1,v) (u+1,v+1), tested with the same point.
      N = (nm(u, v) + nm(u + 1, v) + nm(u + 1, v + 1)) / 3.0;
      B = pt(u + 1, v);
      S = 0.5 * ((A - B) % (A - C)).Length();
      S1 = 0.5 * ((B - P) % (C - P)).Length();
      alpha = S1 / S;
      beta = S2 / S;
      gamma = 1 - alpha - beta;
      if (inside(alpha, beta, gamma)) {
        point = V3f(P);
        normal = V3f(N);
        return true;
      }
    }
  }
  return false;
}

bool Terrain::heightAt(V3f world, V3f& onTerrain) {
  std::lock_guard<std::mutex> lock(mutex_);
  V3f normal;
  return rayCast(world, onTerrain, normal);
}

bool Terrain::normalAt(V3f world, V3f& normal) {
  std::lock_guard<std::mutex> lock(mutex_);
  V3f point;
  return rayCast(world, point, normal);
}

void Terrain::setMode(Node n, VisibilityMode mode) {
  patch(n).mode = mode;
  if (n.level + 1 < (int)levels_.size())
    for (int quadrant : {0, 1, 2, 3}) setMode(child(n, quadrant), mode);
}

void Terrain::visibilityAll(VisibilityMode mode) {
  std::lock_guard<std::mutex> lock(mutex_);
  setMode(Node{0, 0, 0}, mode);
}

void Terrain::visibilityPatch(VisibilityMode mode, V3f world) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto node = under(V3d(world), Node{0, 0, 0}, true)) setMode(*node, mode);
}

void Terrain::scaleBy(float factor) {
  std::lock_guard<std::mutex> lock(mutex_);
  fill();
  width_ = fileWidth_ * factor;
  for (auto& level : levels_) {
    for (Patch& p : level) {
      for (V3d& q : p.points) q *= (double)factor;
      p.topLeft *= (double)factor;
      p.bottomRight *= (double)factor;
      p.midPoint *= (double)factor;
      p.maxHeight *= factor;
    }
  }
  measureExtent();
}

void Terrain::measureExtent() {
  extent_ = Bounds{};
  for (const auto& level : levels_) {
    for (const Patch& p : level) {
      extent_.add(V3f(p.topLeft));
      extent_.add(V3f(p.bottomRight));
    }
  }
}

void Terrain::addExtent(Bounds& b) const {
  std::lock_guard<std::mutex> lock(mutex_);
  b.add(extent_);
}

// ---- drawing -----------------------------------------------------------------------------------

bool Terrain::split(const Patch& p, int level) const {
  V3d pos = p.midPoint;
  pos.y = 0;
  double dist = (camera_ - pos).Length();
  double d = std::sqrt(2.0) * (width_ / std::pow(2.0, (double)level));
  return dist <= (reach_[level] + d * (double)declaration_.distance) / 2.0;
}

void Terrain::choose(Node n) {
  Patch& p = patch(n);
  if (n.level == (int)levels_.size() - 1 || !split(p, n.level)) {
    p.drawn = true;
    return;
  }
  for (int quadrant : {1, 0, 3, 2}) choose(child(n, quadrant));  // NE, NW, SE, SW
}

Terrain::Cracks Terrain::cracksOf(Node n) const {
  Cracks c;
  if (n.level < 2) return c;
  // Only the sides facing away from the siblings can meet a coarser patch: its parent is drawn.
  const int side = 1 << n.level;
  auto parentDrawn = [&](int row, int col) { return patch(Node{n.level - 1, row / 2, col / 2}).drawn; };
  const bool south = n.row & 1, east = n.col & 1;
  if (!south && n.row > 0) c.n = parentDrawn(n.row - 1, n.col);
  if (south && n.row + 1 < side) c.s = parentDrawn(n.row + 1, n.col);
  if (!east && n.col > 0) c.w = parentDrawn(n.row, n.col - 1);
  if (east && n.col + 1 < side) c.e = parentDrawn(n.row, n.col + 1);
  return c;
}

// Turns lpfg's GL calls for one patch into Geometry: triangle strips and triangles with their
// vertex order (the winding decides which side two-sided lighting treats as the front), and the
// grid lines.
class Terrain::Writer {
 public:
  Writer(Geometry& out, int color, int texture, const Image* image, bool grid)
      : out_(out), color_(color), texture_(texture), image_(image), grid_(grid) {}

  void patch(const Patch& p, Cracks cracks) {
    if (p.mode == Hidden) return;
    cracks_ = cracks;
    out_.useTexture(texture_, p.mode == Wireframe ? PolygonFill::Lines
                              : p.mode == Shaded  ? PolygonFill::Solid
                                                  : PolygonFill::Default);
    p_ = &p;
    solid();
    borders();
    corners();
    if (grid_) gridLines();
  }

 private:
  uint32_t vertex(int u, int v, bool negated = false) {
    const Patch& p = *p_;
    size_t k = p.at(u, v);
    MeshVertex m;
    m.position = V3f(p.points[k]);
    m.normal = V3f(negated ? V3d(-p.normals[k]) : p.normals[k]);
    m.uv = V2f(p.uvs[k]);
    m.color = color_;
    lastUV_ = m.uv;
    return out_.addVertex(m);
  }
  void triangle(int u0, int v0, int u1, int v1, int u2, int v2) {
    uint32_t a = vertex(u0, v0), b = vertex(u1, v1), c = vertex(u2, v2);
    out_.addTriangle(a, b, c);
  }
  // GL_TRIANGLE_STRIP: triangle k is (k, k+1, k+2), odd ones turned (k+1, k, k+2).
  void flush() {
    for (size_t k = 0; k + 2 < strip_.size(); ++k) {
      if (k % 2 == 0) out_.addTriangle(strip_[k], strip_[k + 1], strip_[k + 2]);
      else out_.addTriangle(strip_[k + 1], strip_[k], strip_[k + 2]);
    }
    strip_.clear();
  }

  // The interior: one strip per column of cells, restarted where the diagonal changes. Cell
  // corners A (u,v), B (u+1,v), C (u,v+1), D (u+1,v+1); the diagonal joins the pair of corners
  // whose normals agree better.
  void solid() {
    const Patch& p = *p_;
    const Cracks& c = cracks_;
    const int v0 = c.n ? 1 : 0, v1 = c.s ? p.numV - 2 : p.numV - 1;
    const int u0 = c.w ? 1 : 0, u1 = c.e ? p.numU - 2 : p.numU - 1;
    bool flipped = false;
    for (int u = u0; u < u1; ++u) {
      for (int v = v0; v < v1; ++v) {
        const V3d &a = p.normals[p.at(u, v)], &b = p.normals[p.at(u + 1, v)];
        const V3d &cc = p.normals[p.at(u, v + 1)], &d = p.normals[p.at(u + 1, v + 1)];
        if (a * d < b * cc) {
          if (v == v0 || flipped) {
            flush();
            for (const Corner& k : kADiagonal) strip_.push_back(vertex(u + k.du, v + k.dv, true));
            flipped = false;
          } else {
            strip_.push_back(vertex(u, v + 1, true));
            strip_.push_back(vertex(u + 1, v + 1, true));
          }
        } else {
          if (v == v0 || !flipped) {
            flush();
            for (const Corner& k : kBDiagonal) strip_.push_back(vertex(u + k.du, v + k.dv));
            flipped = true;
          } else {
            strip_.push_back(vertex(u + 1, v + 1));
            strip_.push_back(vertex(u, v + 1));
          }
        }
      }
      flush();
    }
  }

  // A cracked side's border row, joined on every other point of the side (those the coarser
  // neighbour has): for each pair of cells, a fan of up to three triangles.
  void borders() {
    const Patch& p = *p_;
    const Cracks& c = cracks_;
    const int U = p.numU, V = p.numV;
    if (c.n) {
      const int v = 0;
      for (int u = 0; u < U - 2; u += 2) {
        if (u != 0) triangle(u, v + 1, u + 1, v + 1, u, v);
        triangle(u + 1, v + 1, u + 2, v, u, v);
        if (u != U - 3) triangle(u + 2, v + 1, u + 2, v, u + 1, v + 1);
      }
    }
    if (c.s) {
      const int v = V - 2;
      for (int u = 0; u < U - 2; u += 2) {
        if (u != 0) triangle(u + 1, v, u, v, u, v + 1);
        triangle(u + 2, v + 1, u + 1, v, u, v + 1);
        if (u != U - 3) triangle(u + 2, v + 1, u + 2, v, u + 1, v);
      }
    }
    if (c.w) {
      const int u = 0;
      for (int v = 0; v < V - 2; v += 2) {
        if (v != 0) triangle(u, v, u + 1, v + 1, u + 1, v);
        triangle(u, v + 2, u + 1, v + 1, u, v);
        if (v != V - 3) triangle(u + 1, v + 2, u + 1, v + 1, u, v + 2);
      }
    }
    if (c.e) {
      const int u = U - 2;
      for (int v = 0; v < V - 2; v += 2) {
        if (v != 0) triangle(u, v, u, v + 1, u + 1, v);
        triangle(u + 1, v, u, v + 1, u + 1, v + 2);
        if (v != V - 3) triangle(u + 1, v + 2, u, v + 1, u, v + 2);
      }
    }
  }

  // Where a cracked side meets an uncracked one, the corner cell's missing triangle.
  void corners() {
    const Patch& p = *p_;
    const Cracks& c = cracks_;
    const int U = p.numU, V = p.numV;
    if (c.n && !c.w) triangle(0, 0, 0, 1, 1, 1);
    if (c.n && !c.e) triangle(U - 1, 0, U - 2, 1, U - 1, 1);
    if (c.e && !c.n) triangle(U - 2, 0, U - 2, 1, U - 1, 0);
    if (c.e && !c.s) triangle(U - 2, V - 2, U - 2, V - 1, U - 1, V - 1);
    if (c.s && !c.e) triangle(U - 1, V - 2, U - 2, V - 2, U - 1, V - 1);
    if (c.s && !c.w) triangle(1, V - 2, 0, V - 2, 0, V - 1);
    if (c.w && !c.n) triangle(0, 0, 1, 1, 1, 0);
    if (c.w && !c.s) triangle(0, V - 1, 1, V - 1, 1, V - 2);
  }

  // The patch's box at 95% around its midpoint, at its middle height.
  void gridLines() {
    const Patch& p = *p_;
    const V3d m(p.midPoint.x, p.topLeft.y, p.midPoint.z);
    const V3d a = m + 0.95 * (p.topLeft - m), b = m + 0.95 * (p.bottomRight - m);
    const int32_t yellow = lineColor(false), red = lineColor(true);
    auto line = [&](V3d from, V3d to, bool crack) { out_.addSegment({V3f(from), V3f(to), 1, crack ? red : yellow}); };
    line(a, V3d(b.x, a.y, a.z), cracks_.n);
    line(V3d(b.x, a.y, a.z), b, cracks_.e);
    line(b, V3d(a.x, b.y, b.z), cracks_.s);
    line(V3d(a.x, b.y, b.z), a, cracks_.w);
  }
  // Yellow or red times the texel at the last texture coordinate (GL_NEAREST, GL_REPEAT).
  int32_t lineColor(bool red) const {
    uint8_t r = 255, g = 255;
    if (image_ && image_->width > 0 && image_->height > 0 &&
        image_->rgba.size() >= size_t(image_->width) * size_t(image_->height) * 4) {
      auto texel = [](float t, int size) {
        float f = t - std::floor(t);
        int i = (int)std::floor(f * (float)size);
        return i < 0 ? 0 : i >= size ? size - 1 : i;
      };
      const uint8_t* px = image_->pixelFromBottom(texel(lastUV_.x, image_->width), texel(lastUV_.y, image_->height));
      r = px[0];
      g = px[1];
    }
    return rgbColor(r, red ? 0 : g, 0);
  }

  Geometry& out_;
  int color_, texture_;
  const Image* image_;
  bool grid_;
  const Patch* p_ = nullptr;
  Cracks cracks_;  // of the patch being written
  std::vector<uint32_t> strip_;
  V2f lastUV_{0, 0};
};

void Terrain::drawPatches(Node n, Writer& w) {
  Patch& p = patch(n);
  if (p.drawn) {
    w.patch(p, cracksOf(n));
    return;
  }
  for (int quadrant : {1, 0, 3, 2}) drawPatches(child(n, quadrant), w);
}

void Terrain::draw(const CameraPosition& camera, int color, const Image* texture, Geometry& out) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The camera's point: lpfg moves it along the view direction by the zoom (in floats).
  float s = (V3f(0, 0, 0) - camera.position).Length() * (-1.0f / camera.scale + 1.0f);
  V3f c = camera.position + s * camera.head;
  camera_ = V3d(c);
  for (auto& level : levels_)
    for (Patch& p : level) p.drawn = false;
  choose(Node{0, 0, 0});
  const bool textured = declaration_.texture >= 0;
  Writer w(out, color, textured ? declaration_.texture : -1, textured ? texture : nullptr, declaration_.grid);
  drawPatches(Node{0, 0, 0}, w);
}

}  // namespace lcjit::runtime
