// Mesh files: see MeshFiles.h. OBJ through tinyobjloader; PLY by the reader below.
#include "runtime/files/MeshFiles.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <tuple>

#include <llvm/Support/MemoryBuffer.h>
#include "runtime/files/TextLines.h"

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

namespace lcjit::runtime {
namespace {

using textfile::fail;

// Applies scale/contact, computes bounds and (unless taken from the file) lpfg's smooth normals.
// posId[v]: the file position vertex v came from (normals are shared per file position).
void finish(MeshData& m, const std::vector<uint32_t>& posId, size_t positionCount, bool haveFileNormals,
            const MeshLoadOptions& o) {
  for (auto& p : m.positions) p = p * o.scale - o.contact;
  if (!m.positions.empty()) {
    m.boundsMin = m.boundsMax = m.positions[0];
    for (const auto& p : m.positions) {
      m.boundsMin = V3f(std::min(m.boundsMin.x, p.x), std::min(m.boundsMin.y, p.y), std::min(m.boundsMin.z, p.z));
      m.boundsMax = V3f(std::max(m.boundsMax.x, p.x), std::max(m.boundsMax.y, p.y), std::max(m.boundsMax.z, p.z));
    }
  }
  if (haveFileNormals && o.fileNormals) {
    for (auto& n : m.normals)
      if (n.Length() > 0) n.Normalize();  // a zero normal in the file stays zero
    return;
  }
  std::vector<V3f> acc(positionCount, V3f(0, 0, 0));
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const V3f& a = m.positions[m.indices[t]];
    const V3f& b = m.positions[m.indices[t + 1]];
    const V3f& c = m.positions[m.indices[t + 2]];
    V3f n = (b - a) % (c - a);
    const float l = n.Length();
    if (l > 0 && std::isfinite(l)) n = n / l; else n = V3f(0, 0, 0);
    for (int k = 0; k < 3; ++k) acc[posId[m.indices[t + k]]] += n;
  }
  m.normals.resize(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    V3f n = acc[posId[v]];
    const float l = n.Length();
    m.normals[v] = l > 0 && std::isfinite(l) ? n / l : V3f(0, 0, 0);
  }
}

std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

// For an error message: the first face line whose indices are out of range (OBJ numbering).
size_t findBadFaceLine(std::string_view text) {
  long nv = 0, nvt = 0, nvn = 0;
  size_t line = 0, start = 0;
  while (start < text.size()) {
    size_t nl = text.find('\n', start);
    std::string l(text.substr(start, nl == std::string_view::npos ? std::string_view::npos : nl - start));
    ++line;
    std::istringstream in(l);
    std::string tok;
    in >> tok;
    if (tok == "v") ++nv;
    else if (tok == "vt") ++nvt;
    else if (tok == "vn") ++nvn;
    else if (tok == "f") {
      std::string corner;
      while (in >> corner) {
        long idx[3] = {0, 0, 0};
        const long cnt[3] = {nv, nvt, nvn};
        size_t p = 0;
        for (int k = 0; k < 3 && p <= corner.size(); ++k) {
          size_t q = corner.find('/', p);
          std::string part = corner.substr(p, q == std::string::npos ? std::string::npos : q - p);
          if (!part.empty()) {
            idx[k] = std::atol(part.c_str());
            long r = idx[k] > 0 ? idx[k] - 1 : cnt[k] + idx[k];
            if (idx[k] == 0 || r < 0 || r >= cnt[k]) return line;
          }
          if (q == std::string::npos) break;
          p = q + 1;
        }
      }
    }
    if (nl == std::string_view::npos) break;
    start = nl + 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64, Invalid };

PlyType plyType(const std::string& s) {
  if (s == "char" || s == "int8") return PlyType::I8;
  if (s == "uchar" || s == "uint8") return PlyType::U8;
  if (s == "short" || s == "int16") return PlyType::I16;
  if (s == "ushort" || s == "uint16") return PlyType::U16;
  if (s == "int" || s == "int32") return PlyType::I32;
  if (s == "uint" || s == "uint32") return PlyType::U32;
  if (s == "float" || s == "float32") return PlyType::F32;
  if (s == "double" || s == "float64") return PlyType::F64;
  return PlyType::Invalid;
}

size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::I8: case PlyType::U8: return 1;
    case PlyType::I16: case PlyType::U16: return 2;
    case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
    case PlyType::F64: return 8;
    default: return 0;
  }
}

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType countType = PlyType::Invalid, type = PlyType::Invalid;
};
struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

enum class PlyFormat { Ascii, BinaryLE, BinaryBE };

// Reads scalar values from the body, in any of the three encodings.
class PlyBody {
 public:
  PlyBody(std::string_view data, PlyFormat f, size_t firstLine) : d_(data), f_(f), line_(firstLine) {}

