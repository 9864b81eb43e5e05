// Contours (.con/.cset): parsing of all cuspy versions, lpfg's numbering, arc-length sampling,
// curve functions, blending and error handling.
#include <gtest/gtest.h>

#include "tests/unit/test_vectors.h"

#include <cmath>
#include <string>

#include "runtime/files/Contours.h"

using namespace lcjit::runtime;

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/contours/";


Contour mustLoad(const std::string& file) {
  auto c = Contour::load(kDir + file);
  if (!c) {
    ADD_FAILURE() << llvm::toString(c.takeError());
    return Contour::defaultCircle();
  }
  return std::move(*c);
}

std::string errorOf(llvm::Expected<Contour> c) {
  if (c) return "";
  return llvm::toString(c.takeError());
}

}  // namespace

TEST(ContourDefault, CircleAsLpfg) {
  ContourStore store;
  ASSERT_EQ(store.size(), 1);
  const Contour* c = store.get(0);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->name(), "def_contour");
  EXPECT_TRUE(c->closed());
  EXPECT_TRUE(c->isDefaultCircle());
  ASSERT_EQ(c->divisions(), 8);
  for (int i = 0; i < 7; ++i) {
    const float a = 2.0f * float(M_PI) * float(i) / 7.0f;
    EXPECT_V3_NEAR(c->points()[i], std::sin(a), std::cos(a), 0, 1e-6);
    EXPECT_V3_NEAR(c->normals()[i], std::sin(a), std::cos(a), 0, 1e-6);
  }
  EXPECT_EQ(c->points()[7], c->points()[0]);
  EXPECT_EQ(c->arcLength(), 0.0f);

  Contour d = Contour::defaultCircle();
  d.setDivisions(5);  // 4 sides: top, right, bottom, left, top
  ASSERT_EQ(d.points().size(), 5u);
  EXPECT_V3_NEAR(d.points()[0], 0, 1, 0, 1e-6);
  EXPECT_V3_NEAR(d.points()[1], 1, 0, 0, 1e-6);
  EXPECT_V3_NEAR(d.points()[2], 0, -1, 0, 1e-6);
  EXPECT_V3_NEAR(d.points()[3], -1, 0, 0, 1e-6);
  EXPECT_V3_NEAR(d.points()[4], 0, 1, 0, 1e-6);
}

TEST(ContourSampling, SquareAtNinePoints) {
  Contour c = mustLoad("square.con");
  EXPECT_EQ(c.name(), "square");
  EXPECT_TRUE(c.closed());
  ASSERT_TRUE(c.fileSamples().has_value());
  EXPECT_EQ(*c.fileSamples(), 9);
  ASSERT_EQ(c.divisions(), 9);
  // Starts at the last control point (lpfg puts the last three in front), equal arc-length steps
  // of 1 along the perimeter of 8, clockwise.
  const float expect[9][2] = {{-1, -1}, {-1, 0}, {-1, 1}, {0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}};
  for (int i = 0; i < 9; ++i) EXPECT_V3_NEAR(c.points()[i], expect[i][0], expect[i][1], 0, 1e-3) << i;
  // Outward normals at the edge midpoints.
  EXPECT_V3_NEAR(c.normals()[1], -1, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.normals()[3], 0, 1, 0, 1e-4);
  EXPECT_V3_NEAR(c.normals()[5], 1, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.normals()[7], 0, -1, 0, 1e-4);
  EXPECT_NEAR(c.arcLength(), 8.0f, 1e-3);
}

TEST(ContourSampling, SquareAtFivePointsAndClamping) {
  Contour c = mustLoad("square.con");
  ContourSamples s = c.sampled(5);
  EXPECT_EQ(c.divisions(), 9);  // sampled() leaves the contour alone
  ASSERT_EQ(s.points.size(), 5u);
  EXPECT_TRUE(s.closed);
  const float expect[5][2] = {{-1, -1}, {-1, 1}, {1, 1}, {1, -1}, {-1, -1}};
  for (int i = 0; i < 5; ++i) EXPECT_V3_NEAR(s.points[i], expect[i][0], expect[i][1], 0, 1e-3) << i;

  c.setDivisions(1);
  EXPECT_EQ(c.divisions(), 3);
  c.setDivisions(20000);
  EXPECT_EQ(c.divisions(), 10000);
  EXPECT_EQ(c.points().size(), 10000u);
}

