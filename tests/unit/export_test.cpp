// Exporters (runtime/export): a hand-made Geometry written in every format and read back —
// OBJ with tinyobjloader, glTF/GLB with tinygltf, PLY/STL with the small readers below, SVG,
// PostScript and POV-Ray by counting their elements and reading their coordinates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
#include <tiny_gltf.h>

#include "runtime/export/Export.h"

using namespace lcjit::runtime;
namespace fs = std::filesystem;

namespace {

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

size_t countOf(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

std::string hex(const std::array<float, 4>& c) {
  char buf[8];
  auto b = [](float f) { return (int)std::lround(std::clamp(f, 0.0f, 1.0f) * 255); };
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", b(c[0]), b(c[1]), b(c[2]));
  return buf;
}

// The test scene (model units; the camera below shows x, y ∈ [0, 4] in a 400 × 400 window):
//   a unit quad (two triangles) of colour 2 at z = 0, normals +z;
//   a triangle of colour 5 at z = 1..2 with zero normals (drawn unlit), nearest the viewer;
//   a triangle of colour 2 with texture 0;
//   segments: a chain (0,0,0)→(0,2,0)→(0,3,0) of colour 3, width 2, and (2,0,0)→(2,1,0) colour 4;
//   a disc of colour 6 at (3,3,0), radius 0.5; a label of colour 7 at (1,1,0).
constexpr int kMeshTriangles = 4, kDiscSides = 32;

Geometry makeGeometry() {
  Geometry g;
  auto vtx = [&](V3f p, V3f n, int color, V2f uv = V2f(0, 0)) {
    MeshVertex v;
    v.position = p;
    v.normal = n;
    v.color = color;
    v.uv = uv;
    return g.addVertex(v);
  };
  V3f up(0, 0, 1), none(0, 0, 0);
  uint32_t a = vtx({0, 0, 0}, up, 2), b = vtx({1, 0, 0}, up, 2), c = vtx({1, 1, 0}, up, 2), d = vtx({0, 1, 0}, up, 2);
  g.addTriangle(a, b, c);
  g.addTriangle(a, c, d);
  uint32_t e = vtx({2, 2, 1}, none, 5), f = vtx({3, 2, 1}, none, 5), h = vtx({2, 3, 2}, none, 5);
  g.addTriangle(e, f, h);
  g.useTexture(0);
  uint32_t i = vtx({1, 2, 0}, up, 2, {0, 0}), j = vtx({2, 2, 0}, up, 2, {1, 0}), k = vtx({1, 3, 0}, up, 2, {0, 1});
  g.addTriangle(i, j, k);
  g.useTexture(-1);
  g.segments.push_back({{0, 0, 0}, {0, 2, 0}, 2, 3});
  g.segments.push_back({{0, 2, 0}, {0, 3, 0}, 2, 3});
  g.segments.push_back({{2, 0, 0}, {2, 1, 0}, 1, 4});
  g.discs.push_back({{3, 3, 0}, 0, 0.5f, 6});
  g.labels.push_back({{1, 1, 0}, "A<b>&(c)", 7});
  return g;
}

CameraMatrices makeCamera() {
  CameraMatrices cam;
  cam.width = cam.height = 400;
  cam.eye = {2, 2, 10};
  cam.viewDirection = {0, 0, -1};
  cam.view = glm::lookAt(glm::vec3(2, 2, 10), glm::vec3(2, 2, 0), glm::vec3(0, 1, 0));
  cam.projection = glm::ortho(-2.0f, 2.0f, -2.0f, 2.0f, 1.0f, 20.0f);
  cam.perspective = false;
  return cam;
}

// Where the camera puts a model point, in window pixels (x right, y down).
std::pair<float, float> window(float x, float y) { return {x * 100, 400 - y * 100}; }

class ExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("lcjit_export_test_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    // A colormap with a distinct colour per index.
    std::string map(768, '\0');
    for (int i = 0; i < 256; ++i) {
      map[3 * i] = (char)i;
      map[3 * i + 1] = (char)(255 - i);
      map[3 * i + 2] = (char)((i * 37) & 255);
    }
    std::ofstream(dir / "colors.map", std::ios::binary) << map;
    llvm::Error err = palette.loadColormap((dir / "colors.map").string());
    ASSERT_FALSE((bool)err) << llvm::toString(std::move(err));
    static const unsigned char png[] = {0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49,
                                        0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06,
                                        0x00, 0x00, 0x00, 0x1F, 0x15, 0xC4, 0x89, 0x00, 0x00, 0x00, 0x0A, 0x49, 0x44,
                                        0x41, 0x54, 0x78, 0x9C, 0x63, 0x00, 0x01, 0x00, 0x00, 0x05, 0x00, 0x01, 0x0D,
                                        0x0A, 0x2D, 0xB4, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42,
                                        0x60, 0x82};
    std::ofstream(dir / "leaf.png", std::ios::binary).write((const char*)png, sizeof png);
    geometry = makeGeometry();
    in.geometry = &geometry;
    in.palette = &palette;
    in.view = &view;
    in.camera = makeCamera();
    in.width = in.height = 400;
    in.textureFiles = {"leaf.png"};
    in.textureDirectory = dir.string();
    in.discSegments = kDiscSides;
  }
  // LCJIT_KEEP_EXPORT_TEST=1 keeps the files to look at.
  void TearDown() override {
    if (!std::getenv("LCJIT_KEEP_EXPORT_TEST")) fs::remove_all(dir);
  }

  fs::path exportTo(const std::string& name) {
    fs::path p = dir / name;
    llvm::Error err = exportGeometry(p.string(), in);
    EXPECT_FALSE((bool)err) << llvm::toString(std::move(err));
    EXPECT_TRUE(fs::exists(p)) << p;
    return p;
  }
  std::array<float, 4> color(int i) const { return palette.color(i); }

  // The bounds every mesh format should reproduce: all vertices, segment ends, the disc's rim
  // (in the camera's x/y plane, so z stays at the centre).
  Bounds meshBounds() const {
    Bounds b;
    for (const MeshVertex& v : geometry.vertices) b.add(v.position);
    for (const Segment& s : geometry.segments) b.add(s.from), b.add(s.to);
    for (const Disc& d : geometry.discs) {
      b.add(d.center + V3f(d.outer, d.outer, 0));
      b.add(d.center - V3f(d.outer, d.outer, 0));
    }
    return b;
  }

  fs::path dir;
  Palette palette;
  ViewSettings view;
  Geometry geometry;
  ExportInput in;
};

void expectBounds(const Bounds& got, const Bounds& want, float tol = 1e-5f) {
  EXPECT_NEAR(got.min.x, want.min.x, tol);
  EXPECT_NEAR(got.min.y, want.min.y, tol);
  EXPECT_NEAR(got.min.z, want.min.z, tol);
  EXPECT_NEAR(got.max.x, want.max.x, tol);
  EXPECT_NEAR(got.max.y, want.max.y, tol);
  EXPECT_NEAR(got.max.z, want.max.z, tol);
}

void expectColor(const float* got, const std::array<float, 4>& want, float tol = 1e-5f) {
  EXPECT_NEAR(got[0], want[0], tol);
  EXPECT_NEAR(got[1], want[1], tol);
  EXPECT_NEAR(got[2], want[2], tol);
}

// ---------------------------------------------------------------------------------------------

TEST(ExportFormat, ByExtension) {
  EXPECT_TRUE(isExportFormat("obj"));
  EXPECT_TRUE(isExportFormat(".GLB"));
  EXPECT_TRUE(isExportFormat("out/tree.Svg"));
  EXPECT_TRUE(isExportFormat("a.b/c.eps"));
  EXPECT_FALSE(isExportFormat("png"));
  EXPECT_FALSE(isExportFormat("tree.obj.txt"));
  EXPECT_FALSE(isExportFormat("dir.obj/tree"));
  EXPECT_EQ(exportFormatFor("x.ply"), ExportFormat::Ply);
  EXPECT_EQ(exportFormatFor("x.gltf"), ExportFormat::Gltf);
  EXPECT_EQ(exportFormatFor("x.pov"), ExportFormat::Pov);
  EXPECT_STREQ(exportFormatExtension(ExportFormat::Stl), "stl");
}

TEST_F(ExportTest, Errors) {
  llvm::Error e = exportGeometry((dir / "tree.xyz").string(), in);
  ASSERT_TRUE((bool)e);
  std::string msg = llvm::toString(std::move(e));
  EXPECT_NE(msg.find("tree.xyz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown"), std::string::npos) << msg;

  for (const char* name : {"tree.obj", "tree.ply", "tree.stl", "tree.gltf", "tree.glb", "tree.svg", "tree.ps", "tree.pov"}) {
    std::string path = (dir / "no such dir" / name).string();
    llvm::Error err = exportGeometry(path, in);
    ASSERT_TRUE((bool)err) << name;
    std::string m = llvm::toString(std::move(err));
    EXPECT_NE(m.find("no such dir"), std::string::npos) << m;
  }
  geometry.indices.push_back(999);
  geometry.indices.push_back(0);
  geometry.indices.push_back(1);
  llvm::Error bad = exportGeometry((dir / "bad.obj").string(), in);
  ASSERT_TRUE((bool)bad);
  EXPECT_NE(llvm::toString(std::move(bad)).find("999"), std::string::npos);
  ExportInput none;
  EXPECT_TRUE((bool)llvm::errorToBool(exportGeometry((dir / "x.obj").string(), none)));
}

TEST_F(ExportTest, Obj) {
  fs::path p = exportTo("tree.obj");
  ASSERT_TRUE(fs::exists(dir / "tree.mtl"));
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, p.string().c_str(), dir.string().c_str()))
      << err;
  EXPECT_TRUE(err.empty()) << err;

  const size_t discVertices = kDiscSides + 1;
  const size_t segmentPoints = 3 + 2;  // the chain shares its middle point
  EXPECT_EQ(attrib.vertices.size() / 3, geometry.vertices.size() + discVertices + segmentPoints);
  EXPECT_EQ(attrib.normals.size() / 3, geometry.vertices.size() + discVertices);
  EXPECT_EQ(attrib.texcoords.size() / 2, geometry.vertices.size() + discVertices);
  Bounds b;
  for (size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
    b.add(V3f(attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]));
  expectBounds(b, meshBounds());
  for (size_t i = 0; i + 2 < attrib.normals.size(); i += 3)
    EXPECT_NEAR(std::hypot(attrib.normals[i], attrib.normals[i + 1], attrib.normals[i + 2]), 1, 1e-5);

  std::map<std::string, int> materialIndex;
  for (size_t i = 0; i < materials.size(); ++i) materialIndex[materials[i].name] = (int)i;
  for (const char* name : {"s002", "s005", "s002_t0", "s006", "s003", "s004"})
    EXPECT_TRUE(materialIndex.count(name)) << name;
  EXPECT_EQ(materials.size(), 6u);
  for (auto [name, index] : std::map<std::string, int>{{"s002", 2}, {"s005", 5}, {"s006", 6}, {"s003", 3}, {"s004", 4}})
    expectColor(materials[materialIndex[name]].diffuse, color(index));
  EXPECT_EQ(materials[materialIndex["s002_t0"]].diffuse_texname, "leaf.png");
  EXPECT_TRUE(materials[materialIndex["s002"]].diffuse_texname.empty());

  size_t faces = 0, lineSegments = 0;
  std::map<std::string, int> facesPerMaterial;
  for (const tinyobj::shape_t& s : shapes) {
    faces += s.mesh.num_face_vertices.size();
    for (int id : s.mesh.material_ids) facesPerMaterial[id >= 0 ? materials[id].name : "?"]++;
    for (int n : s.lines.num_line_vertices) lineSegments += n - 1;
  }
  EXPECT_EQ(faces, kMeshTriangles + kDiscSides);
  EXPECT_EQ(facesPerMaterial["s002"], 2);
  EXPECT_EQ(facesPerMaterial["s005"], 1);
  EXPECT_EQ(facesPerMaterial["s002_t0"], 1);
  EXPECT_EQ(facesPerMaterial["s006"], kDiscSides);
  EXPECT_EQ(lineSegments, geometry.segments.size());

  std::string text = readAll(p);
  EXPECT_NE(text.find("mtllib tree.mtl"), std::string::npos);
  EXPECT_EQ(countOf(text, "\nl "), 2u);  // two polylines
}

