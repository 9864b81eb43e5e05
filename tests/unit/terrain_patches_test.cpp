// Terrain .patch files (runtime/files/TerrainPatches.h): the layout lpfg reads (width, then per
// level numU numV and u-major point/normal entries), only the levels asked for, and errors with
// the line for damaged or hostile files.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "runtime/files/TerrainPatches.h"

using namespace lcjit::runtime;

// The largest block operator new handed out since the last reset: "allocates nothing" measured,
// not timed. (Replacing the global operator new for this test program only counts; it still
// allocates with malloc.)
static std::atomic<size_t> largestAllocation{0};
void* operator new(size_t n) {
  for (size_t seen = largestAllocation.load(); n > seen && !largestAllocation.compare_exchange_weak(seen, n);) {
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/terrain/";

std::string errorOf(llvm::Expected<TerrainPatchFile> f) {
  if (f) return "";
  return llvm::toString(f.takeError());
}

// The file, or a failure with its error (and an empty file).
TerrainPatchFile must(llvm::Expected<TerrainPatchFile> f) {
  if (!f) {
    ADD_FAILURE() << llvm::toString(f.takeError());
    return TerrainPatchFile();
  }
  return std::move(*f);
}

void expectV3d(const V3d& v, double x, double y, double z) {
  EXPECT_EQ(v.x, x);
  EXPECT_EQ(v.y, y);
  EXPECT_EQ(v.z, z);
}

// One level of 2×2 entries: "x y z" and "nx ny nz" lines.
const char* kLevel0 = "2\n2\n0 0 0\n0 1 0\n0 0 1\n0 1 0\n1 0 0\n0 1 0\n1 0 1\n0 1 0\n";

}  // namespace

TEST(TerrainPatchFile, ReadsEveryLevelUMajor) {
  TerrainPatchFile f = must(loadTerrainPatches(kDir + "small.patch", 2));
  EXPECT_EQ(f.width, 2.5f);
  ASSERT_EQ(f.levels.size(), 2u);
  const TerrainGrid& a = f.levels[0];
  EXPECT_EQ(a.numU, 2);
  EXPECT_EQ(a.numV, 2);
  ASSERT_EQ(a.points.size(), 4u);
  // Entries run along v first: (u=0,v=0), (u=0,v=1), (u=1,v=0), (u=1,v=1).
  expectV3d(a.points[a.at(0, 0)], -1, 0.5, -1);
  expectV3d(a.points[a.at(0, 1)], -1, 0.25, 1);
  expectV3d(a.normals[a.at(0, 1)], 0.6, 0.8, 0);
  expectV3d(a.points[a.at(1, 0)], 1, 0, -1);
  expectV3d(a.normals[a.at(1, 0)], 0, 0.8, 0.6);
  expectV3d(a.points[a.at(1, 1)], 1, -0.5, 1);
  const TerrainGrid& b = f.levels[1];
  EXPECT_EQ(b.numU, 3);
  EXPECT_EQ(b.numV, 3);
  expectV3d(b.points[b.at(0, 1)], -1, 0.3, 0);
  expectV3d(b.points[b.at(1, 0)], 0, 0.1, -1);
  expectV3d(b.points[b.at(2, 1)], 1, -0.25, 0);
  expectV3d(b.normals[b.at(2, 2)], 0, 1, 0);
}

TEST(TerrainPatchFile, ReadsOnlyTheLevelsAskedFor) {
  // lpfg reads as many levels as the terrain: line says and ignores the rest of the file.
  TerrainPatchFile f = must(parseTerrainPatches(std::string("8\n") + kLevel0 + "whatever follows\n", "t.patch", 1));
  EXPECT_EQ(f.width, 8.0f);
  ASSERT_EQ(f.levels.size(), 1u);
  expectV3d(f.levels[0].points[3], 1, 0, 1);
  EXPECT_EQ(must(loadTerrainPatches(kDir + "small.patch", 1)).levels.size(), 1u);
}

TEST(TerrainPatchFile, NumbersAsAStreamReadsThem) {
  // Line breaks do not matter; CRLF is fine; exponents and signs are numbers.
  TerrainPatchFile f =
      must(parseTerrainPatches("3.5e0\r\n+2 2 -1e-1 .5 1. 0 1 0 0 0 1 0 1 0 1 0 0 0 1 0 1 0 1 0 1 0\r\n", "t.patch", 1));
  EXPECT_EQ(f.width, 3.5f);
  ASSERT_EQ(f.levels.size(), 1u);
  expectV3d(f.levels[0].points[0], -0.1, 0.5, 1);
}

TEST(TerrainPatchFile, DamagedFilesNameTheLine) {
  EXPECT_EQ(errorOf(parseTerrainPatches("", "t.patch", 1)),
            "t.patch:1: error: the file ends where the terrain width should be");
  EXPECT_EQ(errorOf(parseTerrainPatches("wide\n", "t.patch", 1)),
            "t.patch:1: error: the terrain width must be a number, not 'wide'");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2.5\n", "t.patch", 1)),
            "t.patch:3: error: the size of level 0 must be an integer, not '2.5'");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2\n0 0 0\n0 1 0\n0 x 1\n", "t.patch", 1)),
            "t.patch:6: error: a point of level 0 must be a number, not 'x'");
  // What strtod would take but a C++ stream does not.
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2\n0 0 0\n0 nan 0\n", "t.patch", 1)),
            "t.patch:5: error: a normal of level 0 must be a number, not 'nan'");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2\n0 0x1p3 0\n", "t.patch", 1)),
            "t.patch:4: error: a point of level 0 must be a number, not '0x1p3'");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2\n0 1e999 0\n", "t.patch", 1)),
            "t.patch:4: error: a point of level 0 is out of range: 1e999");
  // Truncated: the error is on the last line.
  EXPECT_EQ(errorOf(parseTerrainPatches(std::string("8\n") + kLevel0, "t.patch", 2)),
            "t.patch:11: error: the file ends where the size of level 1 should be");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2\n2\n0 0 0\n0 1 0\n0 0 1\n0 1\n", "t.patch", 1)),
            "t.patch:7: error: the file ends where a normal of level 0 should be");
}