TEST(ContourSampling, DrawDivisionsRule) {
  Contour withSamples = mustLoad("square.con");
  Contour without = mustLoad("old11.con");
  EXPECT_EQ(withSamples.drawDivisions(0, 16), 9);   // file's samples
  EXPECT_EQ(without.drawDivisions(0, 16), 17);      // view's contour sides + 1
  EXPECT_EQ(without.drawDivisions(0, 6), 7);
  EXPECT_EQ(withSamples.drawDivisions(5, 16), 5);   // ContourSides wins
  EXPECT_EQ(Contour::defaultCircle().drawDivisions(0, 16), 17);
}

TEST(ContourCurve, ArcLengthParameterOnStraightLine) {
  // Control points 0 (×3), 0.5, 3 (×3): unevenly spaced, yet t is the arc-length parameter.
  Contour c = mustLoad("line.con");
  EXPECT_FALSE(c.closed());
  EXPECT_EQ(c.divisions(), 8);
  EXPECT_NEAR(c.arcLength(), 3.0f, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(0.0f), 0, 0, 0, 1e-5);
  EXPECT_V3_NEAR(c.pointAt(0.5f), 1.5f, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(0.25f), 0.75f, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(1.0f), 3.0f, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(-2.0f), 0, 0, 0, 1e-5);  // clamped
  EXPECT_V3_NEAR(c.pointAt(7.0f), 3.0f, 0, 0, 1e-4);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(c.points()[i].x, 3.0f * float(i) / 7.0f, 1e-4) << i;
  EXPECT_V3_NEAR(c.normalAt(0.5f), 0, 1, 0, 1e-5);  // tangent +x turned +90°
}

TEST(ContourCurve, SetPointRecalculateResetScale) {
  Contour c = mustLoad("line.con");
  ASSERT_EQ(c.controlPoints().size(), 7u);  // multiplicities expanded, open: no wrap
  for (int i = 4; i < 7; ++i) EXPECT_TRUE(c.setControlPoint(i, V3f(6, 0, 0)));
  EXPECT_FALSE(c.setControlPoint(7, V3f()));
  EXPECT_FALSE(c.setControlPoint(-1, V3f()));
  EXPECT_V3_NEAR(c.pointAt(1.0f), 3, 0, 0, 1e-4);  // not yet recalculated
  c.recalculate();
  EXPECT_NEAR(c.arcLength(), 6.0f, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(1.0f), 6, 0, 0, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(0.5f), 3, 0, 0, 1e-4);

  c.reset();  // like lpfg: restores the points, keeps the samples until recalculated
  EXPECT_V3_NEAR(c.controlPoints()[6], 3, 0, 0, 0);
  EXPECT_V3_NEAR(c.pointAt(1.0f), 6, 0, 0, 1e-4);
  c.recalculate();
  EXPECT_V3_NEAR(c.pointAt(1.0f), 3, 0, 0, 1e-4);

  c.scale(V3f(2, 1, 1));  // scales and recalculates
  EXPECT_NEAR(c.arcLength(), 6.0f, 1e-4);
  EXPECT_V3_NEAR(c.pointAt(0.5f), 3, 0, 0, 1e-4);
}

TEST(ContourCurve, ClosedControlPointIndexing) {
  Contour c = mustLoad("square.con");
  ASSERT_EQ(c.controlPoints().size(), 15u);  // 12 + the last three repeated in front
  EXPECT_V3_NEAR(c.controlPoints()[0], -1, -1, 0, 0);
  EXPECT_V3_NEAR(c.controlPoints()[3], -1, 1, 0, 0);
  EXPECT_V3_NEAR(c.controlPoints()[14], -1, -1, 0, 0);
}