  size_t line() const { return line_; }

  // Binary: reads one value of type t. Ascii: reads the next token of the current line.
  bool read(PlyType t, double* out) {
    if (f_ == PlyFormat::Ascii) {
      if (tokPos_ >= toks_.size()) return false;
      const std::string& s = toks_[tokPos_++];
      char* end = nullptr;
      double v = std::strtod(s.c_str(), &end);
      if (end != s.c_str() + s.size() || !std::isfinite(v)) return false;
      *out = v;
      return true;
    }
    const size_t n = plySize(t);
    if (n == 0 || pos_ + n > d_.size()) return false;
    unsigned char b[8];
    std::memcpy(b, d_.data() + pos_, n);
    pos_ += n;
    const bool hostLE = [] { uint16_t x = 1; unsigned char c; std::memcpy(&c, &x, 1); return c == 1; }();
    if ((f_ == PlyFormat::BinaryLE) != hostLE) std::reverse(b, b + n);
    switch (t) {
      case PlyType::I8: { int8_t v; std::memcpy(&v, b, 1); *out = v; break; }
      case PlyType::U8: { uint8_t v; std::memcpy(&v, b, 1); *out = v; break; }
      case PlyType::I16: { int16_t v; std::memcpy(&v, b, 2); *out = v; break; }
      case PlyType::U16: { uint16_t v; std::memcpy(&v, b, 2); *out = v; break; }
      case PlyType::I32: { int32_t v; std::memcpy(&v, b, 4); *out = v; break; }
      case PlyType::U32: { uint32_t v; std::memcpy(&v, b, 4); *out = v; break; }
      case PlyType::F32: { float v; std::memcpy(&v, b, 4); *out = v; break; }
      case PlyType::F64: { double v; std::memcpy(&v, b, 8); *out = v; break; }
      default: return false;
    }
    return std::isfinite(*out);
  }

  // Ascii: moves to the next non-blank line (one element instance per line). Binary: no-op.
  bool beginInstance() {
    if (f_ != PlyFormat::Ascii) return true;
    while (pos_ < d_.size()) {
      size_t nl = d_.find('\n', pos_);
      std::string_view l = d_.substr(pos_, nl == std::string_view::npos ? std::string_view::npos : nl - pos_);
      pos_ = nl == std::string_view::npos ? d_.size() : nl + 1;
      ++line_;
      toks_.clear();
      tokPos_ = 0;
      std::istringstream in{std::string(l)};
      std::string t;
      while (in >> t) toks_.push_back(t);
      if (!toks_.empty()) return true;
    }
    return false;
  }
  bool instanceFullyRead() const { return f_ != PlyFormat::Ascii || tokPos_ == toks_.size(); }

 private:
  std::string_view d_;
  PlyFormat f_;
  size_t pos_ = 0;
  size_t line_;
  std::vector<std::string> toks_;
  size_t tokPos_ = 0;
};

}  // namespace

llvm::Expected<MeshData> parseObj(std::string_view text, const std::string& fileName, const MeshLoadOptions& o) {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream in{std::string(text)};
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, /*readMatFn=*/nullptr,
                                   /*triangulate=*/false, /*default_vcols_fallback=*/false);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n')) err.pop_back();
    return fail(fileName, 0, err.empty() ? "cannot parse OBJ" : err);
  }
  const long nv = long(attrib.vertices.size() / 3), nvt = long(attrib.texcoords.size() / 2),
             nvn = long(attrib.normals.size() / 3);

  MeshData m;
  std::vector<uint32_t> posId;
  std::map<std::tuple<int, int, int>, uint32_t> unify;
  bool anyUv = false, allUv = true, allNormals = true;
  std::vector<uint32_t> poly;
  for (const auto& sh : shapes) {
    size_t k = 0;
    for (size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
      const size_t n = sh.mesh.num_face_vertices[f];
      poly.clear();
      for (size_t c = 0; c < n; ++c) {
        const tinyobj::index_t& ix = sh.mesh.indices[k + c];
        if (ix.vertex_index < 0 || ix.vertex_index >= nv || ix.texcoord_index < -1 || ix.texcoord_index >= nvt ||
            ix.normal_index < -1 || ix.normal_index >= nvn) {
          size_t line = findBadFaceLine(text);
          return fail(fileName, line, "face index out of range");
        }
        const int vt = ix.texcoord_index, vn = o.fileNormals ? ix.normal_index : -1;
        if (vt >= 0) anyUv = true; else allUv = false;
        if (ix.normal_index < 0) allNormals = false;
        auto key = std::make_tuple(ix.vertex_index, vt, vn);
        auto it = unify.find(key);
        uint32_t id;
        if (it == unify.end()) {
          id = uint32_t(m.positions.size());
          unify.emplace(key, id);
          const float* p = &attrib.vertices[3 * size_t(ix.vertex_index)];
          m.positions.push_back(V3f(p[0], p[1], p[2]));
          posId.push_back(uint32_t(ix.vertex_index));
          m.uvs.push_back(vt >= 0 ? V2f(attrib.texcoords[2 * size_t(vt)], attrib.texcoords[2 * size_t(vt) + 1])
                                  : V2f(0, 0));
          if (vn >= 0) {
            const float* q = &attrib.normals[3 * size_t(vn)];
            m.normals.push_back(V3f(q[0], q[1], q[2]));
          } else {
            m.normals.push_back(V3f(0, 0, 0));
          }
        } else {
          id = it->second;
        }
        poly.push_back(id);
      }
      k += n;
      for (size_t c = 1; c + 1 < poly.size(); ++c) m.indices.insert(m.indices.end(), {poly[0], poly[c], poly[c + 1]});
    }
  }
  if (m.indices.empty()) return fail(fileName, 0, "the OBJ file has no faces");
  (void)allUv;
  if (!anyUv) m.uvs.clear();
  finish(m, posId, size_t(nv), allNormals && o.fileNormals, o);
  return m;
}

