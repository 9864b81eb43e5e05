// B-spline surfaces: see BSplineSurfaces.h. The formulas and their order of evaluation are lpfg's
// (facts read from its source); the code is lcjit's.
#include "runtime/files/BSplineSurfaces.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include <llvm/Support/MemoryBuffer.h>

#include "support/InputFile.h"

namespace lcjit::runtime {
namespace {

using P = BSplinePoint;

constexpr int kDegree = 3;
constexpr int kMinCoarse = 10;  // lpfg's MIN_HEIGHT / MIN_WIDTH
constexpr double kInitialOffset = 0.000001;  // lpfg's err_tol in the initial net
constexpr size_t kMaxPoints = size_t(1) << 24;

// lpfg's weighted sums of points, left to right.
P lin(const P& a, double ca, const P& b, double cb) { return a * ca + b * cb; }
P lin(const P& a, double ca, const P& b, double cb, const P& c, double cc) { return lin(a, ca, b, cb) + c * cc; }

// A weighted sum Σ w_k·line[at(k)], left to right.
template <class At> P weighted(const std::vector<P>& line, const double* w, int n, At at) {
  P s = line[size_t(at(0))] * w[0];
  for (int k = 1; k < n; ++k) s = s + line[size_t(at(k))] * w[k];
  return s;
}

// One line of control points refined (lpfg's DoubleU when `rowsRule`, DoubleV otherwise; they
// differ only in how the ends of short lines are indexed). Needs at least 4 points.
std::vector<P> refineLine(const std::vector<P>& p, bool rowsRule) {
  const int last = int(p.size()) - 1;
  const double h = 1.0 / 2.0, q1 = 1.0 / 4.0, q3 = 3.0 / 4.0, s3 = 3.0 / 16.0, s11 = 11.0 / 16.0, e = 1.0 / 8.0;
  std::vector<P> o;
  o.reserve(2 * p.size() + 4);
  o.push_back(p[0]);
  o.push_back(lin(p[0], h, p[1], h));
  o.push_back(lin(p[1], q3, p[2], q1));
  o.push_back(lin(p[1], s3, p[2], s11, p[3], e));
  if (rowsRule) {
    for (int i = 2; i < last - 3; ++i) {
      o.push_back(lin(p[i], h, p[i + 1], h));
      o.push_back(lin(p[i], e, p[i + 1], q3, p[i + 2], e));
    }
    o.push_back(lin(p[last - 2], h, p[last - 3], h));
  } else {
    o.push_back(lin(p[2], h, p[3], h));
    for (int i = 3; i < last - 2; ++i) {
      o.push_back(lin(p[i - 1], e, p[i], q3, p[i + 1], e));
      o.push_back(lin(p[i], h, p[i + 1], h));
    }
  }
  o.push_back(lin(p[last - 1], s3, p[last - 2], s11, p[last - 3], e));
  o.push_back(lin(p[last - 2], q1, p[last - 1], q3));
  o.push_back(lin(p[last], h, p[last - 1], h));
  o.push_back(p[last]);
  return o;
}

// One line coarsened by lpfg's reverse subdivision: n points become (n+3)/2 (n >= 17).
std::vector<P> coarsenLine(const std::vector<P>& f) {
  const int m = (int(f.size()) + 3) / 2, last = m - 1, fl = int(f.size()) - 1;
  static const double w1[5] = {-49.0 / 139.0, 98.0 / 139.0, 135.0 / 139.0, -60.0 / 139.0, 15.0 / 139.0};
  static const double w2[7] = {9.0 / 50.0, -9.0 / 25.0, -2.0 / 25.0, 32.0 / 25.0, 43.0 / 100.0, -3.0 / 5.0, 3.0 / 20.0};
  static const double band[7] = {23.0 / 196.0, -23.0 / 49.0, 9.0 / 28.0, 52.0 / 49.0, 9.0 / 28.0, -23.0 / 49.0, 23.0 / 196.0};
  std::vector<P> c(static_cast<size_t>(m));
  auto up = [](int k) { return k; };
  c[0] = f[0];
  c[1] = weighted(f, w1, 5, up);
  c[2] = weighted(f, w2, 7, up);
  for (int k = 3; k <= last - 3; ++k) {
    int b = (k - 3) * 2 + 2;
    c[size_t(k)] = weighted(f, band, 7, [b](int i) { return b + i; });
  }
  auto down = [fl](int k) { return fl - k; };
  c[size_t(last - 2)] = weighted(f, w2, 7, down);
  c[size_t(last - 1)] = weighted(f, w1, 5, down);
  c[size_t(last)] = f[size_t(fl)];
  return c;
}

// lpfg's cubic B-spline along one index: `get(k)` gives control point k of n, t in [3, n].
// The four points below the span are picked with lpfg's clamping (at t = n all four are the
// last point), then de Boor's triangle runs with lpfg's knot rules; the entries of each level
// that the next never reads are not computed.
template <class Get> P deBoor(Get get, int n, double t) {
  const int span = int(t);
  P p[4];
  int i = 0;
  for (; i <= kDegree && span - i <= 0; ++i) p[i] = get(0);
  for (; i <= kDegree && span - i < n; ++i) p[i] = get(span - i);
  for (; i <= kDegree; ++i) p[i] = get(n - 1);
  for (int level = kDegree + 1; level >= 2; --level) {
    double knot = span;
    for (int j = 0; j < level - 1; ++j, knot -= 1) {
      double w;
      if (level - 1 + knot >= n)
        w = (n - knot > 0 && t - knot > 0) ? (t - knot) / (n - knot) : 0;
      else if (level - 1 + knot - kDegree <= 0 || t - kDegree <= 0)
        w = 0;
      else if (knot < kDegree)
        w = (t - kDegree) / (level - 1 + knot - kDegree);
      else
        w = (t - knot) / (level - 1);
      p[j] = lin(p[j], w, p[j + 1], 1 - w);
    }
  }
  return p[0];
}

double clampParameter(double t, int n) {
  if (t > n) t = n;
  if (t < kDegree) t = kDegree;
  return t;
}

// istream-like extraction (what lpfg's `File >> x` does): blanks skipped; a word that is not a
// number stores 0 and stops the reading; the end of the text stops it and stores nothing.
class Extractor {
 public:
  explicit Extractor(std::string_view text) : s_(text) {}
  template <class T> void operator>>(T& out) {
    if (failed_) return;
    while (pos_ < s_.size() && std::isspace((unsigned char)s_[pos_])) ++pos_;
    if (pos_ >= s_.size()) {
      failed_ = true;
      return;
    }
    size_t start = pos_, k = pos_;
    if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
    size_t digits = 0;
    while (k < s_.size() && std::isdigit((unsigned char)s_[k])) ++k, ++digits;
    if constexpr (std::is_floating_point_v<T>) {
      if (k < s_.size() && s_[k] == '.') {
        ++k;
        while (k < s_.size() && std::isdigit((unsigned char)s_[k])) ++k, ++digits;
      }
      if (digits && k < s_.size() && (s_[k] == 'e' || s_[k] == 'E')) {
        size_t x = k + 1;
        if (x < s_.size() && (s_[x] == '+' || s_[x] == '-')) ++x;
        size_t expDigits = 0;
        while (x < s_.size() && std::isdigit((unsigned char)s_[x])) ++x, ++expDigits;
        k = expDigits ? x : k;
      }
    }
    if (!digits) {
      out = 0;
      failed_ = true;
      return;
    }
    std::string word(s_.substr(start, k - start));
    if constexpr (std::is_floating_point_v<T>)
      out = std::strtod(word.c_str(), nullptr);
    else
      out = (T)std::strtol(word.c_str(), nullptr, 10);
    pos_ = k;
  }
  bool failed() const { return failed_; }

