// B-spline surfaces (manual §10.1): lpfg's reading of a .s net, its evaluation (against the
// vertices the reference lpfg writes for BSurface with `-out x.obj`), its normals and
// triangles, and the refinement/coarsening sizes lpfg's operator+ and Interpolate rely on.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "runtime/files/BSplineSurfaces.h"

using namespace lcjit::runtime;

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/bsplines/";

BSplineNet load(const std::string& file) {
  std::vector<std::string> warnings;
  BSplineFile f = loadBSpline(kDir + file, warnings);
  for (const auto& w : warnings) ADD_FAILURE() << w;
  return f.net;
}

// lpfg prints 6 significant digits.
void expectPrinted(const BSplinePoint& p, double x, double y, double z) {
  auto tol = [](double v) { return 6e-6 * std::fabs(v) + 1e-9; };
  EXPECT_NEAR(p.x, x, tol(x));
  EXPECT_NEAR(p.y, y, tol(y));
  EXPECT_NEAR(p.z, z, tol(z));
}

// A net whose point (i,j) is (i, j, i·j), to count and place refined/coarsened points.
BSplineNet grid(int rows, int columns) {
  BSplineNet n(rows, columns);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) n.at(i, j) = {double(i), double(j), double(i * j)};
  return n;
}

}  // namespace

TEST(BSplineFile, ReadsTheNetRowByRow) {
  BSplineNet n = load("net6x7.s");
  ASSERT_EQ(n.rows(), 6);
  ASSERT_EQ(n.columns(), 7);
  // The file's first and last points, as written (read in double).
  EXPECT_EQ(n.at(0, 0).x, -0.5108222);
  EXPECT_EQ(n.at(0, 0).y, 0.0130000);
  EXPECT_EQ(n.at(0, 0).z, 0.1362964);
  EXPECT_EQ(n.at(5, 6).x, 0.5311472);
  EXPECT_EQ(n.at(5, 6).z, 0.1007930);
}

// Too few points and a degree of 2: lpfg warns, reads what is there (a cubic anyway) and keeps
// its initial net elsewhere: point (3,4) of a 4 x 5 net is ((float)3/4 - 0.5 + 1e-6,
// (float)4/5 - 0.5 + 1e-6, 0), which lpfg's GetBsurfaceM returns as 0.250001013, 0.300001025.
TEST(BSplineFile, ShortFileKeepsLpfgsInitialNet) {
  std::vector<std::string> warnings;
  BSplineFile f = loadBSpline(kDir + "short.s", warnings);
  EXPECT_EQ(warnings.size(), 2u);
  EXPECT_EQ(f.degree, 2);
  ASSERT_EQ(f.net.rows(), 4);
  ASSERT_EQ(f.net.columns(), 5);
  EXPECT_EQ(f.net.at(0, 0).x, 0.1);
  EXPECT_EQ(f.net.at(0, 1).z, 3.0);
  EXPECT_EQ((float)f.net.at(3, 4).x, 0.250001013f);
  EXPECT_EQ((float)f.net.at(3, 4).y, 0.300001025f);
  EXPECT_EQ(f.net.at(3, 4).z, 0.0);
}

TEST(BSplineFile, MissingFileIsLpfgsInitialTenByTen) {
  std::vector<std::string> warnings;
  BSplineFile f = loadBSpline(kDir + "no-such-file.s", warnings);
  EXPECT_EQ(warnings.size(), 1u);
  ASSERT_EQ(f.net.rows(), 10);
  ASSERT_EQ(f.net.columns(), 10);
  EXPECT_EQ((float)f.net.at(9, 9).x, 0.400000989f);  // lpfg's GetBsurfaceM value
  EXPECT_EQ((float)f.net.at(2, 3).y, -0.19999899f);
}