TEST(ContourVersions, OlderFormats) {
  Contour v11 = mustLoad("old11.con");
  EXPECT_EQ(v11.name(), "old_line");
  EXPECT_FALSE(v11.closed());
  EXPECT_FALSE(v11.fileSamples().has_value());
  EXPECT_EQ(v11.divisions(), 8);  // lpfg's default
  EXPECT_V3_NEAR(v11.pointAt(0.5f), 0, 1, 0, 1e-4);
  EXPECT_V3_NEAR(v11.normalAt(0.5f), -1, 0, 0, 1e-5);

  Contour v10 = mustLoad("old10.con");
  EXPECT_EQ(v10.name(), "old10");
  EXPECT_FALSE(v10.closed());
  EXPECT_V3_NEAR(v10.pointAt(0.25f), 1, 0, 0, 1e-4);
  EXPECT_NEAR(v10.arcLength(), 4.0f, 1e-4);

  // cver 1.3 with a markers block and blank lines.
  auto m = Contour::parse(
      "cver 1 3\nname: marked extra words\npoints: 2 6\ntype: or\nsamples: 3\nmarkers: 2\nm1\nm2\n\n"
      "0 0 0 3\n0 5 0 3\n",
      "inline.con");
  ASSERT_TRUE(bool(m)) << llvm::toString(m.takeError());
  EXPECT_EQ(m->name(), "marked");
  EXPECT_EQ(m->divisions(), 3);
  EXPECT_V3_NEAR(m->points()[1], 0, 2.5f, 0, 1e-4);
}

TEST(ContourVersions, EndPointInterpolation) {
  // Deprecated 'oe': four collinear, evenly spaced points form a Bézier segment x = 3u.
  auto c = Contour::parse("cver 1 2\nname: ep\npoints: 4 4\ntype: oe\n0 0 0 1\n1 0 0 1\n2 0 0 1\n3 0 0 1\n",
                          "ep.con");
  ASSERT_TRUE(bool(c)) << llvm::toString(c.takeError());
  EXPECT_TRUE(c->endPointInterpolating());
  ASSERT_EQ(c->divisions(), 8);
  for (int i = 0; i < 8; ++i) EXPECT_V3_NEAR(c->points()[i], 3.0f * float(i) / 7.0f, 0, 0, 1e-5) << i;
  EXPECT_V3_NEAR(c->normals()[3], 0, 1, 0, 1e-5);
}

TEST(ContourStoreTest, LpfgNumbering) {
  ContourStore store;
  // The .cset comes first whatever its place on the command line; then the .con files in order.
  llvm::Error e = store.loadFiles({kDir + "line.con", kDir + "set.cset", kDir + "square.con", kDir + "x.func"});
  ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  ASSERT_EQ(store.size(), 5);
  EXPECT_EQ(store.nameOf(0), "def_contour");
  EXPECT_EQ(store.nameOf(1), "setline");
  EXPECT_EQ(store.nameOf(2), "setsquare");
  EXPECT_EQ(store.nameOf(3), "line");
  EXPECT_EQ(store.nameOf(4), "square");
  EXPECT_EQ(store.nameOf(5), "");
  EXPECT_EQ(store.get(5), nullptr);
  EXPECT_EQ(store.get(-1), nullptr);
  EXPECT_EQ(store.get(1)->divisions(), 5);
  EXPECT_TRUE(store.get(2)->closed());
  EXPECT_V3_NEAR(store.get(1)->pointAt(0.5f), 0, 0.5f, 0, 1e-4);
}

TEST(ContourStoreTest, FailedContourKeepsItsId) {
  ContourStore store;
  llvm::Error e = store.loadFiles({kDir + "missing.con", kDir + "square.con"});
  ASSERT_TRUE(bool(e));
  std::string msg = llvm::toString(std::move(e));
  EXPECT_NE(msg.find("missing.con"), std::string::npos) << msg;
  ASSERT_EQ(store.size(), 3);
  EXPECT_TRUE(store.get(1)->isDefaultCircle());
  EXPECT_EQ(store.nameOf(2), "square");
}