 private:
  std::string_view s_;
  size_t pos_ = 0;
  bool failed_ = false;
};

}  // namespace

BSplineNet::BSplineNet(int rows, int columns) {
  if (rows <= 0 || columns <= 0 || size_t(rows) * size_t(columns) > kMaxPoints) return;
  rows_ = rows;
  columns_ = columns;
  points_.resize(size_t(rows) * size_t(columns));
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j)
      at(i, j) = {(float)i / rows - 0.5 + kInitialOffset, (float)j / columns - 0.5 + kInitialOffset, 0};
}

void BSplineNet::mapLines(bool downRows, const std::function<std::vector<P>(const std::vector<P>&)>& f) {
  const int lines = downRows ? columns_ : rows_, length = downRows ? rows_ : columns_;
  std::vector<std::vector<P>> out(static_cast<size_t>(lines));
  std::vector<P> line(static_cast<size_t>(length));
  for (int k = 0; k < lines; ++k) {
    for (int m = 0; m < length; ++m) line[size_t(m)] = downRows ? at(m, k) : at(k, m);
    out[size_t(k)] = f(line);
  }
  const int newLength = out.empty() ? 0 : int(out[0].size());
  (downRows ? rows_ : columns_) = newLength;
  points_.assign(size_t(lines) * size_t(newLength), P{});
  for (int k = 0; k < lines; ++k)
    for (int m = 0; m < newLength; ++m) (downRows ? at(m, k) : at(k, m)) = out[size_t(k)][size_t(m)];
}

