// Bézier surfaces (.s): header and patches, lpfg's frame transform, control point order,
// tessellation (positions, normals, texture coordinates) and error handling.
#include <gtest/gtest.h>

#include "tests/unit/test_vectors.h"

#include <cmath>

#include <fstream>
#include <sstream>
#include <string>

#include "runtime/files/Surfaces.h"

using namespace lcjit::runtime;

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/surfaces/";


BezierSurface mustLoad(const std::string& file) {
  auto s = loadSurface(kDir + file);
  if (!s) {
    ADD_FAILURE() << llvm::toString(s.takeError());
    return BezierSurface();
  }
  return std::move(*s);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string errorOf(llvm::Expected<BezierSurface> s) {
  if (s) return "";
  return llvm::toString(s.takeError());
}

std::string header(const char* heading, const char* up, const char* contact = "X: 0 Y: 0 Z: 0",
                   const char* size = "1") {
  return std::string("0 1 0 1 0 1\nCONTACT POINT  ") + contact + "\nEND POINT  X: 0 Y: 0 Z: 0\nHEADING  " + heading +
         "\nUP  " + up + "\nSIZE: " + size + "\n";
}

std::string patch(const char* name, const std::string& points) {
  return std::string(name) + "\nTOP COLOR: 0 DIFFUSE: 0.00 BOTTOM COLOR: 0 DIFFUSE: 0.00\nAL: ~ A: ~ AR: ~\n"
         "L: ~ R: ~\nBL: ~ B: ~ BR: ~\n" + points;
}

}  // namespace

TEST(SurfaceFile, FlatPatchHeader) {
  BezierSurface s = mustLoad("flat.s");
  EXPECT_EQ(s.name, "flat");
  ASSERT_EQ(s.patches.size(), 1u);
  EXPECT_EQ(s.patchNames[0], "flat");
  EXPECT_V3_NEAR(s.contact, 0, 0, 0, 0);
  EXPECT_V3_NEAR(s.end, 0, 3, 0, 0);
  EXPECT_V3_NEAR(s.heading, 0, 1, 0, 0);
  EXPECT_V3_NEAR(s.up, 0, 0, 1, 0);
  EXPECT_EQ(s.size, 1.0f);
  EXPECT_FALSE(s.precisionS.has_value());
  // GetSurface order: index 4·row + column of the file.
  SurfaceObj g = s.first();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_V3_NEAR(g.points[4 * i + j], float(i), float(j), 0, 0);
}

TEST(SurfaceTessellation, FlatPatchTwoByTwo) {
  BezierSurface s = mustLoad("flat.s");
  PatchGrid g = s.tessellate(0, 2, 2);  // one patch: uv = (v, 1-u)
  EXPECT_EQ(g.uDiv, 2);
  EXPECT_EQ(g.vDiv, 2);
  ASSERT_EQ(g.positions.size(), 9u);
  ASSERT_EQ(g.normals.size(), 9u);
  ASSERT_EQ(g.uvs.size(), 9u);
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j) {
      const size_t k = g.at(i, j);
      EXPECT_EQ(k, size_t(3 * i + j));
      EXPECT_V3_NEAR(g.positions[k], 1.5f * i, 1.5f * j, 0, 1e-6);
      EXPECT_V3_NEAR(g.normals[k], 0, 0, 1, 1e-6);  // ∂P/∂u × ∂P/∂v
      EXPECT_NEAR(g.uvs[k].x, 0.5f * j, 1e-6);
      EXPECT_NEAR(g.uvs[k].y, 1.0f - 0.5f * i, 1e-6);
    }
  ASSERT_EQ(g.indices.size(), 24u);
  // First triangle (0,0) (1,0) (1,1): counter-clockwise about +z.
  EXPECT_EQ(g.indices[0], g.at(0, 0));
  EXPECT_EQ(g.indices[1], g.at(1, 0));
  EXPECT_EQ(g.indices[2], g.at(1, 1));
  for (size_t t = 0; t < g.indices.size(); t += 3) {
    V3f a = g.positions[g.indices[t]], b = g.positions[g.indices[t + 1]], c = g.positions[g.indices[t + 2]];
    EXPECT_GT(((b - a) % (c - a)).z, 0.0f);
  }
}

TEST(SurfaceTessellation, CurvedPatchPointAndNormal) {
  // z = 1 at the four middle control points: P(0.5,0.5).z = (B1+B2)(0.5)^2 = 0.75^2.
  SurfaceObj p;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) p.points[4 * i + j] = V3f(float(i), float(j), (i == 1 || i == 2) && (j == 1 || j == 2) ? 1.f : 0.f);
  EXPECT_V3_NEAR(bezierPoint(p, 0.5f, 0.5f), 1.5f, 1.5f, 0.5625f, 1e-6);
  EXPECT_V3_NEAR(bezierNormal(p, 0.5f, 0.5f), 0, 0, 1, 1e-6);  // symmetric: flat at the centre
  // At u = 0 the surface rises along u (∂P/∂u = (3, 0, 2.25), ∂P/∂v = (0, 3, 0)): normal ∝ (-6.75, 0, 9).
  V3f n = bezierNormal(p, 0.0f, 0.5f);
  EXPECT_V3_NEAR(n, -0.6f, 0, 0.8f, 1e-6);
  PatchGrid g = tessellatePatch(p, 4, 3);
  EXPECT_EQ(g.positions.size(), 20u);
  EXPECT_EQ(g.indices.size(), 72u);
  EXPECT_V3_NEAR(g.positions[g.at(2, 0)], 1.5f, 0, 0, 1e-6);
}

