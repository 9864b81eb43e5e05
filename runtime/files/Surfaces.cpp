// Bézier surfaces: see Surfaces.h. Follows lpfg's surface reader and patch tessellation (facts).
#include "runtime/files/Surfaces.h"
#include "runtime/files/TextLines.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include <llvm/Support/MemoryBuffer.h>

namespace lcjit::runtime {
namespace {

using textfile::fail;
using textfile::splitLines;
using textfile::trim;

bool isBlank(std::string_view s) { return trim(s).empty(); }

// Parses a float at the start of s (after blanks); advances s.
bool readFloat(std::string_view* s, float* out) {
  std::string_view t = trim(*s);
  size_t n = 0;
  while (n < t.size() && !std::isspace((unsigned char)t[n])) ++n;
  if (n == 0) return false;
  std::string tok(t.substr(0, n));
  char* end = nullptr;
  float v = std::strtof(tok.c_str(), &end);
  if (end == tok.c_str() || !std::isfinite(v)) return false;
  size_t used = size_t(end - tok.c_str());
  *out = v;
  *s = t.substr(used);
  return true;
}

// "KEY X: x Y: y Z: z" (blanks between KEY's words and around ':' are free, as with sscanf).
bool readKeyedVector(std::string_view line, std::string_view key, V3f* out) {
  line = trim(line);
  // match the key word by word
  size_t pos = 0;
  for (size_t k = 0; k < key.size();) {
    if (key[k] == ' ') {
      while (pos < line.size() && std::isspace((unsigned char)line[pos])) ++pos;
      ++k;
      continue;
    }
    if (pos >= line.size() || line[pos] != key[k]) return false;
    ++pos;
    ++k;
  }
  std::string_view rest = line.substr(pos);
  float* dst[3] = {&out->x, &out->y, &out->z};
  const char axes[3] = {'X', 'Y', 'Z'};
  for (int a = 0; a < 3; ++a) {
    rest = trim(rest);
    if (rest.size() < 2 || rest[0] != axes[a]) return false;
    rest.remove_prefix(1);
    rest = trim(rest);
    if (rest.empty() || rest[0] != ':') return false;
    rest.remove_prefix(1);
    if (!readFloat(&rest, dst[a])) return false;
  }
  return true;
}

float bern(int i, float f) {
  const float m = 1.0f - f;
  switch (i) {
    case 0: return m * m * m;
    case 1: return 3.0f * f * m * m;
    case 2: return 3.0f * f * f * m;
    default: return f * f * f;
  }
}
float dbern(int i, float f) {
  const float m = 1.0f - f;
  switch (i) {
    case 0: return -3.0f * m * m;
    case 1: return 3.0f * m * m - 6.0f * m * f;
    case 2: return 6.0f * m * f - 3.0f * f * f;
    default: return 3.0f * f * f;
  }
}

std::string surfaceName(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = base.find('.');
  return dot == std::string::npos ? base : base.substr(0, dot);
}

}  // namespace

V3f bezierPoint(const SurfaceObj& s, float u, float v) {
  V3f r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r += s.points[4 * i + j] * (bern(i, u) * bern(j, v));
  return r;
}

V3f bezierNormal(const SurfaceObj& s, float u, float v) {
  V3f du, dv;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      du += s.points[4 * i + j] * (dbern(i, u) * bern(j, v));
      dv += s.points[4 * i + j] * (bern(i, u) * dbern(j, v));
    }
  V3f n = du % dv;
  const float l = n.Length();
  return l > 0 && std::isfinite(l) ? n / l : V3f(0, 0, 0);
}

PatchGrid tessellatePatch(const SurfaceObj& s, int uDiv, int vDiv) {
  PatchGrid g;
  g.uDiv = std::clamp(uDiv, 1, 1024);
  g.vDiv = std::clamp(vDiv, 1, 1024);
  const size_t n = size_t(g.uDiv + 1) * size_t(g.vDiv + 1);
  g.positions.resize(n);
  g.normals.resize(n);
  g.uvs.resize(n);
  for (int i = 0; i <= g.uDiv; ++i) {
    const float u = 1.0f * float(i) / float(g.uDiv);
    for (int j = 0; j <= g.vDiv; ++j) {
      const float v = 1.0f * float(j) / float(g.vDiv);
      const size_t k = g.at(i, j);
      g.positions[k] = bezierPoint(s, u, v);
      g.normals[k] = bezierNormal(s, u, v);
      g.uvs[k] = V2f(v, 1.0f - u);
    }
  }
  g.indices.reserve(size_t(g.uDiv) * size_t(g.vDiv) * 6);
  for (int i = 0; i < g.uDiv; ++i)
    for (int j = 0; j < g.vDiv; ++j) {
      const uint32_t a = uint32_t(g.at(i, j)), b = uint32_t(g.at(i + 1, j)), c = uint32_t(g.at(i + 1, j + 1)),
                     d = uint32_t(g.at(i, j + 1));
      g.indices.insert(g.indices.end(), {a, b, c, a, c, d});
    }
  return g;
}

V3f BezierSurface::controlPoint(int k) const {
  if (k < 0 || size_t(k / 16) >= patches.size()) return V3f();
  return patches[size_t(k / 16)].points[k % 16];
}

PatchGrid BezierSurface::tessellate(size_t k, int uDiv, int vDiv) const {
  if (k >= patches.size()) return PatchGrid();
  PatchGrid g = tessellatePatch(patches[k], uDiv, vDiv);
  if (patches.size() > 1) {
    const float xr = boundsMax.x - boundsMin.x, yr = boundsMax.y - boundsMin.y;
    for (size_t i = 0; i < g.positions.size(); ++i) {
      const V3f& p = g.positions[i];
      const float s = xr != 0 ? (p.x - boundsMin.x) / xr : 0.0f;
      const float t = yr != 0 ? (p.y - boundsMin.y) / yr : 0.0f;
      g.uvs[i] = V2f(s, 1.0f - t);
    }
  }
  return g;
}

