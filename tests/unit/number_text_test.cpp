// runtime/NumberText: %.9g and %.17g as printf writes them, over millions of values of every
// scale — the string's text (-out x.str, -ds, the REPL) depends on it byte for byte.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "runtime/NumberText.h"

using lcjit::runtime::printfG;

namespace {

template <class T> std::string ours(T v, int precision) {
  char buf[40];
  return std::string(buf, printfG(buf, v, precision));
}
template <class T> std::string printfs(T v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, double(v));
  return buf;
}

// By hand, from printf's rules: P significant digits, trailing zeros dropped, exponent form when
// the exponent is below -4 or at least P, two exponent digits at least.
TEST(PrintfG, WorkedExamples) {
  EXPECT_EQ(ours(0.1f, 9), "0.100000001");  // the float nearest 0.1 is 0.100000001490116…
  EXPECT_EQ(ours(1.0f, 9), "1");
  EXPECT_EQ(ours(-2.5f, 9), "-2.5");
  EXPECT_EQ(ours(0.0f, 9), "0");
  EXPECT_EQ(ours(-0.0f, 9), "-0");
  EXPECT_EQ(ours(123456789.0f, 9), "123456792");  // the float nearest 123456789
  EXPECT_EQ(ours(1e9f, 9), "1e+09");
  EXPECT_EQ(ours(0.0001f, 9), "9.99999975e-05");
  EXPECT_EQ(ours(0.00025f, 9), "0.000250000012");
  EXPECT_EQ(ours(0.5, 17), "0.5");
  EXPECT_EQ(ours(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(ours(1e100, 17), "1e+100");  // 1.00000000000000001590…e100: 17 digits, zeros dropped
  EXPECT_EQ(ours(1e-6, 17), "9.9999999999999995e-07");  // 9.99999999999999954748…e-7
  EXPECT_EQ(ours(9.5, 1), "1e+01");  // a tie, 9 odd: up to 10, one digit more, so exponent form
  EXPECT_EQ(ours(8.5, 1), "8");      // a tie, 8 even: stays
  EXPECT_EQ(ours(0.96, 1), "1");     // rounded up into the next decade
  EXPECT_EQ(ours(0.5, 1), "0.5");
  EXPECT_EQ(ours(2.5, 1), "2");  // a tie: to even
  EXPECT_EQ(ours(3.5, 1), "4");
  EXPECT_EQ(ours(std::numeric_limits<float>::infinity(), 9), printfs(std::numeric_limits<float>::infinity(), 9));
}

TEST(PrintfG, FloatsOfEveryScaleAsPrintf) {
  std::mt19937 rng(12345);
  int checked = 0;
  for (int i = 0; i < 3000000; ++i) {
    uint32_t bits = rng();
    float v;
    std::memcpy(&v, &bits, 4);
    if (std::isnan(v)) continue;
    ASSERT_EQ(ours(v, 9), printfs(v, 9)) << "bits " << bits;
    ++checked;
  }
  // Numbers models use: whole numbers, steps of 0.1, halves (ties), powers of ten and their
  // neighbours, subnormals.
  for (int i = -100000; i <= 100000; ++i) {
    for (float v : {float(i), i * 0.1f, i * 0.5f, i * 0.001f, i * 1.5e-5f}) ASSERT_EQ(ours(v, 9), printfs(v, 9)) << v;
  }
  for (int k = -45; k <= 38; ++k) {
    float p = std::pow(10.0f, float(k));
    for (float v : {p, std::nextafter(p, 0.0f), std::nextafter(p, std::numeric_limits<float>::infinity())}) ASSERT_EQ(ours(v, 9), printfs(v, 9)) << v;
  }
  EXPECT_GT(checked, 2900000);
}

TEST(PrintfG, DoublesOfEveryScaleAsPrintf) {
  std::mt19937_64 rng(54321);
  for (int i = 0; i < 2000000; ++i) {
    uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, 8);
    if (std::isnan(v)) continue;
    ASSERT_EQ(ours(v, 17), printfs(v, 17)) << "bits " << bits;
  }
  std::uniform_real_distribution<double> unit(-1000, 1000);
  for (int i = 0; i < 1000000; ++i) {
    double v = unit(rng);
    ASSERT_EQ(ours(v, 17), printfs(v, 17)) << v;
    ASSERT_EQ(ours(float(v), 9), printfs(float(v), 9)) << v;
  }
  for (int k = -320; k <= 308; ++k) {
    double p = std::pow(10.0, k);
    for (double v : {p, std::nextafter(p, 0.0), std::nextafter(p, std::numeric_limits<double>::infinity())}) ASSERT_EQ(ours(v, 17), printfs(v, 17)) << v;
  }
  for (int precision = 1; precision <= 17; ++precision)
    for (double v : {0.125, 2.5, 1234.5, 9.9999999999, 1e-5, 123456789012.0}) ASSERT_EQ(ours(v, precision), printfs(v, precision));
}

}  // namespace
