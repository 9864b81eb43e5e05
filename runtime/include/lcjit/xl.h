// XL's library (GroIMP's de.grogra.rgg.Library, which an XL model has without an import) as the
// C++ that the XL front end's L+C includes (frontend/xl/Translate.cpp), on lpfg's random numbers
// (ran(x): uniform in [0, x)); and Java's text of numbers and its string `+`, for print and
// println to write what Java writes. Model code: header-only, included after <lpfgall.h>.
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

// ---- numbers ----
// random(a, b) uniform in [a, b); irandom(a, b) a whole number from a to b; probability(p) true
// with probability p; normal(mu, sigma) normally distributed (Box and Muller's transform of two
// uniform numbers); R2D and DEG, degrees per radian and radians per degree.
inline float random(float a, float b) { return a + ran(b - a); }
inline int irandom(int a, int b) { return a + (int)ran((float)(b - a + 1)); }
inline bool probability(float p) { return ran(1) < p; }
const double R2D = 180 / M_PI, DEG = M_PI / 180;
inline double normal(double mu, double sigma) {
  double u = 1 - ran(1), v = ran(1);
  return mu + sigma * std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * v);
}

// ---- graph queries ----
// What max and min of no value are (Operators' initial values): a float's −∞ and +∞, an int's
// least and greatest; first and last of none are a float's NaN, an int's 0.
template <class T>
T __xl_least() {
  return std::numeric_limits<T>::has_infinity ? -std::numeric_limits<T>::infinity() : std::numeric_limits<T>::lowest();
}
template <class T>
T __xl_none() {  // first and last of none
  return std::numeric_limits<T>::has_quiet_NaN ? std::numeric_limits<T>::quiet_NaN() : T(0);
}
template <class T>
T __xl_greatest() {
  return std::numeric_limits<T>::has_infinity ? std::numeric_limits<T>::infinity() : std::numeric_limits<T>::max();
}

// ---- derivation modes ----
// GroIMP's derivation modes (de.grogra.xl.impl.base.Graph's constants, Library.setDerivationMode):
// PARALLEL_MODE, every rule where it applies (with EXCLUDE_DELETED_FLAG, GroIMP's default: one
// rule a node, lcjit's engine's way), and SEQUENTIAL_MODE, one rule application a step, the
// first (lcjit_derive_sequentially). The non-deterministic modes choose among applications at
// random, which lcjit's engine cannot yet (a production runs only to apply): they stop the model
// code, at the call, with a message saying so; so does INTERPRETIVE_FLAG.
const int PARALLEL_MODE = 0, PARALLEL_NON_DETERMINISTIC_MODE = 1, SEQUENTIAL_MODE = 2,
          SEQUENTIAL_NON_DETERMINISTIC_MODE = 3, INTERPRETIVE_FLAG = 4, EXCLUDE_DELETED_FLAG = 8;
inline void setDerivationMode(int mode) {
  if ((mode & 3) == PARALLEL_NON_DETERMINISTIC_MODE || (mode & 3) == SEQUENTIAL_NON_DETERMINISTIC_MODE ||
      (mode & INTERPRETIVE_FLAG))
    throw std::invalid_argument("setDerivationMode(" + std::to_string(mode) +
                                "): the non-deterministic modes and INTERPRETIVE_FLAG are not supported yet by lcjit's XL "
                                "(docs/xl.md)");
  lcjit_derive_sequentially((mode & 3) == SEQUENTIAL_MODE);
}

// ---- Java's arrays ----
// `int[] a = new int[n]`, `float[] b = {1, 2}`, `double[][] m = new double[2][3]`: an array is
// shared by every variable it is assigned to, as Java's (a method changes its caller's), holds
// Java's 0 (false) when made with a length, and knows it (`a.length`). An index outside it stops
// the model code with Java's message (the guard reports an uncaught exception); a variable never
// given an array has length 0.
template <class T>
struct __xl_Array {
  using value_type = T;
  std::shared_ptr<T> items;
  int length = 0;
  __xl_Array() = default;
  explicit __xl_Array(long n) : items(new T[n < 0 ? 0 : n](), std::default_delete<T[]>()), length((int)n) {
    if (n < 0) throw std::length_error("NegativeArraySizeException: " + std::to_string(n));
  }
  __xl_Array(std::initializer_list<T> values) : __xl_Array((long)values.size()) {
    long k = 0;
    for (const T& v : values) items.get()[k++] = v;
  }
  T& operator[](long i) const {
    if (i < 0 || i >= length)
      throw std::out_of_range("ArrayIndexOutOfBoundsException: Index " + std::to_string(i) + " out of bounds for length " +
                              std::to_string(length));
    return items.get()[i];
  }
  T* begin() const { return items.get(); }
  T* end() const { return items.get() + length; }
};
// `new T[n][m]…`: an array of n arrays of m …, each its own (A the whole array's type).
template <class A>
A __xl_new(long n) {
  return A(n);
}
template <class A, class... More>
A __xl_new(long n, long m, More... more) {
  A a(n);
  for (auto& row : a) row = __xl_new<typename A::value_type>(m, more...);
  return a;
}

