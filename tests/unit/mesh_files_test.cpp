// Mesh files (OBJ, PLY ascii/binary): triangulation, lpfg's normals, scale/contact, texture
// coordinates, colours and error handling.
#include <gtest/gtest.h>

#include "tests/unit/test_vectors.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/files/MeshFiles.h"

using namespace lcjit::runtime;

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/meshes/";


const float kCube[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                           {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
const int kCubeFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};

MeshData mustLoad(const std::string& path, const MeshLoadOptions& o = {}) {
  auto m = loadMesh(path, o);
  if (!m) {
    ADD_FAILURE() << llvm::toString(m.takeError());
    return MeshData();
  }
  return std::move(*m);
}

int findPosition(const MeshData& m, float x, float y, float z) {
  for (size_t i = 0; i < m.positions.size(); ++i)
    if (m.positions[i] == V3f(x, y, z)) return int(i);
  return -1;
}

// Checks the unit cube as lpfg sees it: 12 triangles, bounds, outward winding and normals.
void checkCube(const MeshData& m) {
  EXPECT_EQ(m.positions.size(), 8u);
  EXPECT_EQ(m.triangleCount(), 12u);
  EXPECT_V3_NEAR(m.boundsMin, -1, -1, -1, 0);
  EXPECT_V3_NEAR(m.boundsMax, 1, 1, 1, 0);
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    V3f a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
    V3f centre = (a + b + c) * (1.0f / 3.0f);
    EXPECT_GT(((b - a) % (c - a)) * centre, 0.0f) << "triangle " << t / 3 << " is not outward";
  }
  // lpfg: normalised plain sum of the triangle normals. A corner that is the fan pivot of all
  // three quads gets each face twice: (-1,-1,-1)/√3. Corner (1,-1,-1) is a pivot only on the
  // x = 1 face: (2,-1,-1)/√6.
  const float r3 = 1 / std::sqrt(3.0f), r6 = 1 / std::sqrt(6.0f);
  int v0 = findPosition(m, -1, -1, -1), v1 = findPosition(m, 1, -1, -1);
  ASSERT_GE(v0, 0);
  ASSERT_GE(v1, 0);
  EXPECT_V3_NEAR(m.normals[v0], -r3, -r3, -r3, 1e-6);
  EXPECT_V3_NEAR(m.normals[v1], 2 * r6, -r6, -r6, 1e-6);
}

std::string cubePlyBinary(bool littleEndian, bool withJunk) {
  std::string h = std::string("ply\nformat ") + (littleEndian ? "binary_little_endian" : "binary_big_endian") +
                  " 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n";
  if (withJunk) h += "element junk 2\nproperty list uchar short vals\nproperty double w\n";
  h += "element face 6\nproperty list uchar int vertex_indices\nproperty uchar flags\nend_header\n";
  std::string d = h;
  auto put = [&](const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    std::string b(c, n);
    const uint16_t one = 1;
    const bool hostLE = *reinterpret_cast<const uint8_t*>(&one) == 1;
    if (hostLE != littleEndian) std::reverse(b.begin(), b.end());
    d += b;
  };
  for (auto& v : kCube)
    for (float f : v) put(&f, 4);
  if (withJunk)
    for (int i = 0; i < 2; ++i) {
      uint8_t n = uint8_t(i + 1);
      put(&n, 1);
      for (int k = 0; k < n; ++k) {
        int16_t s = int16_t(-7 * k);
        put(&s, 2);
      }
      double w = 0.5;
      put(&w, 8);
    }
  for (auto& f : kCubeFaces) {
    uint8_t n = 4;
    put(&n, 1);
    for (int k : f) {
      int32_t i = k;
      put(&i, 4);
    }
    uint8_t flags = 9;
    put(&flags, 1);
  }
  return d;
}

std::string errorOf(llvm::Expected<MeshData> m) {
  if (m) return "";
  return llvm::toString(m.takeError());
}

}  // namespace