TEST(SurfaceFile, TwoPatchesFrameAndSurfaceUv) {
  BezierSurface s = mustLoad("two.s");
  ASSERT_EQ(s.patches.size(), 2u);
  EXPECT_EQ(s.patchNames[1], "Right_patch");
  ASSERT_TRUE(s.precisionS && s.precisionT);
  EXPECT_EQ(*s.precisionS, 5);
  EXPECT_EQ(*s.precisionT, 7);
  EXPECT_V3_NEAR(s.heading, 0, 1, 0, 0);  // normalised
  // (p - contact) / size with contact (1,2,3), size 2.
  EXPECT_V3_NEAR(s.first().points[1], 0, 1, 0, 1e-6);
  EXPECT_V3_NEAR(s.first().points[4], 1, 0, 0, 1e-6);
  EXPECT_V3_NEAR(s.controlPoint(16), 3, 0, 0, 1e-6);
  EXPECT_V3_NEAR(s.controlPoint(31), 6, 3, 0, 1e-6);
  EXPECT_V3_NEAR(s.controlPoint(32), 0, 0, 0, 0);
  EXPECT_V3_NEAR(s.controlPoint(-1), 0, 0, 0, 0);
  EXPECT_V3_NEAR(s.boundsMin, 0, 0, 0, 1e-6);
  EXPECT_V3_NEAR(s.boundsMax, 6, 3, 0, 1e-6);
  // Several patches: the texture spans the surface's bounding box.
  PatchGrid g = s.tessellate(1, 1, 1);
  EXPECT_NEAR(g.uvs[g.at(0, 0)].x, 0.5f, 1e-6);
  EXPECT_NEAR(g.uvs[g.at(0, 0)].y, 1.0f, 1e-6);
  EXPECT_NEAR(g.uvs[g.at(1, 1)].x, 1.0f, 1e-6);
  EXPECT_NEAR(g.uvs[g.at(1, 1)].y, 0.0f, 1e-6);
  EXPECT_TRUE(s.tessellate(2, 2, 2).positions.empty());
}

TEST(SurfaceFile, LpfgRotation) {
  // heading (1,0,0), up (0,0,1): left = up × heading = (0,1,0); p' = x·(-left) + y·heading + z·up.
  std::string pts;
  for (int i = 0; i < 16; ++i) pts += i == 0 ? "1 2 3\n" : "0 0 0\n";
  auto s = parseSurface(header("X: 1 Y: 0 Z: 0", "X: 0 Y: 0 Z: 1") + patch("p", pts), "rot.s");
  ASSERT_TRUE(bool(s)) << llvm::toString(s.takeError());
  EXPECT_V3_NEAR(s->first().points[0], 2, -1, 3, 1e-6);
  EXPECT_EQ(s->name, "rot");
}

TEST(SurfaceFile, PointsMayWrapLines) {
  std::string pts;
  for (int i = 0; i < 48; ++i) pts += std::to_string(i) + (i % 5 == 4 ? "\n" : " ");
  pts += "\n";
  auto s = parseSurface(header("X: 0 Y: 1 Z: 0", "X: 0 Y: 0 Z: 1") + patch("p", pts), "wrap.s");
  ASSERT_TRUE(bool(s)) << llvm::toString(s.takeError());
  EXPECT_V3_NEAR(s->first().points[15], 45, 46, 47, 0);
}

TEST(SurfaceErrors, TruncatedAndGarbage) {
  const std::string flat = readFile(kDir + "flat.s");
  ASSERT_FALSE(flat.empty());
  // Cut after the second row of control points.
  size_t cut = flat.find("2 0 0");
  std::string e = errorOf(parseSurface(flat.substr(0, cut), "cut.s"));
  EXPECT_NE(e.find("cut.s:"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;

  // Every prefix of the file fails cleanly or parses; none crashes.
  for (size_t n = 0; n < flat.size(); n += 7) (void)errorOf(parseSurface(flat.substr(0, n), "prefix.s"));

  e = errorOf(parseSurface("garbage\nmore garbage\n", "g.s"));
  EXPECT_NE(e.find("g.s:2:"), std::string::npos) << e;
  e = errorOf(parseSurface(header("X: 0 Y: 0 Z: 0", "X: 0 Y: 0 Z: 1"), "zero.s"));
  EXPECT_NE(e.find("zero.s:4:"), std::string::npos) << e;
  e = errorOf(parseSurface(header("X: 0 Y: 1 Z: 0", "X: 0 Y: 0 Z: 1", "X: 0 Y: 0 Z: 0", "0"), "size.s"));
  EXPECT_NE(e.find("size.s:6:"), std::string::npos) << e;
  e = errorOf(parseSurface(header("X: 0 Y: 1 Z: 0", "X: 0 Y: 0 Z: 1"), "nopatch.s"));
  EXPECT_NE(e.find("no patches"), std::string::npos) << e;
  std::string bad;
  for (int i = 0; i < 16; ++i) bad += i == 9 ? "1 x 3\n" : "0 0 0\n";
  e = errorOf(parseSurface(header("X: 0 Y: 1 Z: 0", "X: 0 Y: 0 Z: 1") + patch("p", bad), "bad.s"));
  EXPECT_NE(e.find("bad.s:21:"), std::string::npos) << e;
  EXPECT_FALSE(errorOf(parseSurface("", "empty.s")).empty());
  EXPECT_FALSE(errorOf(parseSurface(std::string("\0\x01\xff\n\0\0", 6), "bin.s")).empty());
  e = errorOf(loadSurface(kDir + "missing.s"));
  EXPECT_NE(e.find("missing.s"), std::string::npos) << e;
}
