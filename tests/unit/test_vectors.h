// Shared by the unit tests: comparing V3f values with a tolerance, with a readable failure.
#pragma once
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/include/lcjit/vectors.h"

inline testing::AssertionResult Near3(V3f v, float x, float y, float z, float tol) {
  if (std::fabs(v.x - x) <= tol && std::fabs(v.y - y) <= tol && std::fabs(v.z - z) <= tol)
    return testing::AssertionSuccess();
  return testing::AssertionFailure() << "(" << v.x << ", " << v.y << ", " << v.z << ") is not within " << tol
                                     << " of (" << x << ", " << y << ", " << z << ")";
}
#define EXPECT_V3_NEAR(v, X, Y, Z, tol) EXPECT_TRUE(Near3((v), float(X), float(Y), float(Z), float(tol)))

// Exact equality for EXPECT_EQ (model code has none: lpfg's vectors define no ==).
inline bool operator==(const V3tf& a, const V3tf& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
inline bool operator==(const V2tf& a, const V2tf& b) { return a.x == b.x && a.y == b.y; }
inline void PrintTo(const V3tf& v, std::ostream* os) { *os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }
