// printf's %.*g without printf (see NumberText.h).
#include "runtime/NumberText.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace lcjit::runtime {

namespace {

using u128 = unsigned __int128;

// 10^n for n <= 38 (10^38 < 2^128).
struct Powers {
  u128 of10[39];
  constexpr Powers() : of10() {
    of10[0] = 1;
    for (int i = 1; i < 39; ++i) of10[i] = of10[i - 1] * 10;
  }
};
constexpr Powers kPowers;
u128 pow10(int n) { return kPowers.of10[n]; }

constexpr char kTwoDigits[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// 10^n as doubles, n from -kDoublePowersBelow to 308, where X's estimate is checked; made at
// compile time by repeated multiplication, so a few ulps off, which only costs the exact check
// below a second try.
constexpr int kDoublePowersBelow = 323;
struct DoublePowers {
  double of10[323 + 309];
  constexpr DoublePowers() : of10() {
    of10[kDoublePowersBelow] = 1;
    for (int n = 1; n <= 308; ++n) of10[kDoublePowersBelow + n] = of10[kDoublePowersBelow + n - 1] * 10;
    for (int n = 1; n <= kDoublePowersBelow; ++n) of10[kDoublePowersBelow - n] = of10[kDoublePowersBelow - n + 1] / 10;
  }
};
constexpr DoublePowers kDoublePowersTable;
constexpr const double* kDoublePowers = kDoublePowersTable.of10;

// a * 2^n, false if it does not fit.
bool shifted(u128 a, int n, u128& out) {
  if (n >= 128 || (n > 0 && (a >> (127 - n)) != 0)) return false;
  out = a << n;
  return true;
}

// m * 2^e * 10^p as its whole part `out` and whether rounding it (ties to even: printf rounds the
// exact binary value) goes up, when every intermediate fits in 128 bits.
bool scaled(uint64_t m, int e, int p, u128& out, bool& up) {
  if (p > 38 || p < -38) return false;
  u128 num = m, den = 1;
  if (p >= 0 && p <= 19) num = u128(m) * uint64_t(pow10(p));  // m < 2^53, 10^19 < 2^64: fits
  else if (p > 19 && __builtin_mul_overflow(num, pow10(p), &num)) return false;
  if (p < 0) den = pow10(-p);
  if (e >= 0 && !shifted(num, e, num)) return false;
  if (e < 0 && p >= 0) {  // the usual case: a division by 2^-e, as a shift
    const int s = -e;
    if (s >= 128) return false;
    const u128 q = num >> s, r = num - (q << s), half = u128(1) << (s - 1);
    out = q;
    up = r > half || (r == half && (q & 1));
    return true;
  }
  if (e < 0 && !shifted(den, -e, den)) return false;
  u128 q = num / den, r = num % den;
  // r compared with den / 2 without overflowing: 2r > den, or == with q odd, rounds up.
  out = q;
  up = r > den - r || (r == den - r && (q & 1));
  return true;
}

template <class T> char* fallback(char* out, T v, int precision) {
  return std::to_chars(out, out + 32, v, std::chars_format::general, precision).ptr;
}

// m·2^e (m > 0) as %.Pg; nullptr where the exact digits do not fit in 128 bits.
char* formatExact(char* out, bool negative, uint64_t m, int e, int log2, double approx, int P) {
  // The decimal exponent X of the value is floor(log10(v)): v·10^(P-1-X) has P digits before the
  // point. Estimated from the binary exponent (floor(log2(v)) · log10(2), then one more where v
  // reaches the next power of ten), it may be one off right at a power of ten: fixed by the
  // exact digits. Then the rounding, which may carry into one digit more (9.99999999996 -> 10).
  int X = (log2 * 78913) >> 18;  // floor(log2 · log10(2)) for |log2| < 1700 (>> floors)
  if (X + 1 >= -kDoublePowersBelow && X + 1 <= 308 && approx >= kDoublePowers[X + 1 + kDoublePowersBelow]) ++X;
  const u128 low = pow10(P - 1), high = pow10(P);
  u128 digits = 0;
  bool up = false;
  for (int tries = 0;; ++tries) {
    if (tries == 3 || !scaled(m, e, P - 1 - X, digits, up)) return nullptr;
    if (digits >= high) ++X;
    else if (digits < low) --X;
    else break;
  }
  if (up && ++digits == high) digits = low, ++X;
  char d[20];
  uint64_t t = uint64_t(digits);  // < 10^17
  int i = P;
  for (; i >= 2; t /= 100) std::memcpy(d + (i -= 2), kTwoDigits + 2 * (t % 100), 2);
  if (i == 1) d[0] = char('0' + t);
  int n = P;
  while (n > 1 && d[n - 1] == '0') --n;  // %g drops the trailing zeros
  char* o = out;
  if (negative) *o++ = '-';
  if (X < -4 || X >= P) {
    *o++ = d[0];
    if (n > 1) {
      *o++ = '.';
      std::memcpy(o, d + 1, n - 1);
      o += n - 1;
    }
    *o++ = 'e';
    *o++ = X < 0 ? '-' : '+';
    int a = X < 0 ? -X : X;
    if (a >= 100) *o++ = char('0' + a / 100);
    *o++ = char('0' + a / 10 % 10);
    *o++ = char('0' + a % 10);
  } else if (X >= 0) {
    for (int i = 0; i <= X; ++i) *o++ = i < n ? d[i] : '0';
    if (n > X + 1) {
      *o++ = '.';
      std::memcpy(o, d + X + 1, n - X - 1);
      o += n - X - 1;
    }
  } else {
    *o++ = '0';
    *o++ = '.';
    for (int i = 0; i < -X - 1; ++i) *o++ = '0';
    std::memcpy(o, d, n);
    o += n;
  }
  return o;
}

// A finite, normal, non-zero v as m·2^e (its bits: the stored mantissa with the leading 1), then
// as above.
template <class T> char* format(char* out, T v, int precision) {
  if (v == 0 && precision >= 1) {
    if (std::signbit(v)) *out++ = '-';
    *out++ = '0';
    return out;
  }
  if (!std::isfinite(v) || std::fpclassify(v) == FP_SUBNORMAL || precision < 1 || precision > 17)
    return fallback(out, v, precision);
  constexpr int digits = std::numeric_limits<T>::digits;  // 24, 53: the mantissa with its leading 1
  using Bits = std::conditional_t<sizeof(T) == 8, uint64_t, uint32_t>;
  Bits bits;
  std::memcpy(&bits, &v, sizeof v);
  constexpr int stored = digits - 1, bias = std::numeric_limits<T>::max_exponent - 1 + stored;
  const int biased = int((bits >> stored) & ((Bits(1) << (sizeof(T) * 8 - 1 - stored)) - 1));
  const uint64_t m = (uint64_t(bits) & ((uint64_t(1) << stored) - 1)) | (uint64_t(1) << stored);
  const int e = biased - bias;  // v = m·2^e, m with its leading 1 at bit `stored`
  char* end = formatExact(out, v < 0, m, e, e + stored, std::fabs(double(v)), precision);
  return end ? end : fallback(out, v, precision);
}

}  // namespace

char* printfG(char* out, double v, int precision) { return format(out, v, precision); }
char* printfG(char* out, float v, int precision) { return format(out, v, precision); }

}  // namespace lcjit::runtime