// ---- GroIMP's node transforms ----
// A Null's translation (x, y, z) (Null(x, y, z), setTransform) is in its parent's frame: x along
// GroIMP's left, y its up, z its head, which are lcjit's −L, −U and H (frontend/xl/Turtle.h), L
// being U × H. d gets the move in the world's axes, for MoveRel3f.
inline void __xl_local_move(float x, float y, float z, float d[3]) {
  float h[3], u[3];
  for (int k = 0; k < 3; ++k) {
    h[k] = lcjit_turtle_field(__lc_TurtleHeadingX + k);
    u[k] = lcjit_turtle_field(__lc_TurtleUpX + k);
  }
  const float l[3] = {u[1] * h[2] - u[2] * h[1], u[2] * h[0] - u[0] * h[2], u[0] * h[1] - u[1] * h[0]};
  for (int k = 0; k < 3; ++k) d[k] = -x * l[k] - y * u[k] + z * h[k];
}
// setTransform(x, y, z) on a label of a module extending Null: its translation's fields.
inline void __xl_set_transform(float& tx, float& ty, float& tz, double x, double y, double z) {
  tx = (float)x, ty = (float)y, tz = (float)z;
}

// ---- GroIMP's gravitropism ----
// RV(g) (GRotation.postTransform): the head v turns to w = v − g·up, normalised (up the world's
// vertical, lcjit's +y), by the rotation about v × w that takes v to w; when v is vertical the
// frame turns over if g pulls the other way (v·(v − g·up) < 0), else stays. hu gets the new head
// and up, for SetHead; false: the frame stays.
inline bool __xl_gravitropism(float g, float hu[6]) {
  double v[3], u[3];
  for (int k = 0; k < 3; ++k) {
    v[k] = lcjit_turtle_field(__lc_TurtleHeadingX + k);
    u[k] = lcjit_turtle_field(__lc_TurtleUpX + k);
  }
  const double q = v[0] * v[0] + v[2] * v[2];  // the head's horizontal part
  if (q < 1e-10 || v[1] * v[1] > 0.99999) {
    if (v[1] * (v[1] - g) >= 0) return false;
    for (int k = 0; k < 3; ++k) hu[k] = (float)-v[k], hu[3 + k] = (float)-u[k];
    return true;
  }
  double w[3] = {v[0], v[1] - g, v[2]};
  const double n = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  for (double& c : w) c /= n;
  // Rodrigues: the axis a = v × w / |v × w|, cos and sin of the angle from v to w.
  double a[3] = {v[1] * w[2] - v[2] * w[1], v[2] * w[0] - v[0] * w[2], v[0] * w[1] - v[1] * w[0]};
  const double s = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), c = v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
  if (s < 1e-12) return false;
  for (double& x : a) x /= s;
  const double au = a[0] * u[0] + a[1] * u[1] + a[2] * u[2];
  const double axu[3] = {a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]};
  for (int k = 0; k < 3; ++k) {
    hu[k] = (float)w[k];
    hu[3 + k] = (float)(u[k] * c + axu[k] * s + a[k] * au * (1 - c));
  }
  return true;
}