// ---------------------------------------------------------------------------------------------
// A small PLY reader: header, then vertex/face/edge elements (binary little endian or ASCII).

struct PlyData {
  std::vector<std::string> vertexProps;
  std::vector<std::vector<double>> vertices;  // every vertex property as double
  std::vector<std::vector<uint32_t>> faces;
  std::vector<std::vector<double>> edges;
  std::vector<std::string> comments;
  size_t prop(const std::string& name) const {
    return std::find(vertexProps.begin(), vertexProps.end(), name) - vertexProps.begin();
  }
};

PlyData readPly(const fs::path& p) {
  std::string data = readAll(p);
  size_t end = data.find("end_header\n");
  EXPECT_NE(end, std::string::npos);
  std::istringstream header(data.substr(0, end));
  std::string line, format;
  struct Element {
    std::string name;
    size_t count;
    std::vector<std::pair<std::string, std::string>> props;  // type, name ("list" types joined)
  };
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (word == "comment") {
      continue;
    } else if (word == "element") {
      Element e;
      ls >> e.name >> e.count;
      elements.push_back(e);
    } else if (word == "property") {
      std::string type, name;
      ls >> type;
      if (type == "list") {
        std::string a, b;
        ls >> a >> b >> name;
        type = "list " + a + " " + b;
      } else {
        ls >> name;
      }
      elements.back().props.push_back({type, name});
    }
  }
  PlyData out;
  {
    std::istringstream hs(data.substr(0, end));
    while (std::getline(hs, line))
      if (line.rfind("comment ", 0) == 0) out.comments.push_back(line.substr(8));
  }
  const bool ascii = format == "ascii";
  EXPECT_TRUE(ascii || format == "binary_little_endian") << format;
  size_t at = end + std::strlen("end_header\n");
  std::istringstream text(ascii ? data.substr(at) : std::string());
  auto scalar = [&](const std::string& type) -> double {
    if (ascii) {
      double v;
      text >> v;
      return v;
    }
    auto take = [&](auto v) {
      std::memcpy(&v, data.data() + at, sizeof v);
      at += sizeof v;
      return (double)v;
    };
    if (type == "float") return take(float());
    if (type == "double") return take(double());
    if (type == "uchar") return take(uint8_t());
    if (type == "int") return take(int32_t());
    if (type == "uint") return take(uint32_t());
    ADD_FAILURE() << "type " << type;
    return 0;
  };
  for (const Element& e : elements) {
    for (size_t i = 0; i < e.count; ++i) {
      std::vector<double> values;
      std::vector<uint32_t> list;
      for (auto& [type, name] : e.props) {
        if (type.rfind("list", 0) == 0) {
          std::istringstream ts(type);
          std::string l, countType, itemType;
          ts >> l >> countType >> itemType;
          size_t n = (size_t)scalar(countType);
          for (size_t k = 0; k < n; ++k) list.push_back((uint32_t)scalar(itemType));
        } else {
          values.push_back(scalar(type));
        }
      }
      if (e.name == "vertex") out.vertices.push_back(values);
      else if (e.name == "face") out.faces.push_back(list);
      else if (e.name == "edge") out.edges.push_back(values);
    }
    if (e.name == "vertex")
      for (auto& pr : e.props) out.vertexProps.push_back(pr.second);
  }
  if (!ascii) {
    EXPECT_EQ(at, data.size());
  }
  return out;
}

void checkPly(const PlyData& ply, const Geometry& g, const Palette& palette, const Bounds& want) {
  const size_t disc = kDiscSides + 1, points = 5;
  ASSERT_EQ(ply.vertices.size(), g.vertices.size() + disc + points);
  EXPECT_EQ(ply.faces.size(), size_t(kMeshTriangles + kDiscSides));
  EXPECT_EQ(ply.edges.size(), g.segments.size());
  for (const auto& f : ply.faces) {
    ASSERT_EQ(f.size(), 3u);
    for (uint32_t i : f) EXPECT_LT(i, ply.vertices.size());
  }
  size_t x = ply.prop("x"), red = ply.prop("red"), s = ply.prop("s");
  ASSERT_LT(red, ply.vertexProps.size());
  EXPECT_LT(s, ply.vertexProps.size());  // textured: s, t present
  Bounds b;
  for (const auto& v : ply.vertices) b.add(V3f((float)v[x], (float)v[x + 1], (float)v[x + 2]));
  expectBounds(b, want);
  // Vertex colours: the quad's first vertex is colour 2, the colour-5 triangle's is 5.
  for (auto [vertex, index] : std::vector<std::pair<int, int>>{{0, 2}, {4, 5}}) {
    auto c = palette.color(index);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ply.vertices[vertex][red + k], std::lround(c[k] * 255), 0.5);
  }
  // Edges: colour of the chain (3) then of the single segment (4), indices past the mesh vertices.
  auto c3 = palette.color(3), c4 = palette.color(4);
  EXPECT_NEAR(ply.edges[0][2], std::lround(c3[0] * 255), 0.5);
  EXPECT_NEAR(ply.edges[2][3], std::lround(c4[1] * 255), 0.5);
  for (const auto& e : ply.edges) {
    EXPECT_GE(e[0], g.vertices.size() + disc);
    EXPECT_LT(e[1], ply.vertices.size());
  }
  // Edge end points are the segments' ends.
  const auto& v0 = ply.vertices[(size_t)ply.edges[0][0]];
  const auto& v1 = ply.vertices[(size_t)ply.edges[0][1]];
  EXPECT_NEAR(v0[x + 1], 0, 1e-6);
  EXPECT_NEAR(v1[x + 1], 2, 1e-6);
}