llvm::Expected<MeshData> parsePly(std::string_view bytes, const std::string& fileName, const MeshLoadOptions& o) {
  // Header (text, up to "end_header").
  size_t pos = 0, line = 0;
  auto nextLine = [&](std::string* out) -> bool {
    if (pos >= bytes.size()) return false;
    size_t nl = bytes.find('\n', pos);
    if (nl == std::string_view::npos) return false;  // the header always ends with a newline
    std::string_view l = bytes.substr(pos, nl - pos);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    *out = std::string(l);
    pos = nl + 1;
    ++line;
    return true;
  };
  std::string l;
  if (!nextLine(&l) || l != "ply") return fail(fileName, 1, "not a PLY file (no 'ply' magic line)");
  std::optional<PlyFormat> format;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (nextLine(&l)) {
    std::istringstream in(l);
    std::string kw;
    in >> kw;
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    if (kw == "format") {
      std::string f, ver;
      in >> f >> ver;
      if (f == "ascii") format = PlyFormat::Ascii;
      else if (f == "binary_little_endian") format = PlyFormat::BinaryLE;
      else if (f == "binary_big_endian") format = PlyFormat::BinaryBE;
      else return fail(fileName, line, "unknown PLY format '" + f + "'");
    } else if (kw == "element") {
      PlyElement e;
      long long n = -1;
      in >> e.name >> n;
      if (e.name.empty() || in.fail() || n < 0) return fail(fileName, line, "malformed 'element' line");
      e.count = size_t(n);
      elements.push_back(e);
    } else if (kw == "property") {
      if (elements.empty()) return fail(fileName, line, "'property' before any 'element'");
      PlyProperty p;
      std::string t;
      in >> t;
      if (t == "list") {
        std::string ct, it;
        in >> ct >> it >> p.name;
        p.isList = true;
        p.countType = plyType(ct);
        p.type = plyType(it);
        if (p.countType == PlyType::Invalid || p.type == PlyType::Invalid || p.name.empty() ||
            p.countType == PlyType::F32 || p.countType == PlyType::F64)
          return fail(fileName, line, "malformed list property");
      } else {
        in >> p.name;
        p.type = plyType(t);
        if (p.type == PlyType::Invalid || p.name.empty()) return fail(fileName, line, "malformed property");
      }
      elements.back().props.push_back(p);
    } else if (kw == "end_header") {
      ended = true;
      break;
    } else {
      return fail(fileName, line, "unknown PLY header keyword '" + kw + "'");
    }
  }
  if (!ended) return fail(fileName, line, "truncated PLY header (no 'end_header')");
  if (!format) return fail(fileName, line, "PLY header has no 'format' line");

  PlyBody body(bytes.substr(pos), *format, line);
  const size_t bodyBytes = bytes.size() - pos;
  auto where = [&]() { return *format == PlyFormat::Ascii ? body.line() : size_t(0); };

  MeshData m;
  size_t vertexCount = 0;
  bool haveNormals = false, haveUv = false, haveColor = false;
  for (const auto& e : elements) {
    // Each instance takes at least one byte (binary) or one line (ascii): bounds the allocation.
    if (e.props.empty()) continue;  // nothing to read
    size_t minPer = 2;  // ascii: at least one character and a separator
    if (*format != PlyFormat::Ascii) {
      minPer = 0;
      for (const auto& p : e.props) minPer += p.isList ? plySize(p.countType) : plySize(p.type);
    }
    if (e.count > bodyBytes / minPer + 1)
      return fail(fileName, where(), "element '" + e.name + "' count exceeds the file size");
    const bool isVertex = e.name == "vertex", isFace = e.name == "face";
    if (isVertex) {
      vertexCount = e.count;
      m.positions.assign(e.count, V3f());
      auto has = [&](const char* n) {
        return std::any_of(e.props.begin(), e.props.end(), [&](const PlyProperty& p) { return !p.isList && p.name == n; });
      };
      haveNormals = has("nx") && has("ny") && has("nz");
      haveUv = (has("u") && has("v")) || (has("s") && has("t")) || (has("texture_u") && has("texture_v")) ||
               (has("texture_s") && has("texture_t"));
      haveColor = has("red") && has("green") && has("blue");
      if (haveNormals) m.normals.assign(e.count, V3f());
      if (haveUv) m.uvs.assign(e.count, V2f());
      if (haveColor) m.colors.assign(e.count, V3f());
    }
    for (size_t i = 0; i < e.count; ++i) {
      if (!body.beginInstance())
        return fail(fileName, where(), "truncated PLY data in element '" + e.name + "' (" + std::to_string(i) +
                                           " of " + std::to_string(e.count) + ")");
      for (const auto& p : e.props) {
        if (p.isList) {
          double cnt = 0;
          if (!body.read(p.countType, &cnt) || cnt < 0 || cnt != std::floor(cnt) || cnt > 1e6)
            return fail(fileName, where(), "truncated or malformed list in element '" + e.name + "'");
          const bool indices = isFace && (p.name == "vertex_indices" || p.name == "vertex_index");
          std::vector<uint32_t> poly;
          for (size_t k = 0; k < size_t(cnt); ++k) {
            double v = 0;
            if (!body.read(p.type, &v))
              return fail(fileName, where(), "truncated or malformed list in element '" + e.name + "'");
            if (indices) {
              if (v < 0 || v >= double(vertexCount) || v != std::floor(v)) {
                // As written: it may be fractional or beyond every integer type (found by fuzz_ply).
                char text[32];
                std::snprintf(text, sizeof text, "%.17g", v);
                return fail(fileName, where(), std::string("face index ") + text + " out of range");
              }
              poly.push_back(uint32_t(v));
            }
          }
          for (size_t c = 1; c + 1 < poly.size(); ++c) m.indices.insert(m.indices.end(), {poly[0], poly[c], poly[c + 1]});
        } else {
          double v = 0;
          if (!body.read(p.type, &v))
            return fail(fileName, where(), "truncated or malformed value '" + p.name + "' in element '" + e.name + "'");
          if (!isVertex) continue;
          const float f = float(v);
          const std::string& n = p.name;
          if (n == "x") m.positions[i].x = f;
          else if (n == "y") m.positions[i].y = f;
          else if (n == "z") m.positions[i].z = f;
          else if (haveNormals && n == "nx") m.normals[i].x = f;
          else if (haveNormals && n == "ny") m.normals[i].y = f;
          else if (haveNormals && n == "nz") m.normals[i].z = f;
          else if (haveUv && (n == "u" || n == "s" || n == "texture_u" || n == "texture_s")) m.uvs[i].x = f;
          else if (haveUv && (n == "v" || n == "t" || n == "texture_v" || n == "texture_t")) m.uvs[i].y = f;
          else if (haveColor && (n == "red" || n == "green" || n == "blue")) {
            const float c = (p.type == PlyType::F32 || p.type == PlyType::F64) ? f
                            : p.type == PlyType::U16 ? f / 65535.0f : f / 255.0f;
            (n == "red" ? m.colors[i].x : n == "green" ? m.colors[i].y : m.colors[i].z) = c;
          }
        }
      }
      if (!body.instanceFullyRead())
        return fail(fileName, where(), "extra values in element '" + e.name + "'");
    }
  }
  if (m.positions.empty()) return fail(fileName, 0, "the PLY file has no vertices");
  if (m.indices.empty()) return fail(fileName, 0, "the PLY file has no faces");
  std::vector<uint32_t> posId(m.positions.size());
  for (size_t i = 0; i < posId.size(); ++i) posId[i] = uint32_t(i);
  finish(m, posId, m.positions.size(), haveNormals, o);
  return m;
}

llvm::Expected<MeshData> loadMesh(const std::string& path, const MeshLoadOptions& options) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  std::string_view data = (*buf)->getBuffer();
  const std::string lp = lower(path);
  auto ends = [&](const char* s) { size_t n = std::strlen(s); return lp.size() >= n && lp.compare(lp.size() - n, n, s) == 0; };
  bool ply;
  if (ends(".ply")) ply = true;
  else if (ends(".obj")) ply = false;
  else ply = data.substr(0, 3) == "ply";
  return ply ? parsePly(data, path, options) : parseObj(data, path, options);
}

}  // namespace lcjit::runtime
