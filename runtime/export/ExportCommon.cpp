// What every exporter shares (see ExportCommon.h): buffered writing, the resolved input, the mesh
// with camera-facing discs, and names.
#include "runtime/export/ExportCommon.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unordered_map>
#include <algorithm>

namespace lcjit::runtime::exporting {

llvm::Error fileError(const std::string& path, const std::string& message) {
  return llvm::createStringError(std::errc::io_error, "cannot write '%s': %s", path.c_str(), message.c_str());
}

FileWriter::~FileWriter() {
  if (file_) std::fclose(file_);  // the new file goes with target_; the old one stays
}

llvm::Error FileWriter::open(const std::string& path, bool binary) {
  target_.emplace(path);
  file_ = std::fopen(target_->writePath().c_str(), binary ? "wb" : "w");
  if (!file_) return fileError(path, std::strerror(errno));
  buf_.reserve(kFlushSize + (1 << 16));
  return llvm::Error::success();
}

void FileWriter::write(const void* data, size_t size) {
  if (size >= kFlushSize) {
    flush();
    if (file_ && !errno_ && std::fwrite(data, 1, size, file_) != size) errno_ = errno ? errno : EIO;
    return;
  }
  const char* p = static_cast<const char*>(data);
  buf_.append(p, p + size);
  if (buf_.size() >= kFlushSize) flush();
}

void FileWriter::flush() {
  if (file_ && !errno_ && buf_.size() && std::fwrite(buf_.data(), 1, buf_.size(), file_) != buf_.size())
    errno_ = errno ? errno : EIO;
  buf_.clear();
}

llvm::Error FileWriter::close() {
  flush();
  if (!file_) return llvm::Error::success();
  if (std::fclose(file_) != 0 && !errno_) errno_ = errno ? errno : EIO;
  file_ = nullptr;
  if (errno_) {
    llvm::Error e = fileError(target_->path(), std::strerror(errno_));
    target_.reset();  // the new file removed, the old one kept
    return e;
  }
  return target_->commit();
}

// ---------------------------------------------------------------------------------------------

Context::Context(const std::string& p, const ExportInput& i)
    : path(p),
      in(i),
      geometry(*i.geometry),
      palette(i.palette ? *i.palette : defaultPalette_),
      view(i.view ? *i.view : defaultView_) {
  for (int c = 0; c < 256; ++c) colors_[c] = palette.color(c);
}

const CameraMatrices& Context::camera() const {
  if (!camera_) {
    if (in.camera) camera_ = *in.camera;
    else
      camera_ = frameView(view, geometry.framingBounds(), geometry.camera, std::max(1, in.width), std::max(1, in.height),
                          in.viewId, in.adjust);
  }
  return *camera_;
}

std::string Context::textureFile(int t) const {
  if (t < 0 || t >= (int)in.textureFiles.size() || in.textureFiles[t].empty()) return {};
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path file(in.textureFiles[t]);
  if (file.is_relative() && !in.textureDirectory.empty()) file = fs::path(in.textureDirectory) / file;
  fs::path absFile = fs::absolute(file, ec);
  return (ec ? file : absFile.lexically_normal()).generic_string();
}

std::string Context::texturePath(int t) const {
  namespace fs = std::filesystem;
  const fs::path absFile = textureFile(t);
  if (absFile.empty() || absFile.is_relative()) return absFile.generic_string();
  std::error_code ec;
  fs::path outDir = fs::absolute(fs::path(path), ec).parent_path();
  if (ec) return absFile.generic_string();
  fs::path rel = absFile.lexically_relative(outDir.lexically_normal());
  return (rel.empty() ? absFile : rel).generic_string();
}

std::string materialName(MaterialKey key) {
  const int c = colorKey(key.color);
  std::string name = isRgbColor(c) ? fmt::format("rgb_{:06X}", c & 0xFFFFFF) : fmt::format("s{:03d}", c);
  if (key.texture >= 0) name += fmt::format("_t{}", key.texture);
  return name;
}

size_t Polylines::edgeCount() const {
  size_t n = 0;
  for (const Polyline& l : lines) n += l.count - 1;
  return n;
}

Polylines chainSegments(const std::vector<Segment>& segments) {
  Polylines p;
  for (const Segment& s : segments) {
    if (!p.lines.empty() && p.lines.back().color == s.color && sameVector(p.points.back(), s.from)) {
      p.points.push_back(s.to);
      p.lines.back().count++;
      continue;
    }
    p.lines.push_back({s.color, (uint32_t)p.points.size(), 2});
    p.points.push_back(s.from);
    p.points.push_back(s.to);
  }
  return p;
}

std::vector<MaterialKey> usedMaterials(const Geometry& g) {
  std::vector<MaterialKey> keys;
  std::unordered_map<int64_t, int> seen;
  MaterialKey last{-1000, -1000};
  forEachTriangle(g, [&](size_t, uint32_t a, uint32_t, uint32_t, int texture) {
    MaterialKey k{colorKey(g.vertices[a].color), texture};
    if (k == last) return;
    last = k;
    if (seen.emplace(k.packed(), (int)keys.size()).second) keys.push_back(k);
  });
  return keys;
}

V3f toV3(const glm::vec3& v) { return {v.x, v.y, v.z}; }
glm::vec3 toGlm(V3f v) { return {v.x, v.y, v.z}; }

void perpendicularFrame(V3f n, V3f& u, V3f& v) {
  n = unit(n);
  V3f a = std::fabs(n.x) < 0.9f ? V3f(1, 0, 0) : V3f(0, 1, 0);
  u = unit(a % n);
  v = n % u;
}

CameraFrame cameraFrame(const CameraMatrices& camera) {
  // Rows of the view matrix's rotation are the camera axes in model space.
  const glm::mat4& m = camera.view;
  CameraFrame f;
  f.right = unit(V3f(m[0][0], m[1][0], m[2][0]));
  f.up = unit(V3f(m[0][1], m[1][1], m[2][1]));
  f.back = unit(V3f(m[0][2], m[1][2], m[2][2]));
  if (f.right * f.right < 0.5f || f.up * f.up < 0.5f) {
    V3f d = toV3(camera.viewDirection);
    f.back = unit(-d);
    perpendicularFrame(f.back, f.right, f.up);
  }
  return f;
}

glm::mat4 lightToModel(const Context& cx) {
  if (!cx.view.stationaryLights) return glm::mat4(1);
  return glm::inverse(cx.camera().view) * cx.camera().stationaryLights;
}

V3f lightDirection(const Context& cx, const Light& light, V3f at) {
  const glm::mat4 m = lightToModel(cx);
  if (light.kind == Light::Kind::Directional) {
    glm::vec3 d = glm::mat3(m) * toGlm(light.position);
    return unit(toV3(d));
  }
  glm::vec4 p = m * glm::vec4(toGlm(light.position), 1);
  return unit(V3f(p.x, p.y, p.z) - at);
}

std::string lowerExtension(std::string_view path) {
  size_t slash = path.find_last_of("/\\");
  size_t dot = path.find_last_of('.');
  std::string ext;
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) ext = path;
  else ext = path.substr(dot + 1);
  for (char& c : ext) c = (char)std::tolower((unsigned char)c);
  return ext;
}