TEST_F(ExportTest, PlyBinary) {
  PlyData ply = readPly(exportTo("tree.ply"));
  checkPly(ply, geometry, palette, meshBounds());
  EXPECT_NE(std::find(ply.comments.begin(), ply.comments.end(), "TextureFile leaf.png"), ply.comments.end());
}

TEST_F(ExportTest, PlyAscii) {
  in.ascii = true;
  fs::path p = exportTo("tree.ply");
  EXPECT_NE(readAll(p).find("format ascii 1.0"), std::string::npos);
  checkPly(readPly(p), geometry, palette, meshBounds());
}

// Explicit colours (kRgbColor | 0xRRGGBB: the terrain's grid, drawn as they are) keep their RGB in
// every format, in colormap mode and with materials: 0x123456 is 18 52 86, 0.0705882
// 0.203922 0.337255; palette entry 255 (what clamping the value as an index gives) is not used.
TEST_F(ExportTest, ExplicitColoursKeepTheirRgb) {
  Geometry g;
  const int rgb = rgbColor(0x12, 0x34, 0x56), line = rgbColor(0xAB, 0xCD, 0xEF);
  auto vtx = [&](V3f p) {
    MeshVertex v;
    v.position = p;
    v.normal = V3f(0, 0, 1);
    v.color = rgb;
    return g.addVertex(v);
  };
  g.addTriangle(vtx({0, 0, 0}), vtx({1, 0, 0}), vtx({0, 1, 0}));
  g.segments.push_back({{0, 0, 0}, {0, 2, 0}, 1, line});
  g.labels.push_back({{0, 0, 0}, "x", rgb});
  in.geometry = &g;
  for (bool materials : {false, true}) {
    SCOPED_TRACE(materials ? "materials" : "colormap");
    if (materials) {  // entry 255 red: {index, transparency, ambient, diffuse, emission, specular, shininess}
      const unsigned char record[15] = {255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 0, 0, 0, 0, 0};
      std::ofstream(dir / "red.mat", std::ios::binary).write((const char*)record, sizeof record);
      llvm::Error e = palette.loadMaterials((dir / "red.mat").string());
      ASSERT_FALSE((bool)e) << llvm::toString(std::move(e));
    }
    ASSERT_EQ(palette.usesMaterials(), materials);
    exportTo("rgb.obj");
    std::string mtl = readAll(dir / "rgb.mtl");
    EXPECT_NE(mtl.find("newmtl rgb_123456\n"), std::string::npos) << mtl;
    EXPECT_NE(mtl.find("Kd 0.07058824 0.20392157 0.3372549\n"), std::string::npos) << mtl;
    EXPECT_NE(mtl.find("newmtl rgb_ABCDEF\n"), std::string::npos) << mtl;
    EXPECT_EQ(mtl.find("s255"), std::string::npos) << mtl;
    in.ascii = true;
    std::string ply = readAll(exportTo("rgb.ply"));
    in.ascii = false;
    EXPECT_NE(ply.find(" 18 52 86 255\n"), std::string::npos) << ply;
    EXPECT_NE(ply.find(" 171 205 239 255\n"), std::string::npos) << ply;
    std::string gltf = readAll(exportTo("rgb.gltf"));
    EXPECT_NE(gltf.find("\"rgb_123456\""), std::string::npos);
    EXPECT_NE(gltf.find("0.0705882"), std::string::npos);
    std::string pov = readAll(exportTo("rgb.pov"));
    EXPECT_NE(pov.find("#declare rgb_123456 = texture { pigment { srgbt <0.07058824,0.20392157,0.3372549,0> }"),
              std::string::npos) << pov;
    // Used by what has the colour: the mesh's texture list, the segment's cylinder; the glTF's
    // triangle and line primitives.
    EXPECT_NE(pov.find("texture { rgb_123456 }"), std::string::npos);
    EXPECT_NE(pov.find("texture { rgb_ABCDEF } }"), std::string::npos);
    EXPECT_NE(pov.find("#declare text_rgb_123456 = texture { pigment { srgb <0.07058824,0.20392157,0.3372549> }"),
              std::string::npos);  // the label's
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, (dir / "rgb.gltf").string())) << err;
    ASSERT_EQ(model.meshes.size(), 1u);
    std::map<int, std::string> materialOf;  // primitive mode → its material's name
    for (const tinygltf::Primitive& p : model.meshes[0].primitives) materialOf[p.mode] = model.materials[p.material].name;
    EXPECT_EQ(materialOf[TINYGLTF_MODE_TRIANGLES], "rgb_123456");
    EXPECT_EQ(materialOf[TINYGLTF_MODE_LINE], "rgb_ABCDEF");
    // STL's VisCAM word: 5 bits of each, 18/255·31 → 2, 52/255·31 → 6, 86/255·31 → 10.
    std::string stl = readAll(exportTo("rgb.stl"));
    ASSERT_EQ(stl.size(), 84u + 50u);
    uint16_t attr;
    std::memcpy(&attr, stl.data() + 84 + 48, 2);
    EXPECT_EQ(attr, 0x8000 | 2 << 10 | 6 << 5 | 10);
    // The 2D formats: the colours themselves (SVG's hex; PostScript's and PDF's numbers to 1/1000).
    std::string svg = readAll(exportTo("rgb.svg"));
    EXPECT_NE(svg.find("{fill:#123456}"), std::string::npos);
    EXPECT_NE(svg.find("{stroke:#abcdef}"), std::string::npos);
    EXPECT_NE(readAll(exportTo("rgb.eps")).find("\n0.071 0.204 0.337 "), std::string::npos);
    EXPECT_NE(readAll(exportTo("rgb.pdf")).find("\n0.671 0.804 0.937 RG "), std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------

TEST_F(ExportTest, StlBinary) {
  std::string data = readAll(exportTo("tree.stl"));
  ASSERT_GE(data.size(), 84u);
  EXPECT_NE(data.substr(0, 5), "solid");
  uint32_t n;
  std::memcpy(&n, data.data() + 80, 4);
  EXPECT_EQ(n, uint32_t(kMeshTriangles + kDiscSides));
  ASSERT_EQ(data.size(), 84u + 50u * n);
  Bounds b;
  std::map<int, int> perColor;
  for (uint32_t t = 0; t < n; ++t) {
    float f[12];
    std::memcpy(f, data.data() + 84 + 50 * t, 48);
    EXPECT_NEAR(std::hypot(f[0], f[1], f[2]), 1, 1e-5);
    for (int k = 1; k < 4; ++k) b.add(V3f(f[3 * k], f[3 * k + 1], f[3 * k + 2]));
    uint16_t attr;
    std::memcpy(&attr, data.data() + 84 + 50 * t + 48, 2);
    EXPECT_TRUE(attr & 0x8000);
    perColor[attr]++;
  }
  // No segments in STL: bounds are the triangles' (mesh vertices and the disc).
  Bounds want;
  for (const MeshVertex& v : geometry.vertices) want.add(v.position);
  want.add(V3f(2.5f, 2.5f, 0)), want.add(V3f(3.5f, 3.5f, 0));
  expectBounds(b, want);
  auto word = [&](int i) {
    auto c = color(i);
    auto five = [](float x) { return (int)std::lround(x * 31); };
    return 0x8000 | five(c[0]) << 10 | five(c[1]) << 5 | five(c[2]);
  };
  EXPECT_EQ(perColor[word(2)], 3);
  EXPECT_EQ(perColor[word(5)], 1);
  EXPECT_EQ(perColor[word(6)], kDiscSides);
}

// A model drawn only with lines has nothing STL can hold: the file has no triangle, and the
// exporter says so instead of leaving it silently empty; a mesh says nothing.
TEST_F(ExportTest, StlOfLinesOnlySaysSo) {
  std::string note;
  in.note = &note;
  exportTo("tree.stl");
  EXPECT_EQ(note, "");
  Geometry lines;
  lines.segments.push_back({V3f(0, 0, 0), V3f(0, 1, 0)});
  lines.segments.push_back({V3f(0, 1, 0), V3f(1, 1, 0)});
  in.geometry = &lines;
  fs::path p = exportTo("lines.stl");
  std::string data = readAll(p);
  ASSERT_EQ(data.size(), 84u);  // the header and a count of 0
  EXPECT_EQ(data.substr(80, 4), std::string(4, '\0'));
  EXPECT_EQ(note, p.string() + " holds no triangles: STL keeps only surfaces, and the model draws 2 line segments "
                               "and no surface (.obj, .ply and .gltf keep lines)");
}

TEST_F(ExportTest, StlAscii) {
  in.ascii = true;
  std::string text = readAll(exportTo("tree.stl"));
  EXPECT_EQ(text.rfind("solid lcjit", 0), 0u);
  EXPECT_EQ(countOf(text, "facet normal"), size_t(kMeshTriangles + kDiscSides));
  EXPECT_EQ(countOf(text, "vertex "), size_t(3 * (kMeshTriangles + kDiscSides)));
  EXPECT_NE(text.find("endsolid"), std::string::npos);
  // The quad's normal is +z.
  EXPECT_NE(text.find("facet normal 0 0 1\n"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------

// `embedded`: the texture's bytes (a .glb carries them); "": the image refers to the file.
void checkGltf(const tinygltf::Model& model, const Geometry& g, const Palette& palette, const Bounds& want,
               const std::string& embedded = "") {
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.nodes.size(), 1u);
  const tinygltf::Mesh& mesh = model.meshes[0];
  std::map<std::string, int> trianglesPerMaterial;
  size_t lineIndices = 0;
  Bounds b;
  for (const tinygltf::Primitive& p : mesh.primitives) {
    const tinygltf::Accessor& pos = model.accessors[p.attributes.at("POSITION")];
    ASSERT_EQ(pos.minValues.size(), 3u);
    b.add(V3f((float)pos.minValues[0], (float)pos.minValues[1], (float)pos.minValues[2]));
    b.add(V3f((float)pos.maxValues[0], (float)pos.maxValues[1], (float)pos.maxValues[2]));
    const tinygltf::Accessor& idx = model.accessors[p.indices];
    EXPECT_EQ(idx.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    // Every index is within the position accessor.
    const tinygltf::BufferView& view = model.bufferViews[idx.bufferView];
    const uint32_t* data =
        reinterpret_cast<const uint32_t*>(model.buffers[view.buffer].data.data() + view.byteOffset + idx.byteOffset);
    for (size_t i = 0; i < idx.count; ++i) EXPECT_LT(data[i], pos.count);
    const tinygltf::Material& m = model.materials.at(p.material);
    if (p.mode == TINYGLTF_MODE_TRIANGLES) {
      EXPECT_TRUE(p.attributes.count("NORMAL"));
      EXPECT_TRUE(p.attributes.count("TEXCOORD_0"));
      trianglesPerMaterial[m.name] += (int)idx.count / 3;
    } else {
      EXPECT_EQ(p.mode, TINYGLTF_MODE_LINE);
      lineIndices += idx.count;
    }
    // Base colour = the palette colour of the material's index (sNNN).
    int index = std::stoi(m.name.substr(1, 3));
    auto c = palette.color(index);
    ASSERT_EQ(m.pbrMetallicRoughness.baseColorFactor.size(), 4u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.pbrMetallicRoughness.baseColorFactor[k], c[k], 1e-5);
  }
  expectBounds(b, want);
  EXPECT_EQ(trianglesPerMaterial["s002"], 2);
  EXPECT_EQ(trianglesPerMaterial["s005"], 1);
  EXPECT_EQ(trianglesPerMaterial["s002_t0"], 1);
  EXPECT_EQ(trianglesPerMaterial["s006"], kDiscSides);
  EXPECT_EQ(lineIndices, 2 * g.segments.size());
  // The textured material refers to the texture file, or carries it.
  ASSERT_EQ(model.images.size(), 1u);
  if (embedded.empty()) {
    EXPECT_EQ(model.images[0].uri, "leaf.png");
  } else {
    EXPECT_EQ(model.images[0].uri, "");
    EXPECT_EQ(model.images[0].mimeType, "image/png");
    ASSERT_GE(model.images[0].bufferView, 0);
    const tinygltf::BufferView& v = model.bufferViews[model.images[0].bufferView];
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(model.buffers[v.buffer].data.data()) + v.byteOffset,
                          v.byteLength),
              embedded);
  }
  for (const tinygltf::Material& m : model.materials)
    EXPECT_EQ(m.pbrMetallicRoughness.baseColorTexture.index >= 0, m.name == "s002_t0") << m.name;
  // Unit normals everywhere (the zero ones were replaced).
  for (const tinygltf::Primitive& p : mesh.primitives) {
    if (!p.attributes.count("NORMAL")) continue;
    const tinygltf::Accessor& n = model.accessors[p.attributes.at("NORMAL")];
    const tinygltf::BufferView& view = model.bufferViews[n.bufferView];
    const float* f = reinterpret_cast<const float*>(model.buffers[view.buffer].data.data() + view.byteOffset);
    for (size_t i = 0; i < n.count; ++i) EXPECT_NEAR(std::hypot(f[3 * i], f[3 * i + 1], f[3 * i + 2]), 1, 1e-5);
  }
}

bool noImages(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

TEST_F(ExportTest, Glb) {
  fs::path p = exportTo("tree.glb");
  EXPECT_EQ(readAll(p).substr(0, 4), "glTF");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(noImages, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, p.string())) << err;
  // A .glb is one file: it carries its texture (not a path into the checkout).
  checkGltf(model, geometry, palette, meshBounds(), readAll(dir / "leaf.png"));
}

TEST_F(ExportTest, Gltf) {
  fs::path p = exportTo("tree.gltf");
  // The buffer is NAME.gltf.bin: NAME.bin is the binary string `-out NAME.bin` writes.
  EXPECT_TRUE(fs::exists(dir / "tree.gltf.bin"));
  EXPECT_FALSE(fs::exists(dir / "tree.bin"));
  EXPECT_NE(readAll(p).find("\"tree.gltf.bin\""), std::string::npos);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(noImages, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadASCIIFromFile(&model, &err, &warn, p.string())) << err;
  checkGltf(model, geometry, palette, meshBounds());
}

// ---------------------------------------------------------------------------------------------

std::vector<std::pair<float, float>> numbers(const std::string& s, const std::regex& pattern) {
  std::vector<std::pair<float, float>> out;
  for (std::sregex_iterator it(s.begin(), s.end(), pattern), end; it != end; ++it)
    out.push_back({std::stof((*it)[1]), std::stof((*it)[2])});
  return out;
}

bool near(std::pair<float, float> a, std::pair<float, float> b, float tol = 0.02f) {
  return std::fabs(a.first - b.first) <= tol && std::fabs(a.second - b.second) <= tol;
}

// The compact SVG read back: its colour classes, and every <path>'s subpaths as absolute points.
struct SvgPath {
  std::string cls, strokeWidth;
  std::vector<std::vector<std::pair<float, float>>> subpaths;
};
struct SvgPicture {
  std::map<std::string, std::string> color;  // class ("f3", "s3") → "#rrggbb"
  std::vector<SvgPath> paths;
  size_t groups = 0;
  size_t points() const {
    size_t n = 0;
    for (auto& p : paths)
      for (auto& s : p.subpaths) n += s.size();
    return n;
  }
};

// SVG path data with the commands lcjit writes (m M z, implicit linetos after a move).
std::vector<std::vector<std::pair<float, float>>> parsePathData(const std::string& d) {
  std::vector<std::vector<std::pair<float, float>>> out;
  float x = 0, y = 0, sx = 0, sy = 0;
  char command = 0;
  int pairInCommand = 0;
  size_t i = 0;
  auto number = [&]() {
    size_t start = i;
    if (d[i] == '-') ++i;
    while (i < d.size() && std::isdigit((unsigned char)d[i])) ++i;
    if (i < d.size() && d[i] == '.') {
      ++i;
      while (i < d.size() && std::isdigit((unsigned char)d[i])) ++i;
    }
    return std::stof(d.substr(start, i - start));
  };
  while (i < d.size()) {
    char c = d[i];
    if (c == ' ' || c == ',') {
      ++i;
    } else if (c == 'm' || c == 'M') {
      command = c, pairInCommand = 0, ++i;
    } else if (c == 'z' || c == 'Z') {
      x = sx, y = sy, ++i;
    } else {
      float a = number();
      while (i < d.size() && (d[i] == ' ' || d[i] == ',')) ++i;
      float b = number();
      bool relative = command == 'm' && !(out.empty() && pairInCommand == 0);
      x = relative ? x + a : a, y = relative ? y + b : b;
      if (pairInCommand++ == 0) out.push_back({}), sx = x, sy = y;
      out.back().push_back({x, y});
    }
  }
  return out;
}

SvgPicture readSvg(const std::string& svg) {
  SvgPicture pic;
  std::regex cls("\\.([fs][0-9a-f]+)\\{(?:fill|stroke):(#[0-9a-f]{6})\\}");
  for (std::sregex_iterator it(svg.begin(), svg.end(), cls), end; it != end; ++it) pic.color[(*it)[1]] = (*it)[2];
  // By hand: libstdc++'s regex recurses per character and overflows the stack on long paths. A
  // <path> without a class takes its group's (<g class=… stroke-width=…>).
  auto attribute = [](const std::string& element, const std::string& name) {
    size_t at = element.find(" " + name + "=\"");
    if (at == std::string::npos) return std::string();
    at += name.size() + 3;
    return element.substr(at, element.find('"', at) - at);
  };
  std::string groupClass, groupWidth;
  for (size_t at = svg.find('<'); at != std::string::npos; at = svg.find('<', at + 1)) {
    std::string element = svg.substr(at, svg.find('>', at) - at);
    if (element.rfind("<g class=", 0) == 0) {
      groupClass = attribute(element, "class"), groupWidth = attribute(element, "stroke-width");
      ++pic.groups;
    } else if (element == "</g") {
      groupClass.clear(), groupWidth.clear();
    } else if (element.rfind("<path ", 0) == 0) {
      SvgPath p;
      p.cls = attribute(element, "class");
      p.strokeWidth = attribute(element, "stroke-width");
      if (p.cls.empty()) p.cls = groupClass, p.strokeWidth = groupWidth;
      p.subpaths = parsePathData(attribute(element, "d"));
      pic.paths.push_back(std::move(p));
    }
  }
  return pic;
}

// The colour class of kind 'f' or 's' in a path's class list ("t f3 s3" → the colour of f3).
std::string classColor(const SvgPicture& pic, const SvgPath& p, char kind) {
  std::istringstream in(p.cls);
  for (std::string c; in >> c;)
    if (c[0] == kind && c.size() > 1 && pic.color.count(c)) return pic.color.at(c);
  return "";
}

TEST_F(ExportTest, Svg) {
  std::string svg = readAll(exportTo("tree.svg"));
  EXPECT_NE(svg.find("width=\"400\" height=\"400\" viewBox=\"0 0 400 400\""), std::string::npos);
  EXPECT_NE(svg.find("<rect id=\"background\" x=\"0\" y=\"0\" width=\"400\" height=\"400\" fill=\"" + hex(color(0)) + "\""),
            std::string::npos);
  SvgPicture pic = readSvg(svg);
  std::vector<std::pair<std::string, std::vector<std::pair<float, float>>>> triangles, lines;  // colour, points
  std::map<std::string, std::string> lineWidth;                                                // colour → width
  for (const SvgPath& p : pic.paths) {
    bool isTriangle = p.cls.rfind("t ", 0) == 0, isLine = p.cls.rfind("l ", 0) == 0;
    ASSERT_TRUE(isTriangle || isLine) << p.cls;
    for (auto& sub : p.subpaths) {
      if (isTriangle) {
        EXPECT_EQ(classColor(pic, p, 'f'), classColor(pic, p, 's'));  // outlined in its own colour
        triangles.push_back({classColor(pic, p, 'f'), sub});
      } else {
        lines.push_back({classColor(pic, p, 's'), sub});
        lineWidth[classColor(pic, p, 's')] = p.strokeWidth;
      }
    }
  }
  // The unit quad's two triangles share an edge: one 4-corner polygon. The others stay triangles.
  ASSERT_EQ(triangles.size(), size_t(kMeshTriangles - 1));
  ASSERT_EQ(lines.size(), geometry.segments.size());
  auto count = [](auto& items, const std::string& col) {
    return std::count_if(items.begin(), items.end(), [&](auto& t) { return t.first == col; });
  };
  EXPECT_EQ(count(triangles, hex(color(2))), 2);
  EXPECT_EQ(count(triangles, hex(color(5))), 1);
  EXPECT_EQ(triangles[0].second.size(), 4u);
  for (auto [x, y] : std::vector<std::pair<float, float>>{{0, 0}, {1, 0}, {1, 1}, {0, 1}})
    EXPECT_TRUE(std::any_of(triangles[0].second.begin(), triangles[0].second.end(),
                            [&](auto c) { return near(c, window(x, y), 0.051f); }));
  EXPECT_EQ(count(lines, hex(color(3))), 2);
  EXPECT_EQ(count(lines, hex(color(4))), 1);
  EXPECT_EQ(lineWidth[hex(color(3))], "2");
  EXPECT_EQ(lineWidth[hex(color(4))], "");  // SVG's default, 1
  EXPECT_EQ(countOf(svg, "<circle "), 1u);
  EXPECT_EQ(countOf(svg, "<text "), 1u);
  EXPECT_NE(svg.find(">A&lt;b&gt;&amp;(c)</text>"), std::string::npos);

  // Polygon corners are the projected vertices (to the file's 0.1 px).
  std::vector<std::pair<float, float>> corners;
  for (auto& [col, pts] : triangles) corners.insert(corners.end(), pts.begin(), pts.end());
  for (auto [x, y] : std::vector<std::pair<float, float>>{{0, 0}, {1, 0}, {1, 1}, {2, 2}, {3, 2}, {2, 3}, {1, 3}})
    EXPECT_TRUE(std::any_of(corners.begin(), corners.end(), [&](auto c) { return near(c, window(x, y), 0.051f); }))
        << x << "," << y;
  // Painter order: the colour-5 triangle is nearest the viewer, so it is drawn last.
  EXPECT_EQ(triangles.back().first, hex(color(5)));
  EXPECT_GT(svg.rfind("<g class=\"t"), svg.find("<text "));
  // Segment ends and the disc.
  ASSERT_EQ(lines[0].second.size(), 2u);
  EXPECT_TRUE(near(lines[0].second[0], window(0, 0)));
  EXPECT_TRUE(near(lines[0].second[1], window(0, 2)));
  auto circle = numbers(svg, std::regex("cx=\"([-0-9.]+)\" cy=\"([-0-9.]+)\""));
  ASSERT_EQ(circle.size(), 1u);
  EXPECT_TRUE(near(circle[0], window(3, 3)));
  EXPECT_NE(svg.find(" r=\"50\""), std::string::npos);
  // The label: left end at the anchor, baseline 2 px below it (as in the picture).
  auto text = numbers(svg, std::regex("<text class=\"f[0-9a-f]+\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\""));
  ASSERT_EQ(text.size(), 1u);
  EXPECT_TRUE(near(text[0], {window(1, 1).first, window(1, 1).second + 2}));
}

// Labels in any script: SVG and POV-Ray keep the text (UTF-8; SVG's escaped and well-formed XML
// even from bytes that are no UTF-8), PostScript and PDF draw the shaped glyphs' outlines, one
// filled path per glyph.
TEST_F(ExportTest, NonAsciiLabels) {
  const std::string mixed = "\xc3\xa9 \xc3\xbc \xc3\x9f \xce\xa9 \xe6\x9c\xa8";  // "é ü ß Ω 木"
  geometry.labels = {{{1, 1, 0}, mixed, 7}, {{2, 1, 0}, "bad\xff<\x01", 7}};
  fs::path svgFile = exportTo("u.svg");
  std::string svg = readAll(svgFile);
  EXPECT_NE(svg.find(">" + mixed + "</text>"), std::string::npos);
  EXPECT_NE(svg.find(">bad\xef\xbf\xbd&lt;</text>"), std::string::npos);  // U+FFFD; the control dropped
  ASSERT_EQ(std::system("command -v xmllint >/dev/null"), 0) << "xmllint (libxml2-utils; setup.sh installs it)";
  EXPECT_EQ(std::system(("xmllint --noout '" + svgFile.string() + "'").c_str()), 0);

  // Between a label's comment and the next label: its glyphs (five characters; spaces draw nothing).
  auto glyphs = [&](const std::string& file, const std::string& fill) {
    size_t from = file.find("% label: " + mixed + "\n");
    EXPECT_NE(from, std::string::npos);
    if (from == std::string::npos) return size_t(0);
    size_t to = file.find("% label: ", from + 1);
    std::string block = file.substr(from, to == std::string::npos ? std::string::npos : to - from);
    EXPECT_NE(block.find(" c "), std::string::npos);  // curves: outlines, not boxes
    return countOf(block, fill);
  };
  std::string ps = readAll(exportTo("u.ps")), pdf = readAll(exportTo("u.pdf"));
  EXPECT_EQ(glyphs(ps, "h\nfill\n"), 5u);
  EXPECT_EQ(glyphs(pdf, "h\nf\n"), 5u);
  EXPECT_EQ(glyphs(readAll(exportTo("u.eps")), "h\nfill\n"), 5u);
  EXPECT_EQ(pdf.find("/Font"), std::string::npos);  // nothing relies on a font
  // POV-Ray keeps the text, as UTF-8 in a scene that says so.
  std::string pov = readAll(exportTo("u.pov"));
  EXPECT_NE(pov.find("charset utf8"), std::string::npos);
  EXPECT_NE(pov.find("\"" + mixed + "\""), std::string::npos);
  EXPECT_NE(pov.find("\"bad\xef\xbf\xbd<\""), std::string::npos);
}

// A bushy picture's SVG: thousands of small triangles and chained segments in a few colours. The
// file stays within the bound the compact path syntax gives, and every point reads back, in
// order, within the file's precision (0.1 px: 0.05 px rounding).
TEST_F(ExportTest, SvgCompact) {
  Geometry g;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> where(0.2f, 3.8f), step(-0.04f, 0.04f);
  V3f up(0, 0, 1);
  std::vector<std::array<V3f, 3>> triangles;
  for (int color = 2; color <= 4; ++color)
    for (int i = 0; i < 2000; ++i) {
      V3f a(where(rng), where(rng), 0), b = a + V3f(step(rng), step(rng), 0), c = a + V3f(step(rng), step(rng), 0);
      if (((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) == 0) continue;  // not drawn
      MeshVertex va, vb, vc;
      va.position = a, vb.position = b, vc.position = c;
      va.normal = vb.normal = vc.normal = up;
      va.color = vb.color = vc.color = color;
      g.addTriangle(g.addVertex(va), g.addVertex(vb), g.addVertex(vc));
      triangles.push_back({a, b, c});
    }
  for (int color = 5; color <= 6; ++color) {
    V3f p(2, 2, 0);
    for (int i = 0; i < 3000; ++i) {
      V3f q = p + V3f(step(rng), step(rng), 0);
      q.x = std::clamp(q.x, 0.1f, 3.9f), q.y = std::clamp(q.y, 0.1f, 3.9f);
      g.segments.push_back({p, q, color == 5 ? 1.0f : 2.0f, color});
      p = q;
    }
  }
  in.geometry = &g;
  std::string svg = readAll(exportTo("bushy.svg"));
  SvgPicture pic = readSvg(svg);
  // One group per colour (all at one depth, so the painter's order keeps them in runs).
  EXPECT_EQ(pic.groups, 5u);
  // The bound: in a 400-pixel picture a number on the 0.1 px grid is at most 6 characters
  // ("-399.9"), so a triangle's element is at most '<path d="m' + 6 × (number + separator) + 'z"/>'
  // and a newline = 57 bytes and a segment's 10 + 4 × 7 + 4 = 42; each group adds at most 80 bytes,
  // the header 1000.
  const size_t bound = 1000 + 57 * triangles.size() + 42 * g.segments.size() + 80 * pic.groups;
  EXPECT_LE(svg.size(), bound);
  // With this scene's corners within 4 px (0.04 units) of the first, the relative numbers are at
  // most 4 characters ("-3.9"): a triangle '<path d="m' + 2 × (5 + 1) + 4 × (4 + 1) + 'z"/>\n' = 46
  // bytes, a segment 10 + 12 + 2 × 5 + 4 = 36. The former elements (<polygon points=… fill=…
  // stroke=…/>, <line x1=… y1=… x2=… y2=… stroke=… stroke-width=…/>) took about 100 bytes each.
  EXPECT_LE(svg.size(), 1000 + 46 * triangles.size() + 36 * g.segments.size() + 80 * pic.groups) << svg.size();
  // The geometry is all there: every triangle and segment, in drawing order, to 0.05 px.
  std::vector<std::pair<float, float>> want, got;
  for (auto& t : triangles)
    for (const V3f& p : t) want.push_back(window(p.x, p.y));
  for (const Segment& s : g.segments) want.push_back(window(s.from.x, s.from.y)), want.push_back(window(s.to.x, s.to.y));
  for (auto& p : pic.paths)
    for (auto& sub : p.subpaths) {
      EXPECT_EQ(sub.size(), p.cls.rfind("t ", 0) == 0 ? 3u : 2u);  // random triangles make no quads
      got.insert(got.end(), sub.begin(), sub.end());
    }
  ASSERT_EQ(got.size(), want.size());
  size_t off = 0;
  for (size_t i = 0; i < want.size(); ++i) off += !near(got[i], want[i], 0.05f + 1e-3f);
  EXPECT_EQ(off, 0u);
}

TEST_F(ExportTest, SvgBackfaceCulling) {
  view.backfaceCulling = true;
  // Turn the colour-5 triangle around: it faces away from the viewer now.
  std::swap(geometry.indices[6 + 1], geometry.indices[6 + 2]);
  std::string svg = readAll(exportTo("tree.svg"));
  SvgPicture pic = readSvg(svg);
  size_t triangles = 0;  // a polygon of n corners is n - 2 triangles
  for (auto& p : pic.paths)
    if (p.cls.rfind("t ", 0) == 0)
      for (auto& sub : p.subpaths) triangles += sub.size() - 2;
  EXPECT_EQ(triangles, size_t(kMeshTriangles - 1));
  EXPECT_EQ(countOf(svg, hex(color(5))), 0u);
}

// `shade`: Lambert shading with the view's lights (the default light shines along the view).
TEST_F(ExportTest, SvgShaded) {
  in.shade = true;
  std::string svg = readAll(exportTo("tree.svg"));
  SvgPicture pic = readSvg(svg);
  size_t full = 0;  // triangles: a polygon of n corners is n - 2 of them
  for (auto& p : pic.paths)
    if (classColor(pic, p, 'f') == hex(color(2)))
      for (auto& sub : p.subpaths) full += sub.size() - 2;
  EXPECT_EQ(full, 3u);  // facing the light: full colour
  EXPECT_EQ(countOf(svg, hex(color(5))), 0u);                      // tilted 45°: darker
  auto c = color(5);
  float k = 0.2f + std::sqrt(0.5f);
  EXPECT_NE(svg.find(hex({c[0] * k, c[1] * k, c[2] * k, 1})), std::string::npos);
}

TEST_F(ExportTest, PostScript) {
  std::string ps = readAll(exportTo("tree.ps"));
  EXPECT_EQ(ps.rfind("%!PS-Adobe", 0), 0u);
  // lpfg's page: a 400 × 400 picture scaled by 1.44 to 576 pt, centred in 8 × 10 in, 18 pt margin.
  EXPECT_NE(ps.find("%%BoundingBox: 18 90 594 666\n"), std::string::npos);
  EXPECT_EQ(countOf(ps, " T\n"), size_t(kMeshTriangles));
  EXPECT_EQ(countOf(ps, " L\n"), geometry.segments.size());
  EXPECT_EQ(countOf(ps, " D\n"), 1u);
  // The label as glyph outlines: one filled path per glyph (8 characters, none blank), after a
  // comment with its text.
  size_t label = ps.find("% label: A<b>&(c)\n");
  ASSERT_NE(label, std::string::npos);
  EXPECT_EQ(countOf(ps.substr(label), "h\nfill\n"), 8u);
  EXPECT_EQ(countOf(ps, " show"), 0u);
  EXPECT_NE(ps.find("showpage"), std::string::npos);
  // Model (0,0) is window (0,400): page (18, 90). Model (1,1): (18 + 144, 90 + 144).
  EXPECT_NE(ps.find(" 18 90 T\n"), std::string::npos);
  EXPECT_NE(ps.find(" 162 234 "), std::string::npos);
  // Line widths scale with the page: width 2 px → 2.88 pt.
  EXPECT_EQ(countOf(ps, " 2.88 "), 2u);
}

TEST_F(ExportTest, Eps) {
  std::string eps = readAll(exportTo("tree.eps"));
  EXPECT_EQ(eps.rfind("%!PS-Adobe-3.0 EPSF-3.0\n", 0), 0u);
  EXPECT_NE(eps.find("%%BoundingBox: 0 0 400 400\n"), std::string::npos);
  EXPECT_EQ(countOf(eps, " T\n"), size_t(kMeshTriangles));
  // 1 pt per pixel, y up: model (1,1) → (100, 100); the disc at (300, 300) with radius 50.
  EXPECT_NE(eps.find(" 300 300 50 D\n"), std::string::npos);
  // The label's first glyph, "A", starts within its em (16 px: 12 pt at 96 dpi) right of the
  // anchor (100, 100), above the baseline 2 px below it.
  size_t label = eps.find("% label: A<b>&(c)\n");
  ASSERT_NE(label, std::string::npos);
  size_t move = eps.find(" m ", label);
  ASSERT_NE(move, std::string::npos);
  float x = 0, y = 0;
  ASSERT_EQ(std::sscanf(eps.c_str() + eps.rfind("newpath ", move) + 8, "%f %f m", &x, &y), 2);
  EXPECT_GE(x, 100);
  EXPECT_LT(x, 100 + 16);
  EXPECT_GE(y, 98 - 0.01f);
  EXPECT_LT(y, 98 + 16);
}

TEST_F(ExportTest, Pdf) {
  std::string pdf = readAll(exportTo("tree.pdf"));
  EXPECT_EQ(pdf.rfind("%PDF-1.4\n", 0), 0u);
  EXPECT_NE(pdf.find("/MediaBox [0 0 400 400]"), std::string::npos);
  // One filled-and-outlined path per triangle, one stroke per segment, the disc, the label.
  EXPECT_EQ(countOf(pdf, " h B\n"), size_t(kMeshTriangles));
  EXPECT_EQ(countOf(pdf, " l S\n"), geometry.segments.size());
  size_t label = pdf.find("% label: A<b>&(c)\n");
  ASSERT_NE(label, std::string::npos);
  EXPECT_EQ(countOf(pdf.substr(label), "h\nf\n"), 8u);  // a filled outline per glyph
  EXPECT_EQ(countOf(pdf, " Tj"), 0u);
  // The xref table is where startxref says, with one entry per object at its offset.
  size_t start = pdf.rfind("startxref\n");
  ASSERT_NE(start, std::string::npos);
  size_t xref = std::stoul(pdf.substr(start + 10));
  ASSERT_EQ(pdf.compare(xref, 4, "xref"), 0);
  for (int obj = 1; obj <= 4; ++obj) {
    size_t at = pdf.find(std::to_string(obj) + " 0 obj\n");
    ASSERT_NE(at, std::string::npos);
    char entry[32];
    std::snprintf(entry, sizeof entry, "%010zu 00000 n ", at);
    EXPECT_NE(pdf.find(entry, xref), std::string::npos) << "object " << obj;
  }
  // The content stream's /Length is its byte count.
  size_t len = pdf.find("/Length ");
  size_t stream = pdf.find("stream\n", len) + 7, end = pdf.find("endstream", stream);
  EXPECT_EQ(std::stoul(pdf.substr(len + 8)), end - stream);
}

TEST_F(ExportTest, Pov) {
  std::string pov = readAll(exportTo("tree.pov"));
  EXPECT_NE(pov.find("#version 3.7;"), std::string::npos);
  auto c0 = color(0);
  EXPECT_NE(pov.find(fmt::format("background {{ srgb <{},{},{}> }}", c0[0], c0[1], c0[2])), std::string::npos);
  EXPECT_EQ(countOf(pov, "camera {"), 1u);
  EXPECT_NE(pov.find("orthographic"), std::string::npos);
  // The view is 4 × 4 model units: right/up vectors of that length along x and y.
  EXPECT_NE(pov.find("right <4,0,0>"), std::string::npos);
  EXPECT_NE(pov.find("up <0,4,0>"), std::string::npos);
  EXPECT_EQ(countOf(pov, "light_source"), 1u);
  EXPECT_EQ(countOf(pov, "mesh2 {"), 1u);
  EXPECT_NE(pov.find(fmt::format("vertex_vectors {{ {},", geometry.vertices.size())), std::string::npos);
  EXPECT_NE(pov.find(fmt::format("face_indices {{ {},", kMeshTriangles)), std::string::npos);
  EXPECT_NE(pov.find("texture_list { 3,"), std::string::npos);
  EXPECT_NE(pov.find("uv_vectors"), std::string::npos);
  // Colormap mode: flat colours (lpfg draws colormaps unlit).
  for (int i : {2, 3, 4, 5, 6}) {
    auto c = color(i);
    EXPECT_NE(pov.find(fmt::format("#declare s{:03d} = texture {{ pigment {{ srgbt <{},{},{},0> }} finish {{ ambient 0 "
                                   "diffuse 0 emission 1 }} }}",
                                   i, c[0], c[1], c[2])),
              std::string::npos)
        << i;
  }
  auto t7 = palette.textColor(7);
  EXPECT_NE(pov.find(fmt::format("#declare text_s007 = texture {{ pigment {{ srgb <{},{},{}> }}", t7[0], t7[1], t7[2])),
            std::string::npos);
  EXPECT_NE(pov.find("#declare s002_t0 = texture { uv_mapping pigment { image_map { png \"leaf.png\""), std::string::npos);
  EXPECT_EQ(countOf(pov, "\ncylinder {"), geometry.segments.size());
  // Width 2 px at 100 px per unit → radius 0.01.
  EXPECT_NE(pov.find("cylinder { <0,0,0>, <0,2,0>, 0.01 texture { s003 } }"), std::string::npos);
  EXPECT_NE(pov.find("disc { <3,3,0>, <0,0,1>, 0.5 texture { s006 } }"), std::string::npos);
  EXPECT_NE(pov.find("text { ttf \"timrom.ttf\" \"A<b>&(c)\""), std::string::npos);
}

// Without a camera the picture is framed with frameView (the renderer's framing).
TEST_F(ExportTest, FramedByView) {
  in.camera.reset();
  in.width = 320, in.height = 200;
  std::string svg = readAll(exportTo("framed.svg"));
  EXPECT_NE(svg.find("width=\"320\" height=\"200\""), std::string::npos);
  SvgPicture pic = readSvg(svg);
  size_t segments = 0, triangles = 0;
  std::vector<std::pair<float, float>> points;
  for (auto& p : pic.paths)
    for (auto& sub : p.subpaths) {
      if (p.cls.rfind("l ", 0) == 0) ++segments;
      else triangles += sub.size() - 2;
      points.insert(points.end(), sub.begin(), sub.end());
    }
  EXPECT_EQ(segments, geometry.segments.size());
  EXPECT_EQ(triangles, size_t(kMeshTriangles));
  // Everything drawn lies inside the window.
  for (auto [x, y] : points) {
    EXPECT_GE(x, -0.01f);
    EXPECT_LE(x, 320.01f);
    EXPECT_GE(y, -0.01f);
    EXPECT_LE(y, 200.01f);
  }
  exportTo("framed.pov");
  exportTo("framed.obj");
}

// A materials file: OBJ/MTL, glTF and POV-Ray take the material's parts.
TEST_F(ExportTest, Materials) {
  // .mat records: index, transparency, ambient rgb, diffuse rgb, emission rgb, specular rgb, shininess.
  std::string mat;
  auto record = [&](int index, int transparency, std::array<int, 12> c, int shininess) {
    mat += (char)index;
    mat += (char)transparency;
    for (int v : c) mat += (char)v;
    mat += (char)shininess;
  };
  record(2, 0, {51, 51, 51, 200, 100, 50, 0, 0, 0, 255, 255, 255}, 40);
  record(5, 128, {0, 0, 0, 10, 20, 30, 255, 0, 0, 0, 0, 0}, 0);
  std::ofstream(dir / "plant.mat", std::ios::binary) << mat;
  Palette materials;
  llvm::Error err = materials.loadMaterials((dir / "plant.mat").string());
  ASSERT_FALSE((bool)err) << llvm::toString(std::move(err));
  ASSERT_TRUE(materials.usesMaterials());
  in.palette = &materials;
  const Material& m2 = materials.material(2);
  const Material& m5 = materials.material(5);

  fs::path obj = exportTo("m.obj");
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> mtl;
  std::string warn, e;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &mtl, &warn, &e, obj.string().c_str(), dir.string().c_str())) << e;
  std::map<std::string, const tinyobj::material_t*> byName;
  for (const auto& x : mtl) byName[x.name] = &x;
  ASSERT_TRUE(byName.count("s002") && byName.count("s005"));
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(byName["s002"]->diffuse[k], m2.diffuse[k], 1e-6);
    EXPECT_NEAR(byName["s002"]->specular[k], m2.specular[k], 1e-6);
    EXPECT_NEAR(byName["s002"]->ambient[k], m2.ambient[k], 1e-6);
    EXPECT_NEAR(byName["s005"]->emission[k], m5.emission[k], 1e-6);
  }
  EXPECT_NEAR(byName["s002"]->shininess, m2.shininess, 1e-6);
  EXPECT_NEAR(byName["s005"]->dissolve, 1 - m5.transparency, 1e-6);
  EXPECT_NEAR(byName["s002"]->dissolve, 1, 1e-6);

  fs::path glb = exportTo("m.glb");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(noImages, nullptr);
  tinygltf::Model model;
  std::string gerr, gwarn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &gerr, &gwarn, glb.string())) << gerr;
  for (const tinygltf::Material& m : model.materials) {
    if (m.name == "s005") {
      EXPECT_EQ(m.alphaMode, "BLEND");
      EXPECT_NEAR(m.pbrMetallicRoughness.baseColorFactor[3], 1 - m5.transparency, 1e-6);
      EXPECT_NEAR(m.emissiveFactor[0], m5.emission[0], 1e-6);
    }
    if (m.name == "s002") {
      EXPECT_EQ(m.alphaMode, "OPAQUE");
      EXPECT_NEAR(m.pbrMetallicRoughness.baseColorFactor[1], m2.diffuse[1], 1e-6);
    }
  }

  std::string pov = readAll(exportTo("m.pov"));
  EXPECT_NE(pov.find(fmt::format("#declare s002 = texture {{ pigment {{ srgbt <{},{},{},0> }} finish {{ ambient srgb <{},{},{}> "
                                 "diffuse 1 phong 1 phong_size {} }} }}",
                                 m2.diffuse[0], m2.diffuse[1], m2.diffuse[2], m2.ambient[0], m2.ambient[1],
                                 m2.ambient[2], m2.shininess)),
            std::string::npos)
      << pov;
  // The background is the palette's (material 0's emission in materials mode).
  auto bg = materials.background();
  EXPECT_NE(pov.find(fmt::format("background {{ srgb <{},{},{}> }}", bg[0], bg[1], bg[2])), std::string::npos);
  std::string svg = readAll(exportTo("m.svg"));
  EXPECT_NE(svg.find("fill=\"" + hex(bg) + "\""), std::string::npos);
  EXPECT_NE(svg.find("fill-opacity=\""), std::string::npos);  // the half-transparent colour 5
}