// The grid of BSurface(0, 1) for `bsurface: net6x7.s 1 4 3`, u = 3 + i·(6−3)/4, v = 3 + j·(7−3)/3:
// the vertices printed by the reference lpfg (vlab 9bf820dc) with -out x.obj.
TEST(BSplineEvaluation, GridIsLpfgs) {
  BSplineNet n = load("net6x7.s");
  BSplineNet::Grid g = n.sample(4, 3);
  ASSERT_EQ(g.positions.size(), 20u);
  auto at = [&](int i, int j) { return g.positions[size_t(i) * 4 + size_t(j)]; };
  expectPrinted(at(0, 0), -0.510822, 0.013, 0.136296);
  expectPrinted(at(1, 0), -0.509353, 0.473371, 0.31681);
  expectPrinted(at(1, 1), -0.109958, 0.459815, 0.141767);
  expectPrinted(at(0, 1), -0.111427, -0.000555924, 0.06099);
  expectPrinted(at(1, 2), 0.129252, 0.450323, -0.0495148);
  expectPrinted(at(2, 1), -0.126998, 0.726944, 0.136957);
  expectPrinted(at(3, 2), 0.105151, 0.984581, -0.0307707);
  expectPrinted(at(4, 0), -0.506853, 1.468, -0.106239);
  expectPrinted(at(4, 3), 0.531147, 1.44863, 0.100793);
}

// `bsurface: net5x6.s 1 3 3`, the same way.
TEST(BSplineEvaluation, SmallNetIsLpfgs) {
  BSplineNet n = load("net5x6.s");
  BSplineNet::Grid g = n.sample(3, 3);
  ASSERT_EQ(g.positions.size(), 16u);
  auto at = [&](int i, int j) { return g.positions[size_t(i) * 4 + size_t(j)]; };
  expectPrinted(at(0, 0), -0.412265, 0.013, 0.337245);
  expectPrinted(at(1, 0), -0.436604, 0.487222, 0.240717);
  expectPrinted(at(1, 1), -0.105021, 0.476903, 0.142894);
  expectPrinted(at(0, 2), 0.121151, -0.00652238, 0.0389913);
  expectPrinted(at(2, 2), 0.0862928, 0.733552, 0.0105929);
  expectPrinted(at(3, 1), -0.0963992, 1.16668, -0.117041);
  expectPrinted(at(3, 3), 0.437018, 1.15183, 0.13855);
}

// lpfg differentiates forwards below parameter 5 and backwards above; at the last column of a
// net with 5 columns the forward step is clamped away, and lpfg's normal there is NaN (its
// picture darkens that edge: GL lights such a vertex with its ambient term only).
TEST(BSplineEvaluation, NormalsUnitOrLpfgsNaN) {
  BSplineNet n = load("net6x7.s");
  BSplineNet::Grid g = n.sample(4, 3);
  for (const BSplinePoint& p : g.normals) EXPECT_NEAR(p.x * p.x + p.y * p.y + p.z * p.z, 1.0, 1e-6);
  BSplineNet five = grid(5, 5);
  BSplinePoint edge = five.normal(4, 5);
  EXPECT_TRUE(std::isnan(edge.x));
  BSplinePoint inside = five.normal(4, 4);
  EXPECT_NEAR(inside.x * inside.x + inside.y * inside.y + inside.z * inside.z, 1.0, 1e-6);
}

// Each quad is cut along the diagonal whose end normals agree more; vertex order as lpfg's GL
// calls, texture coordinates (i/uDiv, j/vDiv).
TEST(BSplineEvaluation, MeshTrianglesAndTextureCoordinates) {
  BSplineNet n = load("net6x7.s");
  BSplineNet::Grid g = n.sample(4, 3);
  PatchGrid m = BSplineNet::mesh(g, 4, 3);
  ASSERT_EQ(m.indices.size(), size_t(4 * 3 * 6));
  EXPECT_FLOAT_EQ(m.uvs[m.at(4, 3)].x, 1);
  EXPECT_FLOAT_EQ(m.uvs[m.at(4, 3)].y, 1);
  EXPECT_FLOAT_EQ(m.uvs[m.at(1, 2)].x, 0.25f);
  EXPECT_FLOAT_EQ(m.uvs[m.at(1, 2)].y, 2.0f / 3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) {
      const uint32_t* t = &m.indices[size_t(i * 3 + j) * 6];
      EXPECT_EQ(t[0], m.at(i, j + 1));  // lpfg starts each quad at (i, j+1), then (i, j)
      EXPECT_EQ(t[1], m.at(i, j));
      bool flip = t[2] == m.at(i + 1, j);  // then (i+1, j) or (i+1, j+1)
      EXPECT_TRUE(flip || t[2] == m.at(i + 1, j + 1));
      if (flip) EXPECT_EQ(std::vector<uint32_t>(t + 3, t + 6), (std::vector<uint32_t>{t[0], t[2], uint32_t(m.at(i + 1, j + 1))}));
      else EXPECT_EQ(std::vector<uint32_t>(t + 3, t + 6), (std::vector<uint32_t>{t[1], uint32_t(m.at(i + 1, j)), t[2]}));
    }
}