TEST(ContourBlend, Pointwise) {
  Contour sq = mustLoad("square.con");
  ContourSamples a = sq.samples();
  ContourSamples b = Contour::defaultCircle().sampled(9);
  ContourSamples h = blendContours(a, b, 0.5f);
  ASSERT_EQ(h.points.size(), 9u);
  for (int i = 0; i < 9; ++i) {
    EXPECT_V3_NEAR(h.points[i], 0.5f * (a.points[i].x + b.points[i].x), 0.5f * (a.points[i].y + b.points[i].y), 0,
                   1e-6);
    EXPECT_V3_NEAR(h.normals[i], 0.5f * (a.normals[i].x + b.normals[i].x),
                   0.5f * (a.normals[i].y + b.normals[i].y), 0, 1e-6);
  }
  ContourSamples z = blendContours(a, b, 0.0f);
  EXPECT_EQ(z.points[3], a.points[3]);
  ContourSamples o = blendContours(a, b, 1.0f);
  EXPECT_EQ(o.points[3], b.points[3]);
  // Different counts: b is resampled at a's parameters.
  ContourSamples b5 = Contour::defaultCircle().sampled(5);
  ContourSamples m = blendContours(a, b5, 1.0f - 1e-7f);
  ASSERT_EQ(m.points.size(), 9u);
  EXPECT_V3_NEAR(m.points[2], 1, 0, 0, 1e-5);  // circle sample 1 of 5
  EXPECT_V3_NEAR(m.points[1], 0.5f, 0.5f, 0, 1e-5);
}

TEST(ContourErrors, TruncatedAndGarbage) {
  std::string e = errorOf(Contour::load(kDir + "truncated.con"));
  EXPECT_NE(e.find("truncated.con:"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;

  e = errorOf(Contour::parse("cver 1 3\nname: x\npoints: 2 6\ntype: or\n0 0 0 3\n1 0 0 x\n", "bad.con"));
  EXPECT_NE(e.find("bad.con:6:"), std::string::npos) << e;

  e = errorOf(Contour::parse("hello world\n", "garbage.con"));
  EXPECT_NE(e.find("garbage.con:1:"), std::string::npos) << e;

  e = errorOf(Contour::parse("cver 1 3\nname: x\npoints: 2 6\ntype: or\n0 0 0 3\n1 0 0 2\n", "sum.con"));
  EXPECT_NE(e.find("multiplicities"), std::string::npos) << e;

  e = errorOf(Contour::parse("cver 1 9\nname: x\n", "ver.con"));
  EXPECT_NE(e.find("ver.con:1:"), std::string::npos) << e;

  e = errorOf(Contour::parse("cver 1 3\nname: x\npoints: 1 3\ntype: or\n0 0 0 3\n", "few.con"));
  EXPECT_NE(e.find("few.con:3:"), std::string::npos) << e;

  e = errorOf(Contour::parse("cver 1 2\nname: x\npoints: 2 6\ntype: zz\n", "type.con"));
  EXPECT_NE(e.find("type.con:4:"), std::string::npos) << e;

  EXPECT_FALSE(errorOf(Contour::parse("", "empty.con")).empty());
  EXPECT_FALSE(errorOf(Contour::parse("cver 1 3\nname: x\npoints: 2 6\n", "hdr.con")).empty());
  EXPECT_FALSE(errorOf(Contour::parse("cver 1 3\nname: x\npoints: 2 99999999999\ntype: or\n", "big.con")).empty());
  EXPECT_FALSE(errorOf(Contour::parse("4 2 closed\n0 0\n1 0\n", "old.con")).empty());
  EXPECT_FALSE(errorOf(Contour::parse(std::string("\0\xff\x01garbage", 10), "bin.con")).empty());

  ContourStore store;
  llvm::Error se = store.loadSetText("contourgalleryver 1 1\nitems: 2\ncver 1 1\nname: a\npoints: 2 6\ntype: open\n"
                                     "0 0 0 3\n1 0 0 3\n",
                                     "short.cset");
  ASSERT_TRUE(bool(se));
  std::string sm = llvm::toString(std::move(se));
  EXPECT_NE(sm.find("short.cset:"), std::string::npos) << sm;
  EXPECT_EQ(store.size(), 2);  // the item read before the failure stays, as in lpfg
  se = store.loadSetText("items: 1\n", "nohdr.cset");
  EXPECT_TRUE(bool(se));
  llvm::consumeError(std::move(se));
}