// A perspective camera for POV-Ray: the direction vector carries the field of view.
TEST_F(ExportTest, PovPerspective) {
  CameraMatrices cam = makeCamera();
  cam.perspective = true;
  cam.projection = glm::perspective(glm::radians(90.0f), 1.0f, 1.0f, 20.0f);
  in.camera = cam;
  std::string pov = readAll(exportTo("p.pov"));
  EXPECT_NE(pov.find("perspective\n  location <2,2,10>\n  direction <0,0,-1>\n"), std::string::npos) << pov;
  // 90° field of view: right and up are twice the direction's length.
  EXPECT_NE(pov.find("right <2,0,0>"), std::string::npos);
  EXPECT_NE(pov.find("up <0,2,0>"), std::string::npos);
  // Segment radius from the pixel width at the segment's depth (10 units: 20 units / 400 px).
  EXPECT_NE(pov.find("cylinder { <0,0,0>, <0,2,0>, 0.05 "), std::string::npos);
}

// The PostScript gradient (`gradient: 1 m`) brightens triangles along their first texture
// coordinate, as lpfg does across a surface's patch.
TEST_F(ExportTest, PostScriptGradient) {
  view.gradientDirection = 1;
  view.gradientMagnitude = 0.5f;
  in.textureFiles.clear();
  // Colour 2 is dark enough to brighten without clipping: (2, 253, 74)/255 → green clips, red does not.
  std::string ps = readAll(exportTo("g.ps"));
  auto c = color(2);
  float k = 1 + 0.5f * (0 + 1 + 0) / 3.0f;  // the textured triangle's u: 0, 1, 0
  char want[64];
  std::snprintf(want, sizeof want, "%g ", std::round(c[0] * k * 1000) / 1000);
  EXPECT_NE(ps.find(std::string("\n") + want), std::string::npos) << want;
}