std::string baseName(const std::string& path) {
  size_t slash = path.find_last_of("/\\");
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string replaceExtension(const std::string& path, std::string_view ext) {
  size_t slash = path.find_last_of("/\\");
  size_t dot = path.find_last_of('.');
  std::string stem = (dot == std::string::npos || (slash != std::string::npos && dot < slash)) ? path : path.substr(0, dot);
  return stem + std::string(ext);
}

// ---------------------------------------------------------------------------------------------

static void addDisc(Geometry& g, const Disc& d, const CameraFrame& f, int sides) {
  const int n = std::max(3, sides);
  MeshVertex base;
  base.normal = f.back;
  base.color = d.color;
  auto ring = [&](float r) {
    uint32_t first = (uint32_t)g.vertices.size();
    for (int i = 0; i < n; ++i) {
      float a = 2 * float(M_PI) * i / n;
      MeshVertex v = base;
      v.position = d.center + f.right * (r * std::cos(a)) + f.up * (r * std::sin(a));
      v.uv = V2f(0.5f + 0.5f * std::cos(a) * r / std::max(d.outer, 1e-20f), 0.5f + 0.5f * std::sin(a) * r / std::max(d.outer, 1e-20f));
      g.addVertex(v);
    }
    return first;
  };
  uint32_t outer = ring(d.outer);
  if (d.inner > 0) {
    uint32_t inner = ring(d.inner);
    for (int i = 0; i < n; ++i) {
      uint32_t j = (i + 1) % n;
      g.addTriangle(inner + i, outer + i, outer + j);
      g.addTriangle(inner + i, outer + j, inner + j);
    }
  } else {
    MeshVertex c = base;
    c.position = d.center;
    c.uv = V2f(0.5f, 0.5f);
    uint32_t centre = g.addVertex(c);
    for (int i = 0; i < n; ++i) g.addTriangle(centre, outer + i, outer + (i + 1) % n);
  }
}

std::vector<V3f> unitNormals(const Geometry& g) {
  // Unit normals; zero ones from the (area-weighted) normals of the faces around the vertex.
  std::vector<V3f> normals;
  const size_t nv = g.vertices.size();
  normals.resize(nv);
  bool anyZero = false;
  for (size_t i = 0; i < nv; ++i) {
    V3f n = g.vertices[i].normal;
    float l2 = n * n;
    if (l2 > 1e-20f) {
      normals[i] = std::fabs(l2 - 1) < 1e-4f ? n : n / std::sqrt(l2);
    } else {
      normals[i] = V3f(0, 0, 0);
      anyZero = true;
    }
  }
  if (anyZero) {
    std::vector<V3f> sum(nv, V3f(0, 0, 0));
    std::vector<char> zero(nv, 0);
    for (size_t i = 0; i < nv; ++i) zero[i] = normals[i] * normals[i] == 0;
    const auto& idx = g.indices;
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
      if (a >= nv || b >= nv || c >= nv) continue;
      if (!zero[a] && !zero[b] && !zero[c]) continue;
      V3f fn = (g.vertices[b].position - g.vertices[a].position) % (g.vertices[c].position - g.vertices[a].position);
      if (zero[a]) sum[a] += fn;
      if (zero[b]) sum[b] += fn;
      if (zero[c]) sum[c] += fn;
    }
    for (size_t i = 0; i < nv; ++i)
      if (zero[i]) {
        float l2 = sum[i] * sum[i];
        normals[i] = l2 > 0 ? sum[i] / std::sqrt(l2) : V3f(0, 0, 1);
      }
  }
  return normals;
}

Mesh prepareMesh(const Context& cx) {
  Mesh m;
  m.g = &cx.geometry;
  if (!cx.geometry.discs.empty()) {
    auto copy = std::make_shared<Geometry>();
    copy->vertices = cx.geometry.vertices;
    copy->indices = cx.geometry.indices;
    copy->runs = cx.geometry.runs;
    if (copy->runs.empty() && !copy->indices.empty()) copy->runs.push_back({0, (uint32_t)copy->indices.size(), -1});
    copy->useTexture(-1);
    CameraFrame f = cameraFrame(cx.camera());
    for (const Disc& d : cx.geometry.discs) addDisc(*copy, d, f, cx.in.discSegments);
    m.storage_ = copy;
    m.g = copy.get();
  }
  const Geometry& g = *m.g;
  for (const TriangleRun& r : g.runs)
    if (r.texture >= 0 && r.indexCount) m.textured = true;

  m.normals = unitNormals(g);
  return m;
}

}  // namespace lcjit::runtime::exporting