// ---- Java's Math ----
// As Java has it: the functions of doubles (Math.sqrt of a float is a double), abs, min and max
// of the type they are given (Math.min of two ints is an int), round to the nearest with halves
// up, random uniform in [0, 1).
namespace __xl_Math {
const double PI = M_PI, E = M_E;
// Java's functions of one double and of two, each the C++ one of that name.
#define XL_MATH1(f) \
  inline double f(double x) { return std::f(x); }
#define XL_MATH2(f) \
  inline double f(double x, double y) { return std::f(x, y); }
XL_MATH1(sqrt) XL_MATH1(cbrt) XL_MATH1(exp) XL_MATH1(log) XL_MATH1(log10) XL_MATH1(sin) XL_MATH1(cos)
XL_MATH1(tan) XL_MATH1(asin) XL_MATH1(acos) XL_MATH1(atan) XL_MATH1(sinh) XL_MATH1(cosh) XL_MATH1(tanh)
XL_MATH1(floor) XL_MATH1(ceil)
XL_MATH2(pow) XL_MATH2(atan2) XL_MATH2(hypot)
#undef XL_MATH1
#undef XL_MATH2
inline double toRadians(double x) { return x * (M_PI / 180); }
inline double toDegrees(double x) { return x * (180 / M_PI); }
inline double signum(double x) { return x > 0 ? 1.0 : x < 0 ? -1.0 : x; }
template <class T>
inline T abs(T x) { return x < 0 ? -x : x; }
template <class A, class B>
inline auto min(A a, B b) { return a < b ? a : b; }
template <class A, class B>
inline auto max(A a, B b) { return a > b ? a : b; }
inline int round(float x) { return (int)std::floor(x + 0.5f); }
inline long long round(double x) { return (long long)std::floor(x + 0.5); }
inline double random() { return ran(1); }
}  // namespace __xl_Math

// ---- Java's text of a number ----
// Float.toString and Double.toString: the fewest digits that read back as the same number (9 at
// most for a float, 17 for a double); from 10^-3 up to 10^7 written plainly with at least one
// decimal (2.0, 0.001), else as d.dddE±n (1.0E7, 1.5E-4); NaN, Infinity, -0.0 as Java has them.
inline std::string __xl_javaText(double x, bool single) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Infinity" : "-Infinity";
  if (x == 0) return std::signbit(x) ? "-0.0" : "0.0";
  char buf[48];
  int precision = 1;
  for (; precision < (single ? 9 : 17); ++precision) {
    std::snprintf(buf, sizeof buf, "%.*e", precision - 1, x);
    if (single ? std::strtof(buf, nullptr) == (float)x : std::strtod(buf, nullptr) == x) break;
  }
  std::snprintf(buf, sizeof buf, "%.*e", precision - 1, x);
  // buf is [-]d.ddde±XX: its digits and its exponent.
  std::string text = buf, digits;
  const bool negative = text[0] == '-';
  const size_t e = text.find('e');
  for (size_t i = negative ? 1 : 0; i < e; ++i)
    if (text[i] != '.') digits += text[i];
  const int exponent = std::atoi(text.c_str() + e + 1);
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
  std::string out = negative ? "-" : "";
  const double magnitude = std::fabs(x);
  if (magnitude >= 1e-3 && magnitude < 1e7) {
    if (exponent >= 0) {
      std::string whole = digits.substr(0, digits.size() < size_t(exponent + 1) ? digits.size() : size_t(exponent + 1));
      while (whole.size() < size_t(exponent + 1)) whole += '0';
      std::string fraction = digits.size() > size_t(exponent + 1) ? digits.substr(exponent + 1) : "0";
      out += whole + "." + fraction;
    } else {
      out += "0." + std::string(size_t(-exponent - 1), '0') + digits;
    }
  } else {
    out += digits.substr(0, 1) + "." + (digits.size() > 1 ? digits.substr(1) : "0") + "E" + std::to_string(exponent);
  }
  return out;
}
inline std::string __xl_text(float x) { return __xl_javaText(x, true); }
inline std::string __xl_text(double x) { return __xl_javaText(x, false); }
inline std::string __xl_text(int x) { return std::to_string(x); }
inline std::string __xl_text(long x) { return std::to_string(x); }
inline std::string __xl_text(long long x) { return std::to_string(x); }
inline std::string __xl_text(bool x) { return x ? "true" : "false"; }
inline std::string __xl_text(char x) { return std::string(1, x); }
inline std::string __xl_text(const char* x) { return x; }

