// Tests for runtime/Functions: lpfg's .func/.fset/.tset/.vset readers and the
// func/pfunc/tfunc/val evaluators, against values derived outside this code.
#include "runtime/Functions.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>

using lcjit::runtime::FunctionStore;

namespace {

std::string data(const char* name) {
  return std::string(LCJIT_FUNCTIONS_DATA) + "/" + name;
}

// Loads or fails the test with the error text.
void mustLoad(llvm::Error err) {
  if (err) FAIL() << llvm::toString(std::move(err));
}

std::string errorText(llvm::Error err) {
  if (!err) return "<no error>";
  return llvm::toString(std::move(err));
}

TEST(Functions, LinearFunction) {
  FunctionStore s;
  mustLoad(s.loadFunction(data("linear.func")));
  // Control points lie on y = 2 + 3x, evenly spaced in x, so the cubic
  // B-spline is that line. lpfg's table stores y at an x found by bisection to
  // within 0.01/samples = 1e-4, i.e. y within 3e-4 of the line.
  EXPECT_NEAR(s.func(1, 0.0f), 2.0f, 3e-4);
  EXPECT_NEAR(s.func(1, 0.25f), 2.75f, 3e-4);
  EXPECT_NEAR(s.func(1, 0.5f), 3.5f, 3e-4);
  EXPECT_NEAR(s.func(1, 0.73f), 4.19f, 3e-4);
  EXPECT_NEAR(s.func(1, 1.0f), 5.0f, 3e-4);
  // Exact reproduction of lpfg's table (bisection stop included): from
  // data/functions/derive_expected.py, described in KnownCurve.
  EXPECT_NEAR(s.func(1, 0.0f), 2.0001831f, 1e-5);
  EXPECT_NEAR(s.func(1, 0.25f), 2.7498169f, 1e-5);
  EXPECT_NEAR(s.func(1, 1.0f), 4.9998169f, 1e-5);
}

TEST(Functions, KnownCurve) {
  FunctionStore s;
  mustLoad(s.loadFunction(data("leaf.func")));
  // leaf.func: 6 points (one with multiplicity 2, so 7 control points),
  // samples: 20. Expectations come from data/functions/derive_expected.py
  // (python3, standard library only: Cox-de Boor
  // recursion over knots 0,0,0,0,1,2,3,4,4,4,4 with u = 4d), which tabulates
  // y at x = i/19 using lpfg's bisection (stop when |x(d)-target| <= 0.01/20)
  // and then interpolates linearly in that table. The exact curve values
  // (parameter solved to 1e-15) are given alongside: the table differs from
  // them by up to ~1.3e-3, which is lpfg's behaviour.
  struct Case {
    float x, table, exactCurve;
  };
  const Case cases[] = {
      {0.0f, 0.0001472f, 0.0f},
      {0.1f, 0.0805600f, 0.0793312f},
      {0.25f, 0.4038382f, 0.4025128f},
      {0.5f, 0.8895106f, 0.8899740f},          // between samples 9 and 10
      {10.0f / 19.0f, 0.9212866f, 0.9209248f},  // exactly sample 10
      {0.75f, 0.7618528f, 0.7616017f},
      {0.9f, 0.6558195f, 0.6554408f},
      {1.0f, 0.6001465f, 0.6f},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.x);
    EXPECT_NEAR(s.func(1, c.x), c.table, 2e-6);
    EXPECT_NEAR(s.func(1, c.x), c.exactCurve, 1.5e-3);
    EXPECT_FLOAT_EQ(s.func("leaf_length", c.x), s.func(1, c.x));
  }
}

TEST(Functions, ClampsArgument) {
  FunctionStore s;
  mustLoad(s.loadFunction(data("leaf.func")));
  EXPECT_EQ(s.func(1, -3.0f), s.func(1, 0.0f));
  EXPECT_EQ(s.func(1, 7.0f), s.func(1, 1.0f));
  EXPECT_EQ(s.func(1, std::nanf("")), s.func(1, 0.0f));
}

TEST(Functions, UnknownIdsAndNamesGiveZero) {
  FunctionStore s;
  EXPECT_EQ(s.func(1, 0.5f), 0.0f);
  mustLoad(s.loadFunction(data("linear.func")));
  EXPECT_EQ(s.func(0, 0.5f), 0.0f);
  EXPECT_EQ(s.func(2, 0.5f), 0.0f);
  EXPECT_EQ(s.func(-1, 0.5f), 0.0f);
  EXPECT_EQ(s.func("nosuch", 0.5f), 0.0f);
  EXPECT_EQ(s.pfunc(2, 0.5f, 0, 1), 0.0f);
  EXPECT_EQ(s.tfunc("nosuch", 0.5f), 0.0f);
  EXPECT_EQ(s.val("nosuch"), 0.0f);
  EXPECT_EQ(s.idOf("nosuch"), 0);
}

