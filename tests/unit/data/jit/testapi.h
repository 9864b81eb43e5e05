// Stand-in for the model API header (lpfgall.h) in jit_test: std headers + templates, so the
// PCH path is exercised the same way as with the real runtime header.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int lcjit_test_host_add(int a, int b); // provided by the test binary as a host symbol
extern "C" void lcjit_test_host_note(int what);   // ditto; records calls

namespace testapi {

inline int twice(int x) { return 2 * x; }

// Inline code that uses std::string and instantiates a template: at -O0 it comes from the
// PCH's support object.
inline std::string label(int n) { return "n=" + std::to_string(n); }

template <class T>
T sum(const std::vector<T>& v) {
  T s{};
  for (const T& x : v)
    s += x;
  return s;
}

inline double sumOfThree() { return sum(std::vector<double>{1.5, 2.5, 3}); }

struct Turtle {
  double x = 0, y = 0, heading = 90;
  void forward(double d) {
    x += d * std::cos(heading * 3.14159265358979 / 180);
    y += d * std::sin(heading * 3.14159265358979 / 180);
  }
  void turn(double a) { heading += a; }
};

} // namespace testapi