TEST(TerrainPatchFile, GridsMustFitLpfgsPatches) {
  // Level l has 2^l patches a side, each with at least two points a side.
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n1 2\n0 0 0 0 1 0\n0 0 1 0 1 0\n", "t.patch", 1)),
            "t.patch:2: error: level 0 is 1 x 2 points: at least 2 per side are needed");
  EXPECT_EQ(errorOf(parseTerrainPatches(std::string("8\n") + kLevel0 + "2 3\n", "t.patch", 2)),
            "t.patch:12: error: level 1 is 2 x 3 points: at least 3 per side are needed");
  // A coarser level's points are every other point of the next finer one.
  std::string three = "3\n3\n";
  for (int k = 0; k < 9; ++k) three += "0 0 0 0 1 0\n";
  std::string four = "4\n4\n";
  for (int k = 0; k < 16; ++k) four += "0 0 0 0 1 0\n";
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n" + three + four, "t.patch", 2)),
            "t.patch:13: error: level 1 is 4 x 4 points: at least 5 x 5 are needed after level 0's 3 x 3");
}

TEST(TerrainPatchFile, HostileSizesAllocateNothing) {
  largestAllocation = 0;
  // 2·10⁹ declared points, or 10⁶ in a file of a few bytes: refused before any allocation.
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n50000 40000\n0 0 0 0 1 0\n", "t.patch", 1)),
            "t.patch:2: error: the terrain has more than 2097152 points");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n1000 1000\n0 0 0 0 1 0\n", "t.patch", 1)),
            "t.patch:2: error: level 0 declares 1000000 points, more than the rest of the file holds");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n2147483647 2147483647\n", "t.patch", 1)),
            "t.patch:2: error: the terrain has more than 2097152 points");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n99999999999 2\n", "t.patch", 1)),
            "t.patch:2: error: the size of level 0 is out of range: 99999999999");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n-5 2\n", "t.patch", 1)),
            "t.patch:2: error: level 0 is -5 x 2 points: at least 2 per side are needed");
  // The largest block: the error messages and the file's text, nowhere near a level of points
  // (1 000 000 points of six floats would be 24 MB).
  EXPECT_LT(largestAllocation.load(), size_t(64) << 10);
  // The number of levels the terrain: line may ask for.
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n", "t.patch", 0)), "t.patch:1: error: a terrain has 1 to 10 levels, not 0");
  EXPECT_EQ(errorOf(parseTerrainPatches("8\n", "t.patch", 11)), "t.patch:1: error: a terrain has 1 to 10 levels, not 11");
}

TEST(TerrainPatchFile, MissingFile) {
  std::string e = errorOf(loadTerrainPatches(kDir + "absent.patch", 1));
  EXPECT_NE(e.find("absent.patch: error: cannot open file"), std::string::npos) << e;
}