bool BSplineNet::refineRows() {
  if (rows_ < 4 || columns_ <= 0) return false;
  mapLines(true, [](const std::vector<P>& l) { return refineLine(l, true); });
  return true;
}

bool BSplineNet::refineColumns() {
  if (columns_ < 4 || rows_ <= 0) return false;
  mapLines(false, [](const std::vector<P>& l) { return refineLine(l, false); });
  return true;
}

bool BSplineNet::coarsenRows() {
  if ((rows_ + 3) / 2 < kMinCoarse || columns_ <= 0) return false;
  mapLines(true, coarsenLine);
  return true;
}

bool BSplineNet::coarsenColumns() {
  if ((columns_ + 3) / 2 < kMinCoarse || rows_ <= 0) return false;
  mapLines(false, coarsenLine);
  return true;
}

void BSplineNet::resize(int rows, int columns, bool* stuck) {
  if (stuck) *stuck = false;
  auto refuse = [&] {
    if (stuck) *stuck = true;
  };
  while (rows < rows_ && rows >= kMinCoarse)
    if (!coarsenRows()) {
      refuse();
      break;
    }
  while (columns < columns_ && columns >= kMinCoarse)
    if (!coarsenColumns()) {
      refuse();
      break;
    }
  while (rows >= 2 * rows_ - 3)
    if (!refineRows()) break;
  while (columns >= 2 * columns_ - 3)
    if (!refineColumns()) break;
}

BSplineNet BSplineNet::add(const BSplineNet& l, const BSplineNet& r) {
  BSplineNet a = l, b = r;
  while (a.rows_ < b.rows_ && a.refineRows()) {
  }
  while (b.rows_ < a.rows_ && b.refineRows()) {
  }
  while (a.columns_ < b.columns_ && a.refineColumns()) {
  }
  while (b.columns_ < a.columns_ && b.refineColumns()) {
  }
  BSplineNet s = a;
  for (int i = 0; i < a.rows_; ++i)
    for (int j = 0; j < a.columns_; ++j)
      s.at(i, j) = i < b.rows_ && j < b.columns_ ? a.at(i, j) + b.at(i, j) : a.at(i, j);
  return s;
}

BSplineNet BSplineNet::scaled(double c) const {
  BSplineNet s = *this;
  for (P& p : s.points_) p = p * c;
  return s;
}

BSplineNet BSplineNet::interpolate(const BSplineNet& l, const BSplineNet& r, double alpha, int rows, int columns) {
  BSplineNet a = l, b = r;
  a.resize(rows, columns);
  b.resize(rows, columns);
  return add(a.scaled(1 - alpha), b.scaled(alpha));
}

BSplinePoint BSplineNet::point(double u, double v) const {
  if (empty()) return {};
  u = clampParameter(u, rows_);
  v = clampParameter(v, columns_);
  auto column = [&](int j) { return deBoor([&](int i) { return at(i, j); }, rows_, u); };
  return deBoor(column, columns_, v);
}

BSplinePoint BSplineNet::normal(double u, double v) const {
  if (empty()) return {};
  u = clampParameter(u, rows_);
  v = clampParameter(v, columns_);
  return normalAt(u, v, point(u, v));
}

BSplinePoint BSplineNet::normalAt(double u, double v, const BSplinePoint& at) const {
  const double d = 0.05, inv = 1.0 / 0.05;
  P du = (u > 5.0 ? at - point(u - d, v) : point(u + d, v) - at) * inv;
  P dv = (v > 5.0 ? at - point(u, v - d) : point(u, v + d) - at) * inv;
  du = du * (1 / du.Length());
  dv = dv * (1 / dv.Length());
  P n = du % dv;
  float l = (float)n.Length();
  n = n * double(1 / l);
  // (NaN where a difference vanishes, as in lpfg)
  return n;
}

BSplineNet::Grid BSplineNet::sample(int uDiv, int vDiv) const {
  Grid g;
  if (empty() || uDiv <= 0 || vDiv <= 0) return g;
  g.uDiv = uDiv;
  g.vDiv = vDiv;
  const double du = 1.0 / uDiv * (rows_ - kDegree), dv = 1.0 / vDiv * (columns_ - kDegree);
  for (int i = 0; i <= uDiv; ++i) {
    const double u = 3.0 + i * du;
    for (int j = 0; j <= vDiv; ++j) {
      const double v = 3.0 + j * dv;
      const BSplinePoint p = point(u, v);
      g.positions.push_back(p);
      g.normals.push_back(normalAt(clampParameter(u, rows_), clampParameter(v, columns_), p));
    }
  }
  return g;
}

