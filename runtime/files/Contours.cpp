// Contours: see Contours.h. Follows lpfg's contour reader and sampler (facts, not code).
#include "runtime/files/Contours.h"
#include "runtime/files/TextLines.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <llvm/Support/MemoryBuffer.h>

namespace lcjit::runtime {
namespace {

using textfile::fail;
using textfile::splitLines;
using textfile::trim;

constexpr float kEpsilon = 0.0001f;
constexpr size_t kStepsPerSegment = 1000;  // lpfg evaluates each B-spline segment at 1000 points
constexpr size_t kMaxControlPoints = 20000;  // 2·10^7 curve evaluations at most

std::vector<std::string> tokens(std::string_view s) {
  std::vector<std::string_view> w = textfile::words(s);
  return {w.begin(), w.end()};
}

bool toFloat(const std::string& s, float* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  float v = std::strtof(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

bool toInt(const std::string& s, long* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  long v = std::strtol(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) return false;
  *out = v;
  return true;
}

bool blankOrComment(std::string_view l) {
  l = trim(l);
  return l.empty() || l.front() == '#';
}

// "key:" prefix (case-sensitive, as cuspy writes it); returns the rest of the line.
bool keyed(std::string_view line, std::string_view key, std::string_view* rest) {
  line = trim(line);
  if (line.size() < key.size() || line.substr(0, key.size()) != key) return false;
  *rest = trim(line.substr(key.size()));
  return true;
}

int clampDivisions(long n) {
  return (int)std::clamp<long>(n, Contour::kMinDivisions, Contour::kMaxDivisions);
}

// A uniform cubic B-spline segment (control points a..d) the way lpfg evaluates it: the basis
// matrix times the point matrix (4×4 by 4×3), then the row [s³ s² s 1] times that, every entry a
// float sum from 0 in index order. The tangent uses the derivative's matrix the same way. The
// bits matter: the curve functions return these points (through the arc-length resampling).
constexpr float kSplineBasis[4][4] = {{-1.0f / 6.0f, 3.0f / 6.0f, -3.0f / 6.0f, 1.0f / 6.0f},
                                      {3.0f / 6.0f, -6.0f / 6.0f, 3.0f / 6.0f, 0.0f},
                                      {-3.0f / 6.0f, 0.0f, 3.0f / 6.0f, 0.0f},
                                      {1.0f / 6.0f, 4.0f / 6.0f, 1.0f / 6.0f, 0.0f}};
constexpr float kSplineDerivative[4][4] = {{0.0f, 0.0f, 0.0f, 0.0f},
                                           {-3.0f / 6.0f, 9.0f / 6.0f, -9.0f / 6.0f, 3.0f / 6.0f},
                                           {6.0f / 6.0f, -2.0f, 6.0f / 6.0f, 0.0f},
                                           {-3.0f / 6.0f, 0.0f, 3.0f / 6.0f, 0.0f}};

struct SegmentMatrices {
  float point[4][3], tangent[4][3];
};

SegmentMatrices segmentMatrices(const V3f& a, const V3f& b, const V3f& c, const V3f& d) {
  const float p[4][3] = {{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}, {d.x, d.y, d.z}};
  SegmentMatrices m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) {
      float sp = 0.0f, st = 0.0f;
      for (int k = 0; k < 4; ++k) {
        sp += kSplineBasis[i][k] * p[k][j];
        st += kSplineDerivative[i][k] * p[k][j];
      }
      m.point[i][j] = sp;
      m.tangent[i][j] = st;
    }
  return m;
}

V3f powerRowTimes(const float (&g)[4][3], float s) {
  const float s2 = s * s;
  const float row[4] = {s * s2, s2, s, 1.0f};
  float r[3];
  for (int j = 0; j < 3; ++j) {
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) sum += row[k] * g[k][j];
    r[j] = sum;
  }
  return V3f(r[0], r[1], r[2]);
}

// (0,0,1) × the unit tangent (lpfg normalises with one reciprocal and three products).
V3f normalOfTangent(V3f t) {
  const float len = t.Length();
  if (len < kEpsilon) return V3f(0, 0, 0);
  const float inv = 1.0f / len;
  return V3f(0, 0, 1) % V3f(t.x * inv, t.y * inv, t.z * inv);
}

// Open-uniform cubic B-spline basis with lpfg's integer knots (for the deprecated oe/ce types).
float knot(size_t j, size_t n) {
  const size_t k = 4;
  if (j < k) return 0;
  if (j > n) return float(n - k + 2);
  return float(j - k + 1);
}
float basis(size_t i, size_t order, float u, size_t n) {
  if (order == 1) return (knot(i, n) <= u && u < knot(i + 1, n)) ? 1.f : 0.f;
  float sum = 0;
  float den = knot(i + order - 1, n) - knot(i, n);
  if (den != 0) sum = (u - knot(i, n)) / den * basis(i, order - 1, u, n);
  den = knot(i + order, n) - knot(i + 1, n);
  if (den != 0) sum += (knot(i + order, n) - u) / den * basis(i + 1, order - 1, u, n);
  return sum;
}

std::string stemOf(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = base.find('.');
  return dot == std::string::npos ? base : base.substr(0, dot);
}

bool endsWith(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Blending

ContourSamples blendContours(const ContourSamples& a, const ContourSamples& b, float t) {
  if (t == 0.0f || b.points.empty()) return a;
  if (t == 1.0f || a.points.empty()) return b;
  ContourSamples r;
  r.closed = a.closed;
  const size_t n = a.points.size();
  r.points.resize(n);
  r.normals.resize(n);
  const float s = 1.0f - t;
  for (size_t i = 0; i < n; ++i) {
    V3f bp, bn;
    if (b.points.size() == n) {
      bp = b.points[i];
      bn = b.normals[i];
    } else {
      const double f = n > 1 ? double(i) / double(n - 1) * double(b.points.size() - 1) : 0.0;
      size_t k = std::min(size_t(f), b.points.size() - 1);
      float w = float(f - double(k));
      if (k + 1 < b.points.size()) {
        bp = b.points[k] * (1 - w) + b.points[k + 1] * w;
        bn = b.normals[k] * (1 - w) + b.normals[k + 1] * w;
      } else {
        bp = b.points[k];
        bn = b.normals[k];
      }
    }
    r.points[i] = a.points[i] * s + bp * t;
    r.normals[i] = a.normals[i] * s + bn * t;
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Contour

Contour Contour::defaultCircle() {
  Contour c;
  c.name_ = "def_contour";
  c.closed_ = true;
  c.computeDefault();
  return c;
}

void Contour::computeDefault() {
  const int n = divisions_;
  vertex_.assign(n, V3f());
  normal_.assign(n, V3f());
  for (int i = 0; i < n - 1; ++i) {
    // lpfg: π (a double) over the float 0.5·(n-1), times i, in double; sinf/cosf of that.
    const float a = static_cast<float>(M_PI / (0.5f * float(n - 1)) * double(i));
    vertex_[i] = V3f(std::sin(a), std::cos(a), 0.0f);
    normal_[i] = vertex_[i];
  }
  vertex_[n - 1] = vertex_[0];
  normal_[n - 1] = normal_[0];
  arcLen_ = 0;
}

void Contour::compute() {
  if (cpts_.empty())
    computeDefault();
  else if (endPoint_)
    computeEndPoint();
  else
    computeRegular();
}

void Contour::computeRegular() {
  // The curve is evaluated at 1000 points per segment (a closed one then repeats its first
  // point) and resampled by arc length (lpfg's _Reparametrize2). The dense points are generated
  // twice instead of stored: once for the total length, once while resampling.
  const size_t segments = cpts_.size() >= 4 ? cpts_.size() - 3 : 0;
  if (segments == 0) {  // cannot happen for a parsed contour (>= 4 points)
    computeDefault();
    return;
  }
  const size_t m = segments * kStepsPerSegment + (closed_ ? 1 : 0);
  SegmentMatrices matrices;
  size_t cachedSegment = SIZE_MAX;
  auto dense = [&](size_t k, V3f* p, V3f* nrm) {
    if (k == segments * kStepsPerSegment) k = 0;  // closing point
    const size_t seg = k / kStepsPerSegment;
    if (seg != cachedSegment) {
      matrices = segmentMatrices(cpts_[seg], cpts_[seg + 1], cpts_[seg + 2], cpts_[seg + 3]);
      cachedSegment = seg;
    }
    const float s = float(k % kStepsPerSegment) / float(kStepsPerSegment);
    *p = powerRowTimes(matrices.point, s);
    *nrm = normalOfTangent(powerRowTimes(matrices.tangent, s));
  };

  float total = 0;
  {
    V3f prev, cur, n;
    dense(0, &prev, &n);
    for (size_t k = 1; k < m; ++k) {
      dense(k, &cur, &n);
      total += (cur - prev).Length();
      prev = cur;
    }
  }
  if (total < kEpsilon) total = kEpsilon;
  arcLen_ = total;

  const int n = divisions_;
  vertex_.assign(n, V3f());
  normal_.assign(n, V3f());
  // Segment [j, j+1] of the dense curve with normalised arc-length parameters atj, atj1.
  V3f pj, nj, pj1, nj1;
  dense(0, &pj, &nj);
  dense(1, &pj1, &nj1);
  size_t j1 = 1;
  float atj = 0, atj1 = (j1 == m - 1) ? 1.0f : (pj1 - pj).Length() / total;
  vertex_[0] = pj;
  normal_[0] = nj;
  for (int i = 1; i < n - 1; ++i) {
    const float t = float(i) / float(n - 1);
    while (atj1 < t && j1 < m - 1) {
      pj = pj1;
      nj = nj1;
      atj = atj1;
      ++j1;
      dense(j1, &pj1, &nj1);
      atj1 = (j1 == m - 1) ? 1.0f : atj + (pj1 - pj).Length() / total;
    }
    const float dist = atj1 - atj;
    const float r = dist > 0 ? (t - atj) / dist : 0.0f;
    vertex_[i] = pj * (1.0f - r) + pj1 * r;
    normal_[i] = nj * (1.0f - r) + nj1 * r;
  }
  dense(m - 1, &vertex_[n - 1], &normal_[n - 1]);

  // Null normals (cusps) take the previous one; the first takes the first non-null.
  auto isNull = [](const V3f& v) { return v.x == 0 && v.y == 0 && v.z == 0; };
  if (isNull(normal_[0]))
    for (int i = 1; i < n; ++i)
      if (!isNull(normal_[i])) {
        normal_[0] = normal_[i];
        break;
      }
  for (int i = 1; i < n; ++i)
    if (isNull(normal_[i])) normal_[i] = normal_[i - 1];
}

void Contour::computeEndPoint() {
  // Deprecated oe/ce contours: an open-uniform cubic B-spline through the end points, sampled
  // uniformly in its parameter (lpfg does not reparametrise these). lpfg leaves their normals
  // zero and their arc length unset (curveGAL then returns whatever was in memory, often the
  // previous contour's); here drawing gets normals from the sampled polyline (curveNormal still
  // gives lpfg's zeros) and the arc length is the polyline's length.
  const int n = divisions_;
  const size_t last = cpts_.size() - 1;
  vertex_.assign(n, V3f());
  normal_.assign(n, V3f());
  vertex_[0] = cpts_.front();
  for (int i = 1; i < n - 1; ++i) {
    const float u = float(i) / float(n - 1) * float(last - 2);
    V3f s;
    for (size_t k = 0; k <= last; ++k) s += cpts_[k] * basis(k, 4, u, last);
    vertex_[i] = s;
  }
  vertex_[n - 1] = cpts_.back();
  arcLen_ = 0;
  for (int i = 0; i + 1 < n; ++i) arcLen_ += (vertex_[i + 1] - vertex_[i]).Length();
  for (int i = 0; i < n; ++i) {
    V3f a = vertex_[i > 0 ? i - 1 : i], b = vertex_[i + 1 < n ? i + 1 : i];
    if (closed_ && (i == 0 || i == n - 1)) {
      a = vertex_[n >= 2 ? n - 2 : 0];
      b = vertex_[n >= 2 ? 1 : 0];
    }
    normal_[i] = normalOfTangent(b - a);
  }
}

int Contour::drawDivisions(int turtleSides, int viewContourSides) const {
  if (turtleSides > 0) return clampDivisions(turtleSides);
  if (fileSamples_) return *fileSamples_;
  return clampDivisions(long(viewContourSides) + 1);
}

void Contour::setDivisions(int n) {
  n = clampDivisions(n);
  if (n == divisions_ && int(vertex_.size()) == n) return;
  divisions_ = n;
  compute();
}

ContourSamples Contour::sampled(int n) const {
  if (clampDivisions(n) == divisions_) return samples();
  Contour c = *this;
  c.setDivisions(n);
  return c.samples();
}

V3f Contour::pointAt(float t) const {
  if (vertex_.empty()) return V3f();
  if (!(t >= 0.0f)) t = 0.0f;  // also NaN
  if (t > 1.0f) t = 1.0f;
  const double f = double(t) * (double(vertex_.size()) - 1);
  const size_t ix = size_t(f);
  const float w = float(f - double(ix));
  if (ix + 1 < vertex_.size()) return vertex_[ix] * (1.0f - w) + vertex_[ix + 1] * w;
  return vertex_.back();
}

V3f Contour::normalAt(float t) const {
  // lpfg never computes an end-point contour's normals: curveNormal gives (0,0,0) there. The
  // polyline normals below are only for drawing.
  if (endPoint_ || normal_.empty()) return V3f();
  if (!(t >= 0.0f)) t = 0.0f;
  if (t > 1.0f) t = 1.0f;
  const float f = t * float(normal_.size() - 1);
  const size_t ix = std::min(size_t(f), normal_.size() - 1);
  const float w = f - float(ix);
  if (ix + 1 < normal_.size()) return normal_[ix] * (1.0f - w) + normal_[ix + 1] * w;
  return normal_.back();
}

bool Contour::setControlPoint(int index, V3f p) {
  if (index < 0 || size_t(index) >= cpts_.size()) return false;
  cpts_[index] = p;
  return true;
}

void Contour::scale(V3f s) {
  for (auto& p : cpts_) {
    p.x *= s.x;
    p.y *= s.y;
    p.z *= s.z;
  }
  recalculate();
}

void Contour::recalculate() { compute(); }

void Contour::reset() { cpts_ = origCpts_; }

llvm::Expected<Contour> Contour::parse(std::string_view text, const std::string& fileName) {
  auto lines = splitLines(text);
  size_t line = 0;
  return parse(lines, &line, fileName);
}

llvm::Expected<Contour> Contour::parse(const std::vector<std::string_view>& lines, size_t* line,
                                       const std::string& fileName) {
  size_t& ln = *line;
  auto skipBlank = [&] {
    while (ln < lines.size() && blankOrComment(lines[ln])) ++ln;
  };
  skipBlank();
  if (ln >= lines.size()) return fail(fileName, ln + 1, "expected a contour, found the end of the file");

  Contour c;
  std::vector<std::pair<V3f, long>> pts;  // point, multiplicity
  long total = -1;
  std::string_view rest;
  const size_t headerLine = ln + 1;
  const std::string_view first = trim(lines[ln]);

  if (keyed(first, "cver", &rest)) {
    auto v = tokens(rest);
    long major = 0, minor = 0;
    if (v.size() != 2 || !toInt(v[0], &major) || !toInt(v[1], &minor))
      return fail(fileName, headerLine, "malformed version line '" + std::string(first) + "'");
    if (major != 1 || minor < 1 || minor > 3)
      return fail(fileName, headerLine,
                  "unsupported contour version " + std::to_string(major) + "." + std::to_string(minor));
    ++ln;
    bool haveName = false, haveType = false;
    long distinct = -1;
    // Header lines: cuspy writes name, points, type, [samples], [background, backgroundXY]; lpfg
    // also skips `markers:` blocks. Accepted in any order until the first point line.
    while (true) {
      skipBlank();
      if (ln >= lines.size()) return fail(fileName, ln, "truncated contour header");
      std::string_view l = trim(lines[ln]);
      const size_t here = ln + 1;
      if (keyed(l, "name:", &rest)) {
        auto t = tokens(rest);
        if (t.empty()) return fail(fileName, here, "missing contour name");
        c.name_ = t[0].substr(0, 30);  // lpfg reads the first word, at most 30 characters
        haveName = true;
      } else if (keyed(l, "points:", &rest)) {
        auto t = tokens(rest);
        if (t.size() != 2 || !toInt(t[0], &distinct) || !toInt(t[1], &total))
          return fail(fileName, here, "malformed 'points:' line");
        if (distinct < 1 || total < 4)
          return fail(fileName, here, "a contour needs at least 4 control points (counting multiplicity)");
        if (total > long(kMaxControlPoints) || distinct > total)
          return fail(fileName, here, "inconsistent point counts");
      } else if (keyed(l, "type:", &rest)) {
        auto t = tokens(rest);
        if (t.empty()) return fail(fileName, here, "missing contour type");
        const std::string& ty = t[0];
        if (minor == 1) {
          if (ty == "open")
            c.closed_ = false;
          else if (ty == "closed")
            c.closed_ = true;
          else
            return fail(fileName, here, "contour type must be 'open' or 'closed' in version 1.1");
        } else {
          if (ty.size() < 2 || (ty[0] != 'o' && ty[0] != 'c') || (ty[1] != 'r' && ty[1] != 'e'))
            return fail(fileName, here, "contour type must be or, cr, oe or ce");
          c.closed_ = ty[0] == 'c';
          c.endPoint_ = ty[1] == 'e';
        }
        haveType = true;
      } else if (keyed(l, "samples:", &rest)) {
        auto t = tokens(rest);
        long s = 0;
        if (t.size() != 1 || !toInt(t[0], &s)) return fail(fileName, here, "malformed 'samples:' line");
        c.fileSamples_ = clampDivisions(s);
      } else if (keyed(l, "backgroundXY:", &rest) || keyed(l, "background:", &rest)) {
        // editor-only
      } else if (keyed(l, "markers:", &rest)) {
        auto t = tokens(rest);
        long m = 0;
        if (t.size() != 1 || !toInt(t[0], &m) || m < 0) return fail(fileName, here, "malformed 'markers:' line");
        if (size_t(m) > lines.size() - ln - 1) return fail(fileName, here, "truncated markers");
        ln += size_t(m);
      } else {
        break;  // the first point line
      }
      ++ln;
    }
    if (!haveName) return fail(fileName, headerLine, "contour has no 'name:' line");
    if (total < 0) return fail(fileName, headerLine, "contour has no 'points:' line");
    if (!haveType) return fail(fileName, headerLine, "contour has no 'type:' line");
    long sum = 0;
    for (long i = 0; i < distinct; ++i) {
      skipBlank();
      if (ln >= lines.size())
        return fail(fileName, ln, "truncated contour: expected " + std::to_string(distinct) + " points, found " +
                                      std::to_string(i));
      auto t = tokens(lines[ln]);
      V3f p;
      long m = 0;
      if (t.size() != 4 || !toFloat(t[0], &p.x) || !toFloat(t[1], &p.y) || !toFloat(t[2], &p.z) ||
          !toInt(t[3], &m))
        return fail(fileName, ln + 1, "malformed control point (expected 'x y z multiplicity')");
      if (m < 1 || m > total) return fail(fileName, ln + 1, "invalid multiplicity " + t[3]);
      sum += m;
      if (sum > total) return fail(fileName, ln + 1, "multiplicities exceed the 'points:' total");
      pts.push_back({p, m});
      ++ln;
    }
    if (sum != total)
      return fail(fileName, headerLine,
                  "multiplicities add up to " + std::to_string(sum) + ", not " + std::to_string(total));
  } else {
    // Version 1.0: "n dim type" then n points of dim coordinates.
    auto t = tokens(first);
    long n = 0, dim = 0;
    if (t.size() < 3 || !toInt(t[0], &n) || !toInt(t[1], &dim))
      return fail(fileName, headerLine, "not a contour file (expected 'cver' or 'n dim type')");
    if (dim != 2 && dim != 3) return fail(fileName, headerLine, "dimension must be 2 or 3");
    if (n < 4 || n > long(kMaxControlPoints))
      return fail(fileName, headerLine, "a contour needs at least 4 control points");
    std::string ty = t[2];
    for (auto& ch : ty) ch = char(std::tolower((unsigned char)ch));
    if (ty == "closed")
      c.closed_ = true;
    else if (ty == "open")
      c.closed_ = false;
    else
      return fail(fileName, headerLine, "contour type must be 'open' or 'closed'");
    c.name_ = stemOf(fileName).substr(0, 30);
    ++ln;
    for (long i = 0; i < n; ++i) {
      skipBlank();
      if (ln >= lines.size()) return fail(fileName, ln, "truncated contour: expected " + std::to_string(n) + " points");
      auto pt = tokens(lines[ln]);
      V3f p;
      if (pt.size() < size_t(dim) || !toFloat(pt[0], &p.x) || !toFloat(pt[1], &p.y) ||
          (dim == 3 && !toFloat(pt[2], &p.z)))
        return fail(fileName, ln + 1, "malformed control point");
      pts.push_back({p, 1});
      ++ln;
    }
    total = n;
  }

  // Expanded control points, as lpfg stores them.
  std::vector<V3f> expanded;
  for (auto& [p, m] : pts)
    for (long k = 0; k < m; ++k) expanded.push_back(p);
  if (c.closed_) {
    if (!c.endPoint_) {
      std::vector<V3f> wrapped(expanded.end() - 3, expanded.end());
      wrapped.insert(wrapped.end(), expanded.begin(), expanded.end());
      expanded = std::move(wrapped);
    } else {
      expanded.push_back(expanded.front());
    }
  }
  c.cpts_ = expanded;
  c.origCpts_ = expanded;
  c.divisions_ = c.fileSamples_.value_or(kDefaultDivisions);
  c.compute();
  c.extentMin_ = V3f(1e11f, 1e11f, 0);
  c.extentMax_ = V3f(-1e11f, -1e11f, 0);
  for (const V3f& v : c.vertex_) {
    c.extentMin_ = V3f(std::min(c.extentMin_.x, v.x), std::min(c.extentMin_.y, v.y), 0);
    c.extentMax_ = V3f(std::max(c.extentMax_.x, v.x), std::max(c.extentMax_.y, v.y), 0);
  }
  return c;
}

llvm::Expected<Contour> Contour::load(const std::string& path) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  auto lines = splitLines((*buf)->getBuffer());
  size_t line = 0;
  auto c = parse(lines, &line, path);
  if (!c) return c.takeError();
  return c;
}

// ---------------------------------------------------------------------------------------------
// ContourStore

ContourStore::ContourStore() { clear(); }

void ContourStore::clear() {
  contours_.clear();
  contours_.push_back(Contour::defaultCircle());
}

const std::string& ContourStore::nameOf(int id) const {
  static const std::string empty;
  return valid(id) ? contours_[id].name() : empty;
}

llvm::Error ContourStore::loadSetText(std::string_view text, const std::string& fileName) {
  clear();
  auto lines = splitLines(text);
  size_t ln = 0;
  while (ln < lines.size() && blankOrComment(lines[ln])) ++ln;
  std::string_view rest;
  if (ln >= lines.size() || !keyed(lines[ln], "contourgalleryver", &rest))
    return fail(fileName, ln + 1, "not a contour set (expected 'contourgalleryver 1 1')");
  ++ln;
  while (ln < lines.size() && blankOrComment(lines[ln])) ++ln;
  long n = 0;
  auto t = ln < lines.size() && keyed(lines[ln], "items:", &rest) ? tokens(rest) : std::vector<std::string>{};
  if (t.size() != 1 || !toInt(t[0], &n) || n < 1) return fail(fileName, ln + 1, "expected 'items: n' with n >= 1");
  ++ln;
  for (long i = 0; i < n; ++i) {
    auto c = Contour::parse(lines, &ln, fileName);
    if (!c) return c.takeError();
    contours_.push_back(std::move(*c));
  }
  return llvm::Error::success();
}

llvm::Error ContourStore::loadSet(const std::string& path) {
  auto buf = textfile::readFile(path);
  if (!buf) {
    clear();
    return buf.takeError();
  }
  return loadSetText((*buf)->getBuffer(), path);
}

llvm::Error ContourStore::loadContour(const std::string& path) {
  auto c = Contour::load(path);
  if (!c) {
    Contour d = Contour::defaultCircle();  // lpfg keeps the id with its default contour
    contours_.push_back(std::move(d));
    return c.takeError();
  }
  contours_.push_back(std::move(*c));
  return llvm::Error::success();
}

llvm::Error ContourStore::loadFiles(const std::vector<std::string>& paths) {
  clear();
  llvm::Error errors = llvm::Error::success();
  const std::string* set = nullptr;
  for (const auto& p : paths)
    if (endsWith(p, ".cset")) set = &p;
  if (set) errors = llvm::joinErrors(std::move(errors), loadSet(*set));
  for (const auto& p : paths)
    if (endsWith(p, ".con")) errors = llvm::joinErrors(std::move(errors), loadContour(p));
  return errors;
}

}  // namespace lcjit::runtime