TEST(Functions, FunctionSetAndAllCapsNames) {
  FunctionStore s;
  mustLoad(s.loadFunctionSet(data("set.fset")));
  ASSERT_EQ(s.size(), 2);
  EXPECT_EQ(s.nameOf(1), "width");
  EXPECT_EQ(s.nameOf(2), "Leaf_Angle");
  // width: points on y = 1 - x.
  EXPECT_NEAR(s.func("width", 0.3f), 0.7f, 2e-3);
  EXPECT_NEAR(s.func("WIDTH", 0.3f), 0.7f, 2e-3);
  EXPECT_EQ(s.idOf("WIDTH"), 1);
  // Constant control points: the curve is that constant (the background
  // lines before flip: are skipped).
  EXPECT_FLOAT_EQ(s.func("Leaf_Angle", 0.42f), 0.7f);
  EXPECT_FLOAT_EQ(s.func("LEAF_ANGLE", 0.42f), 0.7f);
  EXPECT_EQ(s.idOf("LEAF_ANGLE"), 2);
  // Only the exact spelling and the all-caps one are defined.
  EXPECT_EQ(s.idOf("leaf_angle"), 0);
  EXPECT_EQ(s.func("leaf_angle", 0.42f), 0.0f);
}

TEST(Functions, TimelineAndRanges) {
  FunctionStore s;
  mustLoad(s.loadTimeline(data("timeline.tset")));
  ASSERT_EQ(s.size(), 2);
  // GROWTH: y = x over the timeline [0,18].
  EXPECT_NEAR(s.tfunc("GROWTH", 9.0f), 0.5f, 1e-4);
  EXPECT_NEAR(s.tfunc(1, 4.5f), 0.25f, 1e-4);
  EXPECT_EQ(s.tfunc(1, 4.5f), s.func(1, 0.25f));
  EXPECT_EQ(s.tfunc(1, -5.0f), s.func(1, 0.0f));  // clamped below start
  EXPECT_EQ(s.tfunc(1, 30.0f), s.func(1, 1.0f));  // and above end
  // pfunc ignores the timeline and maps [min,max] onto [0,1].
  EXPECT_EQ(s.pfunc(1, 15.0f, 10.0f, 20.0f), s.func(1, 0.5f));
  EXPECT_EQ(s.pfunc("GROWTH", 2.0f, 0.0f, 8.0f), s.func(1, 0.25f));
  EXPECT_EQ(s.pfunc(1, 25.0f, 10.0f, 20.0f), s.func(1, 1.0f));
  // pfunc makes [min,max] the range later tfunc calls use, as in lpfg: the last one above set
  // [10,20], so 9 is below the start.
  EXPECT_EQ(s.tfunc(1, 9.0f), s.func(1, 0.0f));
  EXPECT_EQ(s.tfunc(1, 12.5f), s.func(1, 0.25f));
  // Second timeline: funcedit name aging_curve, timeline name Aging; both
  // resolve, domain [10.5, 20.5], constant 1.
  EXPECT_EQ(s.nameOf(2), "aging_curve");
  EXPECT_EQ(s.idOf("aging_curve"), 2);
  EXPECT_EQ(s.idOf("Aging"), 2);
  EXPECT_EQ(s.idOf("AGING_CURVE"), 2);
  EXPECT_FLOAT_EQ(s.tfunc("aging_curve", 15.0f), 1.0f);
  // Non-timeline functions have the range [0,1]: tfunc equals func.
  mustLoad(s.loadFunction(data("leaf.func")));
  EXPECT_EQ(s.tfunc(3, 0.37f), s.func(3, 0.37f));
}

TEST(Functions, Parameters) {
  FunctionStore s;
  mustLoad(s.loadParameters(data("params.vset")));
  EXPECT_FLOAT_EQ(s.val("BR_END"), 15.4362f);
  EXPECT_FLOAT_EQ(s.val("SIM_END"), 23.2721f);  // tab-separated line
  EXPECT_FLOAT_EQ(s.val("COUNT"), 7.0f);
  EXPECT_FLOAT_EQ(s.val(2), 23.2721f);
  EXPECT_EQ(s.val("MISSING"), 0.0f);
  // Parameters are not curves.
  EXPECT_EQ(s.func("BR_END", 0.5f), 0.0f);
}