TEST(MeshFileObj, CubeQuadsTriangulated) {
  MeshData m = mustLoad(kDir + "cube.obj");
  checkCube(m);
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_TRUE(m.colors.empty());
  // Fan triangulation of the first quad 1 4 3 2.
  EXPECT_EQ(m.positions[m.indices[0]], V3f(-1, -1, -1));
  EXPECT_EQ(m.positions[m.indices[1]], V3f(-1, 1, -1));
  EXPECT_EQ(m.positions[m.indices[2]], V3f(1, 1, -1));
  EXPECT_EQ(m.positions[m.indices[3]], V3f(-1, -1, -1));
  EXPECT_EQ(m.positions[m.indices[4]], V3f(1, 1, -1));
  EXPECT_EQ(m.positions[m.indices[5]], V3f(1, -1, -1));
}

TEST(MeshFileObj, ScaleThenContact) {
  MeshLoadOptions o;
  o.scale = 2;
  o.contact = V3f(1, 0, 0);
  MeshData m = mustLoad(kDir + "cube.obj", o);
  EXPECT_V3_NEAR(m.boundsMin, -3, -2, -2, 0);
  EXPECT_V3_NEAR(m.boundsMax, 1, 2, 2, 0);
  int v = findPosition(m, 1, 2, 2);  // (1,1,1)·2 - (1,0,0)
  ASSERT_GE(v, 0);
  const float r3 = 1 / std::sqrt(3.0f);
  EXPECT_V3_NEAR(m.normals[v], r3, r3, r3, 1e-6);
}

TEST(MeshFileObj, PolygonFanAndRelativeIndices) {
  auto m = parseObj("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\nf -5 -4 -3\n", "pent.obj");
  ASSERT_TRUE(bool(m)) << llvm::toString(m.takeError());
  ASSERT_EQ(m->indices.size(), 12u);
  const uint32_t expect[9] = {0, 1, 2, 0, 2, 3, 0, 3, 4};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(m->indices[i], expect[i]);
  EXPECT_EQ(m->indices[9], 0u);
  EXPECT_EQ(m->indices[10], 1u);
  EXPECT_EQ(m->indices[11], 2u);
  for (auto& n : m->normals) EXPECT_V3_NEAR(n, 0, 0, 1, 1e-6);
}

TEST(MeshFileObj, TextureCoordinatesAndSeams) {
  MeshData m = mustLoad(kDir + "textured.obj");
  // (position, uv) pairs: the 4 quad corners plus position 1 again with uv 5.
  ASSERT_EQ(m.positions.size(), 5u);
  ASSERT_EQ(m.uvs.size(), 5u);
  EXPECT_EQ(m.triangleCount(), 3u);
  const float uv[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}};
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(m.uvs[i].x, uv[i][0], 0);
    EXPECT_NEAR(m.uvs[i].y, uv[i][1], 0);
  }
  EXPECT_EQ(m.positions[4], m.positions[0]);
  EXPECT_EQ(m.normals[4], m.normals[0]);  // normals are shared per file position
  EXPECT_V3_NEAR(m.normals[0], 0, 0, 1, 1e-6);

  MeshLoadOptions o;
  o.fileNormals = true;
  MeshData f = mustLoad(kDir + "textured.obj", o);
  EXPECT_EQ(f.positions.size(), 5u);
  EXPECT_V3_NEAR(f.normals[2], 0, 0, 1, 0);
}

TEST(MeshFilePly, AsciiCube) {
  MeshData m = mustLoad(kDir + "cube_ascii.ply");
  checkCube(m);
}

TEST(MeshFilePly, BinaryLittleAndBigEndianCube) {
  for (bool le : {true, false})
    for (bool junk : {false, true}) {
      SCOPED_TRACE(std::string(le ? "little" : "big") + (junk ? " with junk" : ""));
      auto m = parsePly(cubePlyBinary(le, junk), "cube.ply");
      ASSERT_TRUE(bool(m)) << llvm::toString(m.takeError());
      checkCube(*m);
    }
  // Through loadMesh, from a file.
  const std::string path = testing::TempDir() + "/lcjit_mesh_cube_be.ply";
  {
    std::ofstream out(path, std::ios::binary);
    std::string d = cubePlyBinary(false, true);
    out.write(d.data(), std::streamsize(d.size()));
  }
  checkCube(mustLoad(path));
  std::remove(path.c_str());
}