// Sizes behind lpfg's operator+ and Interpolate (their results are checked bit for bit against
// lpfg by tests/models/bspline_lpfg_values): a line of n >= 6 points refines to 2n − 3, of 4 or
// 5 to 9; coarsening gives (n + 3)/2 and refuses to go below 10 rows or columns.
TEST(BSplineNetOps, RefineAndCoarsenSizes) {
  BSplineNet a = grid(6, 7);
  EXPECT_TRUE(a.refineRows());
  EXPECT_EQ(a.rows(), 9);
  EXPECT_TRUE(a.refineColumns());
  EXPECT_EQ(a.columns(), 11);
  BSplineNet b = grid(4, 5);
  EXPECT_TRUE(b.refineRows());
  EXPECT_TRUE(b.refineColumns());
  EXPECT_EQ(b.rows(), 9);
  EXPECT_EQ(b.columns(), 9);
  BSplineNet c = grid(3, 3);
  EXPECT_FALSE(c.refineRows());
  BSplineNet d = grid(17, 16);
  EXPECT_TRUE(d.coarsenRows());
  EXPECT_EQ(d.rows(), 10);
  EXPECT_FALSE(d.coarsenColumns());  // (16 + 3)/2 = 9 < 10
  EXPECT_EQ(d.columns(), 16);
  // The end points stay; refinement keeps the line's points in order.
  EXPECT_EQ(a.at(0, 0).x, 0.0);
  EXPECT_EQ(a.at(8, 10).x, 5.0);
  EXPECT_EQ(a.at(8, 10).y, 6.0);
  EXPECT_EQ(d.at(9, 0).x, 16.0);
}

// Interpolate(l, r, alpha, 31, 31) of a 17 x 10 and a 6 x 7 net: 31 x 31 as lpfg's (the model
// test's N(3,31,31,…)); sums take the left operand's size after refining the smaller one.
TEST(BSplineNetOps, ResizeAndSum) {
  BSplineNet l = load("net17x10.s"), r = load("net6x7.s");
  BSplineNet in = BSplineNet::interpolate(l, r, 0.3f, 31, 31);
  EXPECT_EQ(in.rows(), 31);
  EXPECT_EQ(in.columns(), 31);
  BSplineNet s = BSplineNet::add(l, r);
  EXPECT_EQ(s.rows(), 17);
  EXPECT_EQ(s.columns(), 10);
  float points[10 * 10 * 3];
  int rows = 0, columns = 0;
  EXPECT_TRUE(bsplineToRecord(l, 10, 10, points, &rows, &columns));  // GetBsurfaceS: 17 rows to 10
  EXPECT_EQ(rows, 10);
  EXPECT_EQ(columns, 10);
  EXPECT_EQ(points[0], -0.778500021f);      // lpfg's GetBsurfaceS(0) values
  EXPECT_EQ(points[3 * 90 + 0], -0.758995295f);
  EXPECT_EQ(points[3 * 90 + 1], 4.66900015f);
  EXPECT_EQ(points[3 * 90 + 2], -0.115142599f);
  BSplineNet eleven = grid(11, 9);
  EXPECT_FALSE(bsplineToRecord(eleven, 10, 10, points, &rows, &columns));  // lpfg loops
}
