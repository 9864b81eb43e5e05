// The functions and random draws compiled designs call (lcjit/cfdg.h): rand(), randint() and the
// rand:: distributions, CF::Time, the colour conversions, and Context Free's one- and two-argument
// functions, with its own constants for degrees.
#include <cmath>
#include <cstdint>
#include <limits>

#include "runtime/cfdg/Distributions.h"
#include "runtime/cfdg/Expander.h"

using namespace lcjit::runtime::cfdg;

extern "C" {

double __cf_rand(__cf_Ctx* c, double a, double b) { return drawDouble(c->cur) * std::fabs(b - a) + std::fmin(a, b); }
double __cf_randpm(__cf_Ctx* c, double a, double b) { return (2.0 * drawDouble(c->cur) - 1.0) * b + a; }
double __cf_randint(__cf_Ctx* c, double a, double b) {
  return std::floor(drawDouble(c->cur) * std::fabs(b - a) + std::fmin(a, b));
}
double __cf_pow(double a, double b) { return std::pow(a, b); }
double __cf_distribution(__cf_Ctx* c, int kind, int count, const double* args) {
  return distribution(c->cur, kind, count, args);
}
double __cf_time(__cf_Ctx* c, int which) { return c->time[which != 0]; }

void __cf_colour(int toRgb, const double* in, double* out) {
  if (toRgb) {
    const double hsba[4] = {in[0], in[1], in[2], 1.0};
    double rgba[4];
    rgbOf(hsba, rgba);
    out[0] = rgba[0], out[1] = rgba[1], out[2] = rgba[2];
    return;
  }
  // Value is the largest channel, saturation its share the smallest lacks, hue by the largest
  // (none below 1e-5 of difference).
  const double r = in[0], g = in[1], b = in[2];
  const double lo = r < (g < b ? g : b) ? r : (g < b ? g : b);
  const double hi = r > (g > b ? g : b) ? r : (g > b ? g : b);
  const double delta = hi - lo;
  out[2] = hi;
  if (delta < 0.00001) {
    out[0] = out[1] = 0.0;
    return;
  }
  out[1] = delta / hi;
  double h = r == hi ? (g - b) / delta : g == hi ? 2 + (b - r) / delta : 4 + (r - g) / delta;
  h *= 60;
  out[0] = h < 0.0 ? std::fmod(h + 360.0, 360.0) : std::fmod(h, 360.0);
}


double __cf_fn1(__cf_Ctx*, int fn, double a) {
  switch (fn) {
    case __cf_Cos: return std::cos(a * 0.0174532925199);
    case __cf_Sin: return std::sin(a * 0.0174532925199);
    case __cf_Tan: return std::tan(a * 0.0174532925199);
    case __cf_Cot: return 1.0 / std::tan(a * 0.0174532925199);
    case __cf_Acos: return std::acos(a) * 57.29577951308;
    case __cf_Asin: return std::asin(a) * 57.29577951308;
    case __cf_Atan: return std::atan(a) * 57.29577951308;
    case __cf_Acot: return std::atan(1.0 / a) * 57.29577951308;
    case __cf_Cosh: return std::cosh(a);
    case __cf_Sinh: return std::sinh(a);
    case __cf_Tanh: return std::tanh(a);
    case __cf_Acosh: return std::acosh(a);
    case __cf_Asinh: return std::asinh(a);
    case __cf_Atanh: return std::atanh(a);
    case __cf_Log: return std::log(a);
    case __cf_Log10: return std::log10(a);
    case __cf_Sqrt: return std::sqrt(a);
    case __cf_Exp: return std::exp(a);
    case __cf_Abs: return std::fabs(a);
    case __cf_Floor: return std::floor(a);
    case __cf_Ceiling: return std::ceil(a);
    case __cf_Infinity: return a < 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    case __cf_Factorial: {
      double r = 1;
      for (int i = 2; i <= int(a); ++i) r *= i;
      return r;
    }
    case __cf_Sg: return a == 0.0 ? 0.0 : 1.0;
    case __cf_BitNot: return double(~uint64_t(a) & 0xFFFFFFFFFFFFFull);
  }
  return 0;
}

double __cf_fn2(__cf_Ctx*, int fn, double a, double b) {
  switch (fn) {
    case __cf_Atan2: return std::atan2(a, b) * 57.29577951308;
    case __cf_Mod: return std::fmod(a, b);
    case __cf_Divides: return uint64_t(b) != 0 && uint64_t(a) % uint64_t(b) == 0 ? 1.0 : 0.0;
    case __cf_Div: return uint64_t(b) != 0 ? double(uint64_t(a) / uint64_t(b)) : 0.0;
    case __cf_Abs2: return std::fabs(a - b);
    case __cf_IsNatural: return a >= 0 && a <= b && a == std::floor(a) ? 1.0 : 0.0;  // b: CF::MaxNatural
    case __cf_BitOr: return double((uint64_t(a) | uint64_t(b)) & 0xFFFFFFFFFFFFFull);
    case __cf_BitAnd: return double((uint64_t(a) & uint64_t(b)) & 0xFFFFFFFFFFFFFull);
    case __cf_BitXor: return double((uint64_t(a) ^ uint64_t(b)) & 0xFFFFFFFFFFFFFull);
    case __cf_BitLeft: return double((uint64_t(a) << uint64_t(b)) & 0xFFFFFFFFFFFFFull);
    case __cf_BitRight: return double((uint64_t(a) >> uint64_t(b)) & 0xFFFFFFFFFFFFFull);
    case __cf_Min: return b < a ? b : a;
    case __cf_Max: return b > a ? b : a;
  }
  return 0;
}

}  // extern "C"