TEST(MeshFilePly, NormalsTexcoordsColours) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
      "property list uchar uint vertex_index\nend_header\n"
      "0 0 0 0 0 2 0 0 255 0 0\n1 0 0 0 0 2 1 0 0 255 0\n0 1 0 0 0 2 0 1 0 0 51\n3 0 1 2\n";
  auto m = parsePly(ply, "attrs.ply");
  ASSERT_TRUE(bool(m)) << llvm::toString(m.takeError());
  ASSERT_EQ(m->uvs.size(), 3u);
  EXPECT_EQ(m->uvs[1].x, 1.0f);
  EXPECT_EQ(m->uvs[2].y, 1.0f);
  ASSERT_EQ(m->colors.size(), 3u);
  EXPECT_V3_NEAR(m->colors[0], 1, 0, 0, 0);
  EXPECT_V3_NEAR(m->colors[2], 0, 0, 0.2f, 1e-6);
  EXPECT_V3_NEAR(m->normals[1], 0, 0, 1, 1e-6);  // computed (lpfg)
  MeshLoadOptions o;
  o.fileNormals = true;
  auto f = parsePly(ply, "attrs.ply", o);
  ASSERT_TRUE(bool(f));
  EXPECT_V3_NEAR(f->normals[1], 0, 0, 1, 0);  // the file's, normalised
}

TEST(MeshFileErrors, TruncatedAndGarbage) {
  std::string bin = cubePlyBinary(true, true);
  std::string e = errorOf(parsePly(bin.substr(0, bin.size() - 5), "cut.ply"));
  EXPECT_NE(e.find("cut.ply"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  // Every prefix fails cleanly or parses; none crashes.
  for (size_t n = 0; n < bin.size(); n += 3) (void)errorOf(parsePly(bin.substr(0, n), "prefix.ply"));

  e = errorOf(parsePly("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                       "range.ply"));
  EXPECT_NE(e.find("range.ply:13:"), std::string::npos) << e;
  EXPECT_NE(e.find("face index 7 out of range"), std::string::npos) << e;
  // An index beyond every integer type is named as written (fuzz_ply: it was converted to long
  // long unchecked), as is a fractional one.
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n";
  e = errorOf(parsePly(header + "3 0 1 3777777777777777777777777777777777777777\n", "huge.ply"));
  EXPECT_NE(e.find("huge.ply:13: error: face index 3.77777777777777"), std::string::npos) << e;
  e = errorOf(parsePly(header + "3 0 1 1.5\n", "half.ply"));
  EXPECT_NE(e.find("face index 1.5 out of range"), std::string::npos) << e;
  e = errorOf(parsePly("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "hdr.ply"));
  EXPECT_NE(e.find("end_header"), std::string::npos) << e;
  e = errorOf(parsePly("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nend_header\n1\n", "big.ply"));
  EXPECT_FALSE(e.empty());
  e = errorOf(parsePly("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                       "property float z\nend_header\n0 zero 0\n",
                       "nan.ply"));
  EXPECT_NE(e.find("nan.ply:8:"), std::string::npos) << e;
  EXPECT_FALSE(errorOf(parsePly("garbage", "g.ply")).empty());
  EXPECT_FALSE(errorOf(parsePly("ply\nformat weird 1.0\nend_header\n", "fmt.ply")).empty());

  e = errorOf(parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n# fine so far\nf 1 2 9\n", "range.obj"));
  EXPECT_NE(e.find("range.obj:6:"), std::string::npos) << e;
  e = errorOf(parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/4 2 3\n", "uv.obj"));
  EXPECT_NE(e.find("uv.obj:4:"), std::string::npos) << e;
  e = errorOf(parseObj("this is not an obj file\n\x01\x02\xff", "garbage.obj"));
  EXPECT_NE(e.find("no faces"), std::string::npos) << e;
  EXPECT_FALSE(errorOf(parseObj("", "empty.obj")).empty());
  EXPECT_FALSE(errorOf(parseObj("v 0 0 0\nf 1 0 1\n", "zero.obj")).empty());
  e = errorOf(loadMesh(kDir + "missing.obj"));
  EXPECT_NE(e.find("missing.obj"), std::string::npos) << e;
}