// A multi-view model (manual §7.3): the 2D formats draw every view in its rectangle of the page,
// as the picture lays them out (paneRects), each framed in it alone — its drawing centred in its
// rectangle — with the window border colour between them. The 3D formats hold `geometry` (view 0)
// and say so.
TEST_F(ExportTest, MultiView) {
  std::vector<ViewPane> views(2);
  views[0].geometry.segments.push_back({{0, 0, 0}, {1, 1, 0}, 1, 3});
  views[1].geometry.segments.push_back({{5, 5, 0}, {5, 7, 0}, 1, 4});
  views[0].rect = ViewPane::Rect::inside(0, 0, 0.5f, 1);
  views[1].rect = ViewPane::Rect::inside(0.5f, 0, 0.5f, 1);
  views[1].viewId = 1;
  view.windows = {{"left", 0, 0, 0.5f, 1}, {"right", 0.5f, 0, 0.5f, 1}};
  view.windowBorderSize = 4;
  view.windowBorderColor = {1, 0, 0};
  in.camera.reset();
  in.width = 400, in.height = 200;
  in.views = &views;
  // Side by side, 4 px apart, the whole height: {x0, top y0, width, height} of each.
  const auto rects = paneRects({views[0].rect, views[1].rect}, 400, 200, 4);
  ASSERT_EQ(rects.size(), 2u);
  EXPECT_EQ(rects[0][0], 0);
  EXPECT_EQ(rects[1][0] - (rects[0][0] + rects[0][2]), 4);
  EXPECT_EQ(rects[1][0] + rects[1][2], 400);
  EXPECT_EQ(rects[0][3], 200);
  // Where each view's segment's midpoint falls on the page (x right, y down), and its colour.
  auto centre = [&](int v) {
    return std::pair<float, float>(rects[v][0] + rects[v][2] / 2.0f, rects[v][1] + rects[v][3] / 2.0f);
  };
  const std::string colors[2] = {hex(color(3)), hex(color(4))};

  std::string note;
  in.note = &note;
  std::string svg = readAll(exportTo("mv.svg"));
  EXPECT_EQ(note, "");
  EXPECT_NE(svg.find("<rect id=\"border\" x=\"0\" y=\"0\" width=\"400\" height=\"200\" fill=\"#ff0000\"/>"), std::string::npos);
  const SvgPicture classes = readSvg(svg);
  for (int v = 0; v < 2; ++v) {
    SCOPED_TRACE(v);
    const std::string head = fmt::format("<svg id=\"view{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"", v, rects[v][0],
                                         rects[v][1], rects[v][2], rects[v][3]);
    size_t at = svg.find(head);
    ASSERT_NE(at, std::string::npos) << svg;
    std::string inside = svg.substr(at, svg.find("</svg>", at) - at);
    EXPECT_NE(inside.find(fmt::format("fill=\"{}\"", hex(color(0)))), std::string::npos);  // its background
    SvgPicture pic = readSvg(inside);
    ASSERT_EQ(pic.paths.size(), 1u);
    ASSERT_EQ(pic.paths[0].subpaths.size(), 1u);
    const auto& ends = pic.paths[0].subpaths[0];
    ASSERT_EQ(ends.size(), 2u);
    // In the view's own coordinates: centred in it, inside it.
    EXPECT_TRUE(near({(ends[0].first + ends[1].first) / 2, (ends[0].second + ends[1].second) / 2},
                     {rects[v][2] / 2.0f, rects[v][3] / 2.0f}, 0.11f));
    for (auto [x, y] : ends) {
      EXPECT_GE(x, 0);
      EXPECT_LE(x, rects[v][2]);
      EXPECT_GE(y, 0);
      EXPECT_LE(y, rects[v][3]);
    }
    EXPECT_EQ(classColor(classes, pic.paths[0], 's'), colors[v]);
  }

  // EPS and PDF (1 pt per pixel, y up): each view clipped to its rectangle, its line in it.
  std::string eps = readAll(exportTo("mv.eps"));
  EXPECT_NE(eps.find("\n1 0 0 setrgbcolor fill\n"), std::string::npos);  // the border
  auto epsLines = [&](const std::string& text, const std::regex& pattern) {
    std::vector<std::array<float, 4>> out;
    for (std::sregex_iterator it(text.begin(), text.end(), pattern), end; it != end; ++it)
      out.push_back({std::stof((*it)[1]), std::stof((*it)[2]), std::stof((*it)[3]), std::stof((*it)[4])});
    return out;
  };
  const auto psLines = epsLines(eps, std::regex("([-0-9.]+) ([-0-9.]+) ([-0-9.]+) ([-0-9.]+) L\n"));
  std::string pdf = readAll(exportTo("mv.pdf"));
  const auto pdfLines = epsLines(pdf, std::regex("RG [0-9.]+ w ([-0-9.]+) ([-0-9.]+) m ([-0-9.]+) ([-0-9.]+) l S\n"));
  ASSERT_EQ(psLines.size(), 2u);
  ASSERT_EQ(pdfLines.size(), 2u);
  for (int v = 0; v < 2; ++v) {
    SCOPED_TRACE(v);
    const auto [cx, cy] = centre(v);
    for (const auto& l : {psLines[v], pdfLines[v]})
      EXPECT_TRUE(near({(l[0] + l[2]) / 2, (l[1] + l[3]) / 2}, {cx, 200 - cy}, 0.011f)) << l[0] << " " << l[1];
    EXPECT_NE(eps.find(fmt::format("gsave newpath {} {} moveto {} 0 rlineto 0 {} rlineto", rects[v][0],
                                   200 - rects[v][1] - rects[v][3], rects[v][2], rects[v][3])),
              std::string::npos);
    EXPECT_NE(pdf.find(fmt::format("q {} {} {} {} re W n ", rects[v][0], 200 - rects[v][1] - rects[v][3], rects[v][2],
                                   rects[v][3])),
              std::string::npos);
  }
  exportTo("mv.ps");
  EXPECT_EQ(note, "");

  // A mesh format: `geometry` (view 0), and a note of the views it leaves out.
  PlyData ply = readPly(exportTo("mv.ply"));
  EXPECT_EQ(ply.edges.size(), geometry.segments.size());
  EXPECT_NE(note.find("mv.ply holds view 0 (left) only: the view file's 2 windows are laid out together only in "
                      "pictures"),
            std::string::npos)
      << note;
}

// Default palette and view; empty geometry.
TEST_F(ExportTest, DefaultsAndEmpty) {
  in.palette = nullptr;
  in.view = nullptr;
  for (const char* name : {"d.obj", "d.ply", "d.stl", "d.glb", "d.gltf", "d.svg", "d.ps", "d.eps", "d.pdf", "d.pov"}) exportTo(name);
  Geometry empty;
  in.geometry = &empty;
  for (const char* name : {"e.obj", "e.ply", "e.stl", "e.glb", "e.gltf", "e.svg", "e.ps", "e.eps", "e.pdf", "e.pov"}) exportTo(name);
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (dir / "e.glb").string())) << err;
  EXPECT_EQ(readAll(dir / "e.stl").size(), 84u);
}

}  // namespace