llvm::Expected<BezierSurface> parseSurface(std::string_view text, const std::string& fileName) {
  const auto lines = splitLines(text);
  size_t ln = 0;
  auto next = [&]() -> bool {  // move to the next non-blank line; false at the end
    while (ln < lines.size() && isBlank(lines[ln])) ++ln;
    return ln < lines.size();
  };
  BezierSurface s;
  s.name = surfaceName(fileName);

  // Bounding box line (ignored, as lpfg does).
  if (!next()) return fail(fileName, 1, "empty surface file");
  ++ln;
  if (!next()) return fail(fileName, ln, "truncated surface header");
  {
    std::string_view l = trim(lines[ln]);
    if (l.substr(0, 9) == "PRECISION") {
      // "PRECISION S: s T: t"
      auto num = [&](char axis, std::optional<int>* out) {
        size_t p = l.find(std::string(1, axis) + ":");
        if (p == std::string_view::npos) return;
        std::string tok(trim(l.substr(p + 2)));
        char* end = nullptr;
        long v = std::strtol(tok.c_str(), &end, 10);
        if (end != tok.c_str()) *out = int(v);
      };
      num('S', &s.precisionS);
      num('T', &s.precisionT);
      ++ln;
      if (!next()) return fail(fileName, ln, "truncated surface header");
    }
  }
  if (!readKeyedVector(lines[ln], "CONTACT POINT", &s.contact))
    return fail(fileName, ln + 1, "expected 'CONTACT POINT X: x Y: y Z: z'");
  ++ln;
  if (!next()) return fail(fileName, ln, "truncated surface header");
  if (!readKeyedVector(lines[ln], "END POINT", &s.end)) s.end = V3f();  // lpfg skips this line
  ++ln;
  if (!next() || !readKeyedVector(lines[ln], "HEADING", &s.heading))
    return fail(fileName, std::min(ln + 1, lines.size()), "expected 'HEADING X: x Y: y Z: z'");
  if (s.heading.Length() < 0.001f) return fail(fileName, ln + 1, "the heading vector is (nearly) zero");
  s.heading *= 1.0f / s.heading.Length();  // lpfg normalises by one reciprocal
  ++ln;
  if (!next() || !readKeyedVector(lines[ln], "UP", &s.up))
    return fail(fileName, std::min(ln + 1, lines.size()), "expected 'UP X: x Y: y Z: z'");
  if (s.up.Length() < 0.001f) return fail(fileName, ln + 1, "the up vector is (nearly) zero");
  s.up *= 1.0f / s.up.Length();
  ++ln;
  {
    bool ok = next();
    std::string_view l = ok ? trim(lines[ln]) : std::string_view();
    if (!ok || l.substr(0, 5) != "SIZE:")
      return fail(fileName, std::min(ln + 1, lines.size()), "expected 'SIZE: x'");
    std::string_view rest = l.substr(5);
    if (!readFloat(&rest, &s.size)) return fail(fileName, ln + 1, "malformed 'SIZE:' value");
    if (s.size == 0.0f) return fail(fileName, ln + 1, "SIZE must not be 0");
    ++ln;
  }

  const V3f left = s.up % s.heading;
  const V3f mleft = -left;
  bool haveBounds = false;
  while (next()) {
    const size_t nameLine = ln + 1;
    std::string_view nm = trim(lines[ln]);
    size_t e = 0;
    while (e < nm.size() && !std::isspace((unsigned char)nm[e])) ++e;
    s.patchNames.emplace_back(nm.substr(0, e));
    // colour line and three neighbour lines, ignored
    if (ln + 5 > lines.size())
      return fail(fileName, nameLine, "truncated patch '" + s.patchNames.back() + "'");
    ln += 5;
    SurfaceObj patch;
    int count = 0;
    std::string_view rest;
    while (count < 48) {
      if (ln >= lines.size())
        return fail(fileName, lines.size(),
                    "truncated patch '" + s.patchNames.back() + "': expected 16 control points");
      rest = lines[ln];
      while (count < 48 && !trim(rest).empty()) {
        float v = 0;
        if (!readFloat(&rest, &v))
          return fail(fileName, ln + 1, "malformed control point in patch '" + s.patchNames.back() + "'");
        V3tf& p = patch.points[count / 3];
        (count % 3 == 0 ? p.x : count % 3 == 1 ? p.y : p.z) = v;
        ++count;
      }
      ++ln;  // the rest of the line after the 16th point is ignored, as in lpfg
    }
    for (auto& p : patch.points) {
      const V3f q = (p - s.contact) * (1.0f / s.size);
      p = mleft * q.x + s.heading * q.y + s.up * q.z;
      if (!haveBounds) {
        s.boundsMin = s.boundsMax = p;
        haveBounds = true;
      }
      s.boundsMin = V3f(std::min(s.boundsMin.x, p.x), std::min(s.boundsMin.y, p.y), std::min(s.boundsMin.z, p.z));
      s.boundsMax = V3f(std::max(s.boundsMax.x, p.x), std::max(s.boundsMax.y, p.y), std::max(s.boundsMax.z, p.z));
    }
    s.patches.push_back(patch);
  }
  if (s.patches.empty()) return fail(fileName, lines.size(), "the surface has no patches");
  return s;
}

llvm::Expected<BezierSurface> loadSurface(const std::string& path) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  return parseSurface((*buf)->getBuffer(), path);
}

}  // namespace lcjit::runtime