// ---- Java's strings ----
// What Java's `+` makes of a string and anything: the translation writes each string literal that
// a `+` touches as __xl_String("…"), so that `"n = " + n` (and `a + b + " leaves"`, the numbers
// added first, as in Java) is text, not a pointer moved.
struct __xl_String {
  std::string s;
  __xl_String(const char* text) : s(text) {}
  explicit __xl_String(std::string text) : s(std::move(text)) {}
};
inline __xl_String operator+(const __xl_String& a, const __xl_String& b) { return __xl_String(a.s + b.s); }
template <class T>
inline __xl_String operator+(const __xl_String& a, T b) { return __xl_String(a.s + __xl_text(b)); }
template <class T>
inline __xl_String operator+(T a, const __xl_String& b) { return __xl_String(__xl_text(a) + b.s); }
inline std::string __xl_text(const __xl_String& x) { return x.s; }

// ---- print, println ----
// Java's text of a number, a truth value or a string, to the standard output.
template <class T>
inline void print(const T& x) { std::fputs(__xl_text(x).c_str(), stdout); }
template <class T>
inline void println(const T& x) { std::printf("%s\n", __xl_text(x).c_str()); }
inline void println() { std::printf("\n"); }

// ---- datasets and charts ----
// GroIMP's datasets (Library.dataset(name): a table of rows, each row's cells set by column,
// de.grogra.pf.data's DatasetRef and Dataseries): lcjit keeps each in the model and writes it,
// whenever it changes, to NAME.csv in the folder lcjit runs in: the column keys, if any are set,
// then a line a row, each cell as Java writes its number (a cell never set is empty). GroIMP
// draws a dataset in a chart panel (chart(dataset, XY_PLOT)); lcjit does not draw charts yet:
// chart() says once, on the standard error, where the dataset's table is.
struct __xl_Dataset;
struct __xl_Dataseries {
  __xl_Dataset* dataset;
  size_t row;
  template <class T>
  __xl_Dataseries& set(int column, T value);
  template <class T>
  __xl_Dataseries& add(T value);
};
struct __xl_Dataset {
  std::string name;
  std::vector<std::string> keys;
  std::vector<std::vector<std::string>> rows;
  void save() const {
    if (FILE* f = std::fopen((name + ".csv").c_str(), "w")) {
      auto line = [f](const std::vector<std::string>& cells) {
        for (size_t k = 0; k < cells.size(); ++k) std::fprintf(f, "%s%s", k ? "," : "", cells[k].c_str());
        std::fputc('\n', f);
      };
      if (!keys.empty()) line(keys);
      for (const auto& r : rows) line(r);
      std::fclose(f);
    }
  }
  __xl_Dataset& clear() {
    rows.clear();
    save();
    return *this;
  }
  __xl_Dataseries addRow() {
    rows.emplace_back();
    save();
    return {this, rows.size() - 1};
  }
  __xl_Dataset& setColumnKey(int column, const __xl_String& key) {
    if (column >= 0) {
      if (keys.size() <= (size_t)column) keys.resize(column + 1);
      keys[column] = key.s;
      save();
    }
    return *this;
  }
  __xl_Dataset& setTitle(const __xl_String&) { return *this; }
};
template <class T>
__xl_Dataseries& __xl_Dataseries::set(int column, T value) {
  if (column < 0) throw std::out_of_range("dataset " + dataset->name + ": column " + std::to_string(column));
  std::vector<std::string>& cells = dataset->rows[row];
  if (cells.size() <= (size_t)column) cells.resize(column + 1);
  cells[column] = __xl_text(value);
  dataset->save();
  return *this;
}
template <class T>
__xl_Dataseries& __xl_Dataseries::add(T value) {
  return set((int)dataset->rows[row].size(), value);
}
inline __xl_Dataset& dataset(const __xl_String& name) {
  static std::map<std::string, __xl_Dataset> all;
  __xl_Dataset& d = all[name.s];
  d.name = name.s;
  return d;
}
// ChartPanel's kinds of chart.
const int AREA_PLOT = 0, STACKED_AREA_PLOT = 1, BAR_PLOT = 2, STACKED_BAR_PLOT = 3, LINE_PLOT = 4, PIE_PLOT = 5,
          SCATTER_PLOT = 6, XY_PLOT = 7, STATISTICAL_BAR_PLOT = 9;
inline void chart(__xl_Dataset& d, int) {
  static std::set<std::string> told;
  if (told.insert(d.name).second)
    std::fprintf(stderr, "lcjit: charts are not drawn yet; dataset %s is written to %s.csv\n", d.name.c_str(),
                 d.name.c_str());
}
