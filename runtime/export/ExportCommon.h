// Internal to the exporters: buffered file writing, the resolved input (palette, view, camera),
// the mesh every mesh format writes (geometry + camera-facing discs, usable normals) and names.
#pragma once
#include <array>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "runtime/export/Export.h"
#include "support/ReplacingFile.h"

namespace lcjit::runtime::exporting {

llvm::Error fileError(const std::string& path, const std::string& message);

// fmt into a memory buffer, flushed to the file in large blocks. Errors surface at close().
class FileWriter {
 public:
  FileWriter() = default;
  FileWriter(const FileWriter&) = delete;
  FileWriter& operator=(const FileWriter&) = delete;
  ~FileWriter();

  llvm::Error open(const std::string& path, bool binary = false);
  template <class... T> void print(fmt::format_string<T...> format, T&&... args) {
    fmt::format_to(fmt::appender(buf_), format, std::forward<T>(args)...);
    if (buf_.size() >= kFlushSize) flush();
  }
  void text(std::string_view s) {
    buf_.append(s.data(), s.data() + s.size());
    if (buf_.size() >= kFlushSize) flush();
  }
  void write(const void* data, size_t size);
  template <class T> void put(const T& value) { write(&value, sizeof value); }  // little-endian host
  fmt::memory_buffer& buffer() { return buf_; }
  void flushIfLarge() {
    if (buf_.size() >= kFlushSize) flush();
  }
  // Flushes, closes and puts the file in place (ReplacingFile); on failure, or without close(),
  // the file there before is left as it was and the error names it.
  llvm::Error close();

 private:
  static constexpr size_t kFlushSize = 1 << 22;
  void flush();
  std::optional<support::ReplacingFile> target_;
  std::FILE* file_ = nullptr;
  fmt::memory_buffer buf_;
  int errno_ = 0;
};

using Rgba = std::array<float, 4>;

// A colour as exporters key and name it: an index clamped to 0..255, an explicit colour
// (kRgbColor) kept, as kRgbColor | 0xRRGGBB.
inline int colorKey(int c) {
  if (isRgbColor(c)) return kRgbColor | (c & 0xFFFFFF);
  return c < 0 ? 0 : c > 255 ? 255 : c;
}

// The input with defaults filled in.
struct Context {
  Context(const std::string& path, const ExportInput& in);
  const std::string& path;
  const ExportInput& in;
  const Geometry& geometry;
  const Palette& palette;
  const ViewSettings& view;

  // The exporters read a geometry colour (an index 0..255, or kRgbColor | 0xRRGGBB: Geometry.h)
  // only through these three and colorKey.
  // A colour's RGBA: an index's from the palette, an explicit colour as it is.
  Rgba color(int c) const {
    if (isRgbColor(c)) return {float((c >> 16) & 255) / 255, float((c >> 8) & 255) / 255, float(c & 255) / 255, 1};
    return colors_[colorKey(c)];
  }
  // A label's colour: lpfg's text colour of an index, an explicit colour as it is.
  Rgba textColor(int c) const { return isRgbColor(c) ? color(c) : palette.textColor(c); }
  // The material `c` is drawn lit with: an index's in materials mode; nullptr for a colour drawn
  // flat as color() gives it (colormap mode, and explicit colours, which lpfg draws unlit).
  const Material* material(int c) const {
    return palette.usesMaterials() && !isRgbColor(c) ? &palette.material(colorKey(c)) : nullptr;
  }
  const CameraMatrices& camera() const;  // in.camera, else frameView (computed once)
  // Texture `t`'s file on disk (absolute when it can be made so); "" when `t` names no file.
  std::string textureFile(int t) const;
  // The same file as the output should name it (relative to the output's directory when
  // possible).
  std::string texturePath(int t) const;