PatchGrid BSplineNet::mesh(const Grid& g, int uTex, int vTex) {
  PatchGrid m;
  if (g.positions.empty()) return m;
  m.uDiv = g.uDiv;
  m.vDiv = g.vDiv;
  auto f = [](const P& p) { return V3f(p); };
  for (int i = 0; i <= g.uDiv; ++i)
    for (int j = 0; j <= g.vDiv; ++j) {
      size_t k = m.at(i, j);
      m.positions.push_back(f(g.positions[k]));
      m.normals.push_back(f(g.normals[k]));
      m.uvs.push_back(V2f(float(1.0 * i / uTex), float(1.0 * j / vTex)));
    }
  for (int i = 0; i < g.uDiv; ++i)
    for (int j = 0; j < g.vDiv; ++j) {
      const uint32_t a = uint32_t(m.at(i, j)), b = uint32_t(m.at(i + 1, j)), c = uint32_t(m.at(i + 1, j + 1)),
                     d = uint32_t(m.at(i, j + 1));
      // lpfg: the diagonal (i,j+1)-(i+1,j) when those ends' normals agree more than the other pair's.
      if (g.normals[d] * g.normals[b] > g.normals[c] * g.normals[a])
        m.indices.insert(m.indices.end(), {d, a, b, d, b, c});
      else
        m.indices.insert(m.indices.end(), {d, a, c, a, b, c});
    }
  return m;
}

BSplineNet bsplineFromRecord(const float* points, int maxRows, int maxColumns, int rows, int columns) {
  rows = std::min(rows, maxRows);
  columns = std::min(columns, maxColumns);
  BSplineNet net(rows, columns);
  for (int i = 0; i < net.rows(); ++i)
    for (int j = 0; j < net.columns(); ++j) {
      const float* p = points + 3 * (size_t(i) * size_t(maxColumns) + size_t(j));
      net.at(i, j) = {p[0], p[1], p[2]};
    }
  return net;
}

bool bsplineToRecord(BSplineNet net, int maxRows, int maxColumns, float* points, int* rows, int* columns) {
  bool stuck = false;
  int n = std::min(maxRows, net.rows()), m = std::min(maxColumns, net.columns());
  if (n != net.rows() || m != net.columns()) net.resize(n, m, &stuck);
  n = std::min(maxRows, net.rows());
  m = std::min(maxColumns, net.columns());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      float* p = points + 3 * (size_t(i) * size_t(maxColumns) + size_t(j));
      const BSplinePoint& q = net.at(i, j);
      p[0] = static_cast<float>(q.x);
      p[1] = static_cast<float>(q.y);
      p[2] = static_cast<float>(q.z);
    }
  *rows = n;
  *columns = m;
  return !stuck && n == net.rows() && m == net.columns();
}

BSplineFile parseBSpline(std::string_view text, const std::string& name, std::vector<std::string>& warnings) {
  Extractor in(text);
  int rows = 10, columns = 10, degree = 3;  // lpfg keeps what it had where reading fails
  in >> rows;
  in >> columns;
  in >> degree;
  BSplineFile f;
  f.degree = degree;
  if (degree != 3) warnings.push_back(name + ": warning: not a cubic patch (degree " + std::to_string(degree) + "); read as one, as lpfg does");
  if (rows <= 0 || columns <= 0 || size_t(rows) * size_t(columns) > kMaxPoints) {
    warnings.push_back(name + ": warning: " + std::to_string(rows) + " x " + std::to_string(columns) +
                       " control points: not a surface");
    return f;
  }
  f.net = BSplineNet(rows, columns);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) {
      P& p = f.net.at(i, j);
      in >> p.x;
      in >> p.y;
      in >> p.z;
    }
  if (in.failed())
    warnings.push_back(name + ": warning: fewer than " + std::to_string(rows * columns) +
                       " control points; the others keep lpfg's initial values");
  return f;
}

BSplineFile loadBSpline(const std::string& path, std::vector<std::string>& warnings) {
  auto buf = support::readInputFile(path);
  if (!buf) {
    warnings.push_back(path + ": warning: cannot open file: " + buf.getError().message() +
                       "; lpfg's initial flat 10 x 10 net is used instead");
    BSplineFile f;
    f.net = BSplineNet(10, 10);
    return f;
  }
  return parseBSpline((*buf)->getBuffer(), path, warnings);
}

}  // namespace lcjit::runtime