TEST(Functions, SetParameter) {
  // The REPL's :set: a new value for a .vset entry, by name; curves and unknown names are refused.
  FunctionStore s;
  mustLoad(s.loadFunction(data("linear.func")));
  mustLoad(s.loadParameters(data("params.vset")));
  EXPECT_FALSE(s.isParameter(1));
  EXPECT_TRUE(s.isParameter(s.idOf("COUNT")));
  EXPECT_TRUE(s.setParameter("COUNT", 9.5f));
  EXPECT_FLOAT_EQ(s.val("COUNT"), 9.5f);
  EXPECT_FLOAT_EQ(s.val("BR_END"), 15.4362f);
  EXPECT_FALSE(s.setParameter("linear", 1.0f));
  EXPECT_NEAR(s.func("linear", 0.5f), 3.5f, 3e-4);
  EXPECT_FALSE(s.setParameter("MISSING", 1.0f));
  EXPECT_EQ(s.idOf("MISSING"), 0);
}

TEST(Functions, IdsFollowLoadOrderAcrossFiles) {
  FunctionStore s;
  // lpfg's own order: .fset, .tset, .vset, then .func files.
  mustLoad(s.loadFunctionSet(data("set.fset")));
  mustLoad(s.loadTimeline(data("timeline.tset")));
  mustLoad(s.loadParameters(data("params.vset")));
  mustLoad(s.loadFunction(data("linear.func")));
  mustLoad(s.loadFunction(data("leaf.func")));
  ASSERT_EQ(s.size(), 9);
  const char* names[] = {"width",  "Leaf_Angle", "GROWTH", "aging_curve", "BR_END",
                         "SIM_END", "COUNT",     "linear", "leaf_length"};
  for (int id = 1; id <= 9; ++id) {
    EXPECT_EQ(s.nameOf(id), names[id - 1]);
    EXPECT_EQ(s.idOf(names[id - 1]), id);
  }
  EXPECT_NEAR(s.func(8, 0.5f), 3.5f, 3e-4);
  EXPECT_NEAR(s.func(9, 0.5f), 0.8895106f, 2e-6);
  EXPECT_FLOAT_EQ(s.val(5), 15.4362f);
  EXPECT_EQ(s.val(8), 0.0f);  // a curve has no parameter value
  EXPECT_EQ(s.func(5, 0.5f), 0.0f);

  s.clear();
  EXPECT_EQ(s.size(), 0);
  EXPECT_EQ(s.func("linear", 0.5f), 0.0f);
  mustLoad(s.loadFunction(data("leaf.func")));
  EXPECT_EQ(s.idOf("leaf_length"), 1);
}

TEST(Functions, LaterDuplicateNameWins) {
  FunctionStore s;
  mustLoad(s.loadFunction(data("linear.func")));
  mustLoad(s.loadFunction(data("linear.func")));
  EXPECT_EQ(s.idOf("linear"), 2);
}

TEST(Functions, OldRangeFormatTakesNameFromFile) {
  FunctionStore s;
  mustLoad(s.loadFunction(data("range.func")));
  EXPECT_EQ(s.nameOf(1), "range");
  EXPECT_FLOAT_EQ(s.func("range", 0.6f), 0.5f);
}

TEST(Functions, Errors) {
  FunctionStore s;
  const std::string bp = data("bad_point.func");
  EXPECT_EQ(errorText(s.loadFunction(bp)),
            bp + ":7:10: error: invalid number 'oops'");
  const std::string fp = data("few_points.func");
  EXPECT_EQ(errorText(s.loadFunction(fp)),
            fp + ":5:9: error: a function needs at least 4 control points, got 3");
  const std::string tr = data("truncated.fset");
  EXPECT_EQ(errorText(s.loadFunctionSet(tr)),
            tr + ":11:8: error: unexpected end of file, expected function 2 of 2");
  const std::string bh = data("bad_header.fset");
  EXPECT_EQ(errorText(s.loadFunctionSet(bh)),
            bh + ":1:1: error: expected 'funcgalleryver 1 1' or 'timeEdit 1 2'");
  const std::string bv = data("bad.vset");
  EXPECT_EQ(errorText(s.loadParameters(bv)),
            bv + ":2:1: error: expected '#define NAME VALUE'");
  const std::string nv = data("novalue.vset");
  EXPECT_EQ(errorText(s.loadParameters(nv)),
            nv + ":2:16: error: expected '#define NAME VALUE'");
  const std::string ver = data("bad_version.func");
  EXPECT_EQ(errorText(s.loadFunction(ver)),
            ver + ":1:6: error: unsupported function file version 1.2 (only "
                  "'fver 1 1' is known)");
  const std::string missing = data("does_not_exist.func");
  EXPECT_EQ(errorText(s.loadFunction(missing)),
            missing + ": error: cannot open file: " + std::strerror(ENOENT));
  // A .func is not a function set.
  const std::string lin = data("linear.func");
  EXPECT_EQ(errorText(s.loadFunctionSet(lin)),
            lin + ":1:1: error: expected 'funcgalleryver 1 1' or 'timeEdit 1 2'");
  // Failed loads, including a .vset that failed after a good line, add nothing.
  EXPECT_EQ(s.size(), 0);
  EXPECT_EQ(s.val("OK"), 0.0f);
}

}  // namespace