 private:
  std::array<Rgba, 256> colors_;  // palette.color(i), looked up once
  Palette defaultPalette_;
  ViewSettings defaultView_;
  mutable std::optional<CameraMatrices> camera_;
};

// f without a negative zero (prints "0", not "-0").
inline float z(float f) { return f + 0.0f; }
// v scaled to length 1, or v itself when it has no length (model code's Normalize() divides by
// the length regardless, as lpfg's does).
inline V3f unit(V3f v) {
  float l = v.Length();
  return l > 0 ? V3f(v / l) : v;
}
inline bool sameVector(V3f a, V3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Triangles ready for a mesh format: the geometry's, plus discs turned into camera-facing
// triangles; `normals` has one unit normal per vertex (zero normals replaced by the faces').
struct Mesh {
  const Geometry* g = nullptr;
  std::vector<V3f> normals;
  bool textured = false;  // some run has a texture
  const std::vector<MeshVertex>& vertices() const { return g->vertices; }
  const std::vector<uint32_t>& indices() const { return g->indices; }

 private:
  friend Mesh prepareMesh(const Context&);
  std::shared_ptr<Geometry> storage_;
};
Mesh prepareMesh(const Context& cx);
// One unit normal per vertex; zero normals replaced by the normals of the faces around them.
std::vector<V3f> unitNormals(const Geometry& g);

// Calls f(triangle, a, b, c, texture) for every triangle in order.
template <class F> void forEachTriangle(const Geometry& g, F&& f) {
  const size_t count = g.indices.size() / 3;
  size_t t = 0;
  auto upTo = [&](size_t end, int texture) {
    for (; t < end && t < count; ++t) f(t, g.indices[3 * t], g.indices[3 * t + 1], g.indices[3 * t + 2], texture);
  };
  for (const TriangleRun& r : g.runs) {
    upTo(r.firstIndex / 3, -1);
    upTo((size_t(r.firstIndex) + r.indexCount) / 3, r.texture);
  }
  upTo(count, -1);
}

// A triangle's material: its first vertex's colour (colorKey) and its run's texture.
struct MaterialKey {
  int color = 1, texture = -1;
  bool operator==(const MaterialKey&) const = default;
  int64_t packed() const { return int64_t(texture + 1) << 32 | uint32_t(color); }
};
// lpfg's material names: s001 (colour 1), s001_t0 (colour 1 with texture 0); an explicit colour
// is named after it: rgb_FF8000 (rgb_FF8000_t0).
std::string materialName(MaterialKey key);

// Segments as polylines: consecutive segments of one colour that share an end become one chain.
struct Polyline {
  int color = 1;
  uint32_t first = 0, count = 0;  // into `points`
};
struct Polylines {
  std::vector<V3f> points;
  std::vector<Polyline> lines;
  size_t edgeCount() const;
};
Polylines chainSegments(const std::vector<Segment>& segments);

// Distinct material keys of the triangles, in first-use order.
std::vector<MaterialKey> usedMaterials(const Geometry& g);

// Unit vectors perpendicular to `n` (a right-handed frame u, v, n).
void perpendicularFrame(V3f n, V3f& u, V3f& v);
V3f toV3(const glm::vec3& v);
glm::vec3 toGlm(V3f v);

// The camera's frame in model space: right, up, towards the viewer.
struct CameraFrame {
  V3f right, up, back;
};
CameraFrame cameraFrame(const CameraMatrices& camera);

// Lights in model space. With `stationary lights: on` (lpfg's default) a light is placed through
// the camera's stationaryLights matrix (the initial view's translation only), so it stays fixed
// relative to the viewer; otherwise its coordinates are model coordinates.
glm::mat4 lightToModel(const Context& cx);
V3f lightDirection(const Context& cx, const Light& light, V3f at);  // unit, from `at` towards it

std::string lowerExtension(std::string_view path);  // "obj" for "a/b.OBJ"
std::string baseName(const std::string& path);      // "b.obj"
std::string replaceExtension(const std::string& path, std::string_view ext);  // ext with dot

}  // namespace lcjit::runtime::exporting
