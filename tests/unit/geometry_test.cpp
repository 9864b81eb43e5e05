// Turtle geometry, family by family: each test runs a tiny L+C model (with a view file where the
// family needs one) and checks the produced vertices, normals, colours and lpfg bounding box
// against values computed by hand from the manual's §5 and lpfg's placement rules.
#include <gtest/gtest.h>

#include "tests/unit/test_vectors.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/session/Session.h"

using namespace lcjit;
using namespace lcjit::app;
using lcjit::runtime::Geometry;

namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  static fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("lcjit-geometry-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

void writeFile(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// A one-patch .s surface: the unit square in the xy plane, control point (i,j) at (j/3, i/3, 0).
void writeFlatSurface(const fs::path& path) {
  std::string text = "0 1 0 1 0 0\nCONTACT POINT X: 0 Y: 0 Z: 0\nEND POINT X: 0 Y: 1 Z: 0\n"
                     "HEADING X: 0 Y: 1 Z: 0\nUP X: 0 Y: 0 Z: 1\nSIZE: 1\nleaf\nTOP COLOR: 1 DIFFUSE: 1 BOTTOM COLOR: 1 DIFFUSE: 1\n"
                     "AL: ~ A: ~ AR: ~\nL: ~ R: ~\nBL: ~ B: ~ BR: ~\n";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) text += std::to_string(j / 3.0) + " " + std::to_string(i / 3.0) + " 0\n";
  writeFile(path, text);
}

Session& session() {
  static std::unique_ptr<Session> s = [] {
    auto r = Session::create();
    if (!r) ADD_FAILURE() << llvm::toString(r.takeError());
    return std::move(*r);
  }();
  return *s;
}

// Runs `axiom` (and optional extra L+C lines) with the view file `view` and returns the geometry.
Geometry draw(const std::string& name, const std::string& axiom, const std::string& view = "",
              const std::vector<std::string>& extraFiles = {}, const std::string& extra = "") {
  fs::path l = scratch() / (name + ".l");
  writeFile(l, "#include <lpfgall.h>\n" + extra + "\nderivation length: 0;\naxiom: " + axiom + ";\n");
  ModelFiles files;
  files.lsystem = l.string();
  if (!view.empty()) {
    fs::path v = scratch() / (name + ".v");
    writeFile(v, view);
    files.view = v.string();
  }
  for (auto& f : extraFiles) {
    if (f.ends_with(".con") || f.ends_with(".cset")) files.contours.push_back(f);
  }
  PhaseTimes times;
  Geometry g;
  if (auto e = session().load(files, 1, times)) {
    ADD_FAILURE() << llvm::toString(std::move(e));
    return g;
  }
  for (auto& w : session().warnings()) ADD_FAILURE() << "warning: " << w;
  for (auto& f : extraFiles) EXPECT_TRUE(fs::exists(f)) << f;
  if (auto e = session().engine().run()) {
    ADD_FAILURE() << llvm::toString(std::move(e));
    return g;
  }
  if (auto e = session().engine().interpret(g)) ADD_FAILURE() << llvm::toString(std::move(e));
  return g;
}

#define EXPECT_V3(v, X, Y, Z) EXPECT_V3_NEAR((v), (X), (Y), (Z), 1e-4)

TEST(TurtleGeometry, PixelLinesCarryWidthColourAndTurn) {
  Geometry g = draw("pixel", "SetColor(3) SetWidth(4) F(2) Left(90) F(1) IncColor f(1) G(1)");
  ASSERT_EQ(g.segments.size(), 3u);
  EXPECT_V3(g.segments[0].from, 0, 0, 0);
  EXPECT_V3(g.segments[0].to, 0, 2, 0);
  EXPECT_EQ(g.segments[0].width, 4);
  EXPECT_EQ(g.segments[0].color, 3);
  // Left(90) turns H towards L = (-1,0,0).
  EXPECT_V3(g.segments[1].to, -1, 2, 0);
  // f moves without drawing; G draws.
  EXPECT_V3(g.segments[2].from, -2, 2, 0);
  EXPECT_V3(g.segments[2].to, -3, 2, 0);
  EXPECT_EQ(g.segments[2].color, 4);
  EXPECT_TRUE(g.indices.empty());
  // lpfg's box counts f moves.
  EXPECT_V3(g.extent.min, -3, 0, 0);
  EXPECT_V3(g.extent.max, 0, 2, 0);
}

TEST(TurtleGeometry, BranchesRestoreStateAndAffineModulesDraw) {
  Geometry g = draw("branch", "SB SetColor(2) Right(90) F(1) EB F(1) MoveTo(5,5,0) LineTo(5,7,0) "
                              "SetCoordinateSystem(2) LineRel3f(V3f(1,0,0))");
  ASSERT_EQ(g.segments.size(), 4u);
  EXPECT_V3(g.segments[0].to, 1, 0, 0);
  EXPECT_EQ(g.segments[0].color, 2);
  EXPECT_V3(g.segments[1].to, 0, 1, 0);
  EXPECT_EQ(g.segments[1].color, 1);
  EXPECT_V3(g.segments[2].from, 5, 5, 0);
  EXPECT_V3(g.segments[2].to, 5, 7, 0);
  // After SetCoordinateSystem(2) at (5,7,0) with H=(0,1,0), L=(-1,0,0): x maps to -L, times 2.
  EXPECT_V3(g.segments[3].to, 7, 7, 0);
  // MoveTo does not grow lpfg's box; the lines do.
  EXPECT_V3(g.extent.max, 7, 7, 0);
}

TEST(TurtleGeometry, PolygonLinesFaceTheViewer) {
  Geometry g = draw("polyline", "SetWidth(1) SetColor(5) F(2)", "line style: polygon\n");
  EXPECT_TRUE(g.segments.empty());
  ASSERT_EQ(g.vertices.size(), 4u);
  ASSERT_EQ(g.triangleCount(), 2u);
  // Side vector = normalize(H × view direction) · width/2 = (-0.5, 0, 0).
  EXPECT_V3(g.vertices[0].position, 0.5, 0, 0);
  EXPECT_V3(g.vertices[1].position, -0.5, 0, 0);
  EXPECT_V3(g.vertices[2].position, -0.5, 2, 0);
  EXPECT_V3(g.vertices[3].position, 0.5, 2, 0);
  for (auto& v : g.vertices) {
    EXPECT_V3(v.normal, 0, 0, 1);
    EXPECT_EQ(v.color, 5);
  }
}

// lpfg's limit is 10000 sides; lcjit keeps the geometry, so it draws at most 128 sphere slices
// and 1000 ring sides (a 10000-sided sphere per node took a small tree past 12 GB).
TEST(TurtleGeometry, SidesPastAPixelAreNotDrawn) {
  // (The view file's `contour sides: 10000` is the same number, with a warning: view_file_test.)
  Geometry g = draw("manysides", "ContourSides(10000) Sphere(1)", "contour sides: 8\n");
  // 128 slices, 64 stacks: 65 rows of 129 vertices.
  EXPECT_EQ(g.vertices.size(), 65u * 129u);
  Geometry c = draw("manysidescyl", "ContourSides(5000) SetWidth(2) F(3)", "line style: cylinder\n");
  // 1000 sides: two rings of 1001 points, 2000 triangles.
  EXPECT_EQ(c.vertices.size(), 2u * 1001u);
  EXPECT_EQ(c.triangleCount(), 2000u);
}

TEST(TurtleGeometry, CylinderLinesAreFrustumsOfTheContour) {
  Geometry g = draw("cylinder", "SetWidth(2) SetColor(7) F(3)", "line style: cylinder\ncontour sides: 4\n");
  // 4 sides: 5 points per ring (the last repeats the first), 8 triangles.
  ASSERT_EQ(g.vertices.size(), 10u);
  EXPECT_EQ(g.triangleCount(), 8u);
  // Ring point i = P + L·sin(2πi/4)·w/2 + U·cos(2πi/4)·w/2; vertices alternate begin/end rings.
  EXPECT_V3(g.vertices[0].position, 0, 0, 1);
  EXPECT_V3(g.vertices[1].position, 0, 3, 1);
  EXPECT_V3(g.vertices[2].position, -1, 0, 0);
  EXPECT_V3(g.vertices[4].position, 0, 0, -1);
  EXPECT_V3(g.vertices[6].position, 1, 0, 0);
  EXPECT_V3(g.vertices[8].position, 0, 0, 1);
  EXPECT_V3(g.vertices[2].normal, -1, 0, 0);
  EXPECT_EQ(g.vertices[5].color, 7);
  // Outward-facing winding: the first triangle's geometric normal points along its vertex normal.
  auto& v = g.vertices;
  auto a = v[g.indices[0]].position, b = v[g.indices[1]].position, c = v[g.indices[2]].position;
  auto n = (b - a) % (c - a);
  EXPECT_GT(n * (v[g.indices[0]].normal + v[g.indices[2]].normal), 0);
  EXPECT_V3(g.extent.min, -1, 0, -1);
  EXPECT_V3(g.extent.max, 1, 3, 1);
}

TEST(TurtleGeometry, GeneralizedCylinderSharesRingsAndMapsTexture) {
  Geometry g = draw("gc", "SetWidth(2) CurrentTexture(0) TextureVCoeff(0.25) StartGC F(1) F(2) EndGC F(1)",
                    "line style: cylinder\ncontour sides: 4\ntexture: " + std::string(LCJIT_TEST_DATA) +
                        "/images/checker.rgb\n");
  // Two GC frustums and one plain F: 3 × 10 vertices.
  ASSERT_EQ(g.vertices.size(), 30u);
  // The second frustum starts where the first ended.
  EXPECT_V3(g.vertices[10].position, g.vertices[1].position.x, g.vertices[1].position.y, g.vertices[1].position.z);
  EXPECT_V3(g.vertices[11].position, 0, 3, 1);
  // v runs 0 → 0.25 → 0.75 along the cylinder; u = i/4 around.
  EXPECT_NEAR(g.vertices[0].uv.y, 0, 1e-6);
  EXPECT_NEAR(g.vertices[1].uv.y, 0.25, 1e-6);
  EXPECT_NEAR(g.vertices[11].uv.y, 0.75, 1e-6);
  EXPECT_NEAR(g.vertices[2].uv.x, 0.25, 1e-6);
  ASSERT_FALSE(g.runs.empty());
  EXPECT_EQ(g.runs[0].texture, 0);
}

// lpfg: CurrentTexture(id) makes surfaces take that texture instead of the view file's
// (CurrentTexture(-1): none); an id the view file has not given is ignored, and the surfaces
// have their own textures again.
TEST(TurtleGeometry, CurrentTextureAppliesToSurfaces) {
  std::string data = LCJIT_TEST_DATA;
  std::string texture = "texture: " + data + "/images/checker.rgb\n";
  std::string view = texture + texture + "surface: " + data + "/surfaces/flat.s 1 2 2 0\n";
  Geometry g = draw("texsurf", "Surface(0, 1) CurrentTexture(1) Surface(0, 1) CurrentTexture(-1) Surface(0, 1) "
                               "CurrentTexture(7) Surface(0, 1)",
                    view);
  std::vector<int> textures;
  for (const auto& r : g.runs) textures.push_back(r.texture);
  EXPECT_EQ(textures, (std::vector<int>{0, 1, -1, 0}));
}

// Widths are what SetWidth says, zero and negative ones included (lpfg's; a function dipping
// below zero makes a flower vanish there), not the previous width.
TEST(TurtleGeometry, SetWidthTakesAnyValue) {
  // Sphere0's radius is half the width: 0 and -0.05 draw nothing (the old width, 1, would).
  Geometry g = draw("negwidth", "SetWidth(1) SetWidth(0) Sphere0 SetWidth(-0.1) Sphere0", "contour sides: 4\n");
  EXPECT_TRUE(g.vertices.empty());
  Geometry h = draw("poswidth", "SetWidth(1) SetWidth(0.5) Sphere0", "contour sides: 4\n");
  EXPECT_FALSE(h.vertices.empty());
}

TEST(TurtleGeometry, CirclesAndSpheres) {
  Geometry g = draw("circles", "SetColor(4) Circle(2) ContourSides(4) Circle(1) Sphere(2) CircleFront(3)",
                    "contour sides: 8\n");
  // Circle(2) with 8 sides: centre + 8 rim vertices, 8 triangles.
  // Circle(1) with 4 sides: rim vertex k = P + (−L·sin a + H·cos a)·r.
  ASSERT_GE(g.vertices.size(), 9u + 5u);
  EXPECT_V3(g.vertices[1].position, 0, 2, 0);
  EXPECT_V3(g.vertices[9].position, 0, 0, 0);
  EXPECT_V3(g.vertices[10].position, 0, 1, 0);
  EXPECT_V3(g.vertices[11].position, 1, 0, 0);
  EXPECT_V3(g.vertices[11].normal, 0, 0, 1);
  EXPECT_EQ(g.vertices[11].color, 4);
  // Sphere(2), 4 slices, 2 stacks: 3 rows of 5 vertices, 8 triangles; the equator's first point
  // is (0, r, 0), poles on world ±Z.
  size_t s = 14;
  ASSERT_EQ(g.vertices.size(), s + 15);
  EXPECT_V3(g.vertices[s].position, 0, 0, 2);
  EXPECT_V3(g.vertices[s + 5].position, 0, 2, 0);
  EXPECT_V3(g.vertices[s + 5].normal, 0, 1, 0);
  EXPECT_EQ(g.triangleCount(), 8u + 4u + 8u);
  // CircleFront stays a camera-facing disc.
  ASSERT_EQ(g.discs.size(), 1u);
  EXPECT_EQ(g.discs[0].outer, 3);
  EXPECT_V3(g.extent.max, 3, 3, 3);
}

TEST(TurtleGeometry, PolygonsRhombusAndTriangle) {
  Geometry g = draw("polygons", "SP SetColor(2) f(1) Left(90) SetColor(3) f(1) Left(90) PP G(1) f(1) EP "
                                "MoveTo(10,0,0) SetHead(0,1,0,0,0,1) Rhombus(2,1) Triangle(2,1)");
  // Vertices: f(1) → (0,1,0) colour 2; f(1) → (-1,1,0) colour 3; PP at (-1,1,0); G adds none;
  // f → (-1,-1,0).
  ASSERT_GE(g.vertices.size(), 4u);
  EXPECT_V3(g.vertices[0].position, 0, 1, 0);
  EXPECT_EQ(g.vertices[0].color, 2);
  EXPECT_V3(g.vertices[1].position, -1, 1, 0);
  EXPECT_EQ(g.vertices[1].color, 3);
  EXPECT_V3(g.vertices[3].position, -1, -1, 0);
  EXPECT_V3(g.vertices[0].normal, 0, 0, 1);
  // Fan: (0,1,2), (0,2,3).
  EXPECT_EQ(g.indices[3], 0u);
  EXPECT_EQ(g.indices[5], 3u);
  // Rhombus(2,1) at (10,0,0), in lpfg's (clockwise from +U) order: P, P + H + L/2, P + 2H,
  // P + H − L/2 = (10,0), (9.5,1), (10,2), (10.5,1).
  EXPECT_V3(g.vertices[4].position, 10, 0, 0);
  EXPECT_V3(g.vertices[5].position, 9.5, 1, 0);
  EXPECT_V3(g.vertices[6].position, 10, 2, 0);
  EXPECT_V3(g.vertices[7].position, 10.5, 1, 0);
  // Triangle(2,1): P + L = (9,0), P + H = (10,1), P − L = (11,0).
  EXPECT_V3(g.vertices[8].position, 9, 0, 0);
  EXPECT_V3(g.vertices[9].position, 10, 1, 0);
  EXPECT_V3(g.vertices[10].position, 11, 0, 0);
  // Clockwise seen from +U, as lpfg winds them.
  auto& v = g.vertices;
  EXPECT_LT(((v[5].position - v[4].position) % (v[6].position - v[4].position)).z, 0);
  EXPECT_LT(((v[9].position - v[8].position) % (v[10].position - v[8].position)).z, 0);
  EXPECT_EQ(g.triangleCount(), 2u + 2u + 1u);
}

TEST(TurtleGeometry, ConcavePolygonIsTessellatedWhenAsked) {
  // An L-shaped hexagon: a fan from vertex 0 would cover the notch; ear clipping does not.
  std::string axiom = "SP MoveTo(0,0,0) PP MoveTo(2,0,0) PP MoveTo(2,1,0) PP MoveTo(1,1,0) PP MoveTo(1,2,0) PP "
                      "MoveTo(0,2,0) PP EP";
  Geometry g = draw("concave", axiom, "concave polygons: on\n");
  ASSERT_EQ(g.vertices.size(), 6u);
  ASSERT_EQ(g.triangleCount(), 4u);
  double area = 0;
  for (size_t i = 0; i < g.indices.size(); i += 3) {
    auto a = g.vertices[g.indices[i]].position, b = g.vertices[g.indices[i + 1]].position,
         c = g.vertices[g.indices[i + 2]].position;
    area += std::fabs(((b - a) % (c - a)).z) / 2;
  }
  EXPECT_NEAR(area, 3, 1e-5);
  for (size_t i = 0; i < g.indices.size(); i += 3) {
    auto a = g.vertices[g.indices[i]].position, b = g.vertices[g.indices[i + 1]].position,
         c = g.vertices[g.indices[i + 2]].position;
    auto centre = (a + b + c) / 3.f;
    EXPECT_FALSE(centre.x > 1 + 1e-4 && centre.y > 1 + 1e-4) << "a triangle covers the notch";
  }
}

TEST(TurtleGeometry, TropismBendsTheHeading) {
  // T = (1,0,0), E = 0.5: H × D = (0,0,-0.5), so H turns by 0.5 rad towards +x before the move.
  Geometry g = draw("tropism", "F(1) F(1)", "tropism: T: 1 0 0 E: 0.5\n");
  ASSERT_EQ(g.segments.size(), 2u);
  EXPECT_V3(g.segments[0].to, std::sin(0.5f), std::cos(0.5f), 0);
  // Second F: |H × D| = 0.5·cos(0.5) → bends by that much more.
  float a = 0.5f + 0.5f * std::cos(0.5f);
  EXPECT_V3(g.segments[1].to, std::sin(0.5f) + std::sin(a), std::cos(0.5f) + std::cos(a), 0);
}

TEST(TurtleGeometry, CorrectedRotationOffFlipsPitchAndRoll) {
  Geometry on = draw("rot_on", "Up(90) F(1)");
  Geometry off = draw("rot_off", "Up(90) F(1)", "corrected rotation: off\n");
  ASSERT_EQ(on.segments.size(), 1u);
  ASSERT_EQ(off.segments.size(), 1u);
  EXPECT_V3(on.segments[0].to, 0, 0, 1);
  EXPECT_V3(off.segments[0].to, 0, 0, -1);
}

TEST(TurtleGeometry, LabelsCameraAndDynamicSurface) {
  Geometry g = draw("misc", "f(2) Label(\"tip\") SetColor(6) Camera DSurface(flat())", "",
                    {}, "SurfaceObj flat() { SurfaceObj s; for (int i = 0; i < 4; ++i) for (int j = 0; j < 4; ++j) "
                        "s.Set(4 * i + j, V3f(i / 3.f, j / 3.f, 0)); return s; }\n");
  ASSERT_EQ(g.labels.size(), 1u);
  EXPECT_EQ(g.labels[0].text, "tip");
  EXPECT_V3(g.labels[0].position, 0, 2, 0);
  ASSERT_TRUE(g.camera.has_value());
  EXPECT_V3(g.camera->position, 0, 2, 0);
  EXPECT_V3(g.camera->heading, 0, 1, 0);
  // DSurface: the default 10×10 grid of the flat patch; point (x,y,z) lands at P + x·(−L) + y·H.
  ASSERT_EQ(g.vertices.size(), 121u);
  EXPECT_EQ(g.triangleCount(), 200u);
  EXPECT_V3(g.vertices[0].position, 0, 2, 0);
  EXPECT_V3(g.vertices[120].position, 1, 3, 0);
  EXPECT_EQ(g.vertices[60].color, 6);
  EXPECT_NEAR(std::fabs(g.vertices[60].normal.z), 1, 1e-5);
}

TEST(TurtleGeometry, SurfaceAndMeshFromTheViewFile) {
  fs::path obj = scratch() / "tri.obj";
  writeFile(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  fs::path s = scratch() / "leaf.s";
  writeFlatSurface(s);
  Geometry g = draw("shapes", "Left(90) Mesh(0, 2) SetUPrecision(2) SetVPrecision(2) Surface(0, 3)",
                    "mesh: " + obj.string() + "\nsurface: " + s.string() + "\n");
  // After Left(90): H = (-1,0,0), L = (0,-1,0), so −L = (0,1,0). Mesh vertex (1,0,0)·2 → 2·(−L).
  ASSERT_GE(g.vertices.size(), 3u);
  EXPECT_V3(g.vertices[0].position, 0, 0, 0);
  EXPECT_V3(g.vertices[1].position, 0, 2, 0);
  EXPECT_V3(g.vertices[2].position, -2, 0, 0);
  // Surface(0, 3) at 2×2: 9 vertices; the far corner (1,1,0)·3 → 3·(−L) + 3·H = (-3, 3, 0).
  ASSERT_EQ(g.vertices.size(), 3u + 9u);
  bool corner = false;
  for (size_t i = 3; i < g.vertices.size(); ++i) {
    auto p = g.vertices[i].position;
    if (std::fabs(p.x + 3) < 1e-4 && std::fabs(p.y - 3) < 1e-4) corner = true;
  }
  EXPECT_TRUE(corner);
  EXPECT_EQ(g.triangleCount(), 1u + 8u);
}

TEST(TurtleGeometry, ContourFromFileShapesTheCylinder) {
  // A square contour (closed, 4 control points with multiplicity) drawn with 5 samples.
  fs::path con = scratch() / "square.con";
  writeFile(con, "cver 1 3\nname: square\npoints: 4 12\ntype: cr\nsamples: 5\n"
                 "1 1 0 3\n-1 1 0 3\n-1 -1 0 3\n1 -1 0 3\n");
  Geometry g = draw("contour", "CurrentContour(square) SetWidth(2) F(1)", "line style: cylinder\n", {con.string()});
  ASSERT_EQ(g.vertices.size(), 10u);
  // The square's samples are its corners (up to the curve's start); all points at |x| = |z| = 1.
  for (size_t i = 0; i < g.vertices.size(); i += 2) {
    EXPECT_NEAR(std::fabs(g.vertices[i].position.x), 1, 1e-3) << i;
    EXPECT_NEAR(std::fabs(g.vertices[i].position.z), 1, 1e-3) << i;
  }
}

}  // namespace

namespace {

TEST(TurtleGeometry, CurveFunctionsReadContours) {
  // old11.con: an open line from (0,0) to (0,2): arc length 2, midpoint (0,1).
  std::string con = std::string(LCJIT_TEST_DATA) + "/contours/old11.con";
  Geometry g = draw("curves", "MoveTo(curveX(old_line, 0.5), curveY(old_line, 0.5), 0) F(curveGAL(old_line))", "", {con});
  ASSERT_EQ(g.segments.size(), 1u);
  EXPECT_V3(g.segments[0].from, 0, 1, 0);
  EXPECT_V3(g.segments[0].to, 0, 3, 0);
}

}  // namespace

namespace {

TEST(TurtleGeometry, ScaledAndBlendedContours) {
  // ScaleContour(4, 2): half-axes 2 along L and 1 along U. BlendedContour(0, square, 0.5) mixes
  // the circle and the square sample by sample.
  fs::path con = scratch() / "square5.con";
  writeFile(con, "cver 1 3\nname: square5\npoints: 4 12\ntype: cr\nsamples: 5\n"
                 "0 1 0 3\n-1 0 0 3\n0 -1 0 3\n1 0 0 3\n");
  Geometry g = draw("blend", "ScaleContour(4, 2) StartGC F(1) EndGC ContourSides(5) SetWidth(2) StartGC "
                             "BlendedContour(0, square5, 0.5) F(1) EndGC",
                    "line style: cylinder\ncontour sides: 4\n", {con.string()});
  ASSERT_EQ(g.vertices.size(), 20u);
  // Ring point 0 of the circle is on +U (scaled by 2/2 = 1), point 1 on +L (scaled by 4/2 = 2).
  EXPECT_V3(g.vertices[0].position, 0, 0, 1);
  EXPECT_V3(g.vertices[2].position, -2, 0, 0);
  // The blended ring: circle point 0 (0,1) and square5's first sample (0,1) agree → +U.
  EXPECT_V3(g.vertices[10].position, 0, 1, 1);
}

// lpfg frames a picture by its view-volume turtle, which widens a cylinder F by the extent of the
// last contour selected in string order: its `]` does not put that back (vvturtle.cpp). The
// rectangle spans x in [-1, 3], y in [-1, 1]; with width 2 (half-width 1) along L = (-1, 0, 0)
// an F from the origin reaches x = -3 (+L side, factor 3) and x = 1 (-L side, factor 1).
TEST(TurtleGeometry, ViewVolumeWidensByTheLastContourSelected) {
  fs::path con = scratch() / "rect.con";
  writeFile(con, "cver 1 3\nname: rect\npoints: 4 12\ntype: cr\nsamples: 1000\n"
                 "3 1 0 3\n-1 1 0 3\n-1 -1 0 3\n3 -1 0 3\n");
  const std::string view = "line style: cylinder\n";
  constexpr double kSampling = 0.02;  // 1000 samples of a 12-long outline may miss a corner
  Geometry a = draw("extent_branch", "SB CurrentContour(rect) EB SetWidth(2) F(1)", view, {con.string()});
  EXPECT_V3_NEAR(a.extent.min, -3, 0, -1, kSampling);
  EXPECT_V3_NEAR(a.extent.max, 1, 1, 1, kSampling);
  // A blend mixes the extents (max x: 0.5·1 + 0.5·3 = 2); an unknown id changes nothing.
  Geometry b = draw("extent_blend", "SB BlendedContour(0, rect, 0.5) EB CurrentContour(99) SetWidth(2) F(1)", view,
                    {con.string()});
  EXPECT_V3_NEAR(b.extent.min, -2, 0, -1, kSampling);
  EXPECT_V3_NEAR(b.extent.max, 1, 1, 1, kSampling);
  // The default circle (id 0) spans ±1.
  Geometry c = draw("extent_circle", "SB CurrentContour(rect) EB CurrentContour(0) SetWidth(2) F(1)", view,
                    {con.string()});
  EXPECT_V3(c.extent.min, -1, 0, -1);
  EXPECT_V3(c.extent.max, 1, 1, 1);
}

TEST(TurtleGeometry, ElasticityAndSimpleTropism) {
  // SetElasticity(0, 0) switches the view file's tropism off; Elasticity(0.5) with the simple
  // tropism direction D = (−1,0,0) leans H after each move by s = e·(D·L) = 0.5 towards L.
  Geometry g = draw("elastic", "SetElasticity(0, 0) F(1) SetTropismDirection3f(V3f(-1,0,0)) Elasticity(0.5) F(1) F(1)",
                    "tropism: T: 1 0 0 E: 0.5\n");
  ASSERT_EQ(g.segments.size(), 3u);
  EXPECT_V3(g.segments[0].to, 0, 1, 0);
  // Second F moves straight (the simple tropism applies after the move), then H leans towards
  // L = (−1,0,0) by s = 0.5: H = (c·0 + 0.5·(−1), c·1, 0) with c = sqrt(0.75).
  EXPECT_V3(g.segments[1].to, 0, 2, 0);
  EXPECT_V3(g.segments[2].to, -0.5, 2 + std::sqrt(0.75f), 0);
}

TEST(TurtleGeometry, UserSurfaceAndGetSurface) {
  fs::path s = scratch() / "leaf2.s";
  writeFlatSurface(s);
  // DSurface(GetSurface(0)) after f(5): the file's patch in the turtle frame. Then a user patch:
  // 16 SurfacePoints on a 3×3 grid at z = 7, drawn in world coordinates.
  std::string points;
  for (int q = 0; q < 4; ++q)
    for (int p = 0; p < 4; ++p)
      points += "MoveTo(" + std::to_string(p) + "," + std::to_string(q) + ",7) SurfacePoint(0," + std::to_string(p) + "," +
                std::to_string(q) + ") ";
  Geometry g = draw("usersurface", "SetUPrecision(2) SetVPrecision(2) f(5) DSurface(GetSurface(0)) InitSurface(0) " + points +
                                       "DrawSurface(0)", "surface: " + s.string() + "\n");
  ASSERT_EQ(g.vertices.size(), 18u);
  bool farCorner = false;
  for (size_t i = 0; i < 9; ++i)
    if (std::fabs(g.vertices[i].position.x - 1) < 1e-4 && std::fabs(g.vertices[i].position.y - 6) < 1e-4) farCorner = true;
  EXPECT_TRUE(farCorner) << "GetSurface's (1,1,0) corner at P + (−L) + H = (1, 6, 0)";
  for (size_t i = 9; i < 18; ++i) EXPECT_NEAR(g.vertices[i].position.z, 7, 1e-4);
  EXPECT_V3(g.extent.max, 3, 6, 7);
}

TEST(TurtleGeometry, CircleOutlinesAndColourCycling) {
  Geometry g = draw("rings", "SetWidth(0.5) ContourSides(4) CircleB(1) CircleFrontB(2) SetColor(255) IncColor "
                             "Circle0 SetColor(1) DecColor Sphere0");
  // CircleB(1): a ring of 4 inner (r 0.75) and 4 outer (r 1.25) points, 8 triangles.
  ASSERT_GE(g.vertices.size(), 8u);
  EXPECT_V3(g.vertices[0].position, 0, 0.75, 0);
  EXPECT_V3(g.vertices[1].position, 0, 1.25, 0);
  ASSERT_EQ(g.discs.size(), 1u);
  EXPECT_FLOAT_EQ(g.discs[0].inner, 1.75f);
  EXPECT_FLOAT_EQ(g.discs[0].outer, 2.25f);
  // IncColor wraps 255 → 1; Circle0's radius is width/2; DecColor wraps 1 → 255.
  EXPECT_EQ(g.vertices[8].color, 1);
  EXPECT_V3(g.vertices[9].position, 0, 0.25, 0);
  EXPECT_EQ(g.vertices.back().color, 255);
}

}  // namespace

namespace {

TEST(TurtleGeometry, CappedAndTaperedCylinders) {
  Geometry g = draw("caps", "SetWidth(2) StartGC SetWidth(1) F(2) EndGC",
                    "line style: cylinder\ncontour sides: 4\ncapped cylinders: on\ntapered cylinders: on\n");
  // Start cap (centre + 4), frustum (10), end cap (centre + 4).
  ASSERT_EQ(g.vertices.size(), 5u + 10u + 5u);
  EXPECT_EQ(g.triangleCount(), 4u + 8u + 4u);
  // Both caps face back along the heading (lpfg's rule), at y = 0 and y = 2.
  EXPECT_V3(g.vertices[0].position, 0, 0, 0);
  EXPECT_V3(g.vertices[0].normal, 0, -1, 0);
  EXPECT_V3(g.vertices[15].position, 0, 2, 0);
  EXPECT_V3(g.vertices[15].normal, 0, -1, 0);
  for (size_t i = 0; i < 4 * 3; i += 3) {
    auto a = g.vertices[g.indices[i]].position, b = g.vertices[g.indices[i + 1]].position,
         c = g.vertices[g.indices[i + 2]].position;
    EXPECT_LT(((b - a) % (c - a)).y, 0) << "cap triangles wind towards -H";
  }
  // Tapered: the frustum narrows from radius 1 to 0.5 over length 2; ring points 0 and 1 get the
  // normal of the face between (0,0,1), (−1,0,0) and (0,2,0.5): (−2, 0.5, 2)/|…|, leaning forward.
  float len = std::sqrt(8.25f);
  EXPECT_V3(g.vertices[5].normal, -2 / len, 0.5f / len, 2 / len);
  EXPECT_V3(g.vertices[6].normal, -2 / len, 0.5f / len, 2 / len);
}

}  // namespace

namespace {

TEST(TurtleGeometry, ViewGroupsDrawEachView) {
  // Multi-view (§7.3): `window:` names are view ids for UseView and `vgroup`; each view's
  // interpretation uses its own view group's rules.
  std::string extra = "module A;\nStart: { UseView(right); UseView(left); }\n";
  Geometry main = draw("multiview", "A", "window: left 0 0 0.5 1\nwindow: right 0.5 0 0.5 1\n", {},
                       extra + "interpretation:\nvgroup left:\nA : { produce F(1); }\nvgroup right:\n"
                               "A : { produce F(2) F(3); }\nendgroup\n");
  const auto& views = session().engine().views();
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0], 1);  // right, opened first
  EXPECT_EQ(views[1], 0);
  Geometry left, right;
  ASSERT_FALSE(bool(session().engine().interpret(left, 0)));
  ASSERT_FALSE(bool(session().engine().interpret(right, 1)));
  ASSERT_EQ(left.segments.size(), 1u);
  ASSERT_EQ(right.segments.size(), 2u);
  EXPECT_V3(right.segments[1].to, 0, 5, 0);
  (void)main;
}

// lpfg looks an interpretation rule up by production group and view group: the current
// production group's rules of the view's group, then production group 0's of the same view
// group, never another view group's (vlab's canalization-MV: the histogram view draws none of the
// flower view's petals).
TEST(TurtleGeometry, ViewGroupsDoNotBorrowEachOthersRules) {
  std::string extra =
      "module A;\nmodule B;\nStart: { UseView(left); UseView(right); }\n"
      "group 1:\nB : { produce B; }\nendgroup\n"
      "interpretation:\nvgroup left:\nA : { produce F(1); }\nvgroup right:\nB : { produce F(2); }\nendvgroup\n"
      "group 1:\nvgroup left:\nA : { produce F(4); }\nendvgroup\nendgroup\n";
  draw("viewgroups", "A B", "window: left 0 0 0.5 1\nwindow: right 0.5 0 0.5 1\n", {}, extra);
  runtime::Engine& engine = session().engine();
  Geometry left, right;
  ASSERT_FALSE(bool(engine.interpret(left, 0)));
  ASSERT_FALSE(bool(engine.interpret(right, 1)));
  // left: A draws F(1), B has no rule there; right: B draws F(2), A nothing (view 0's rule is not
  // borrowed).
  ASSERT_EQ(left.segments.size(), 1u);
  EXPECT_V3(left.segments[0].to, 0, 1, 0);
  ASSERT_EQ(right.segments.size(), 1u);
  EXPECT_V3(right.segments[0].to, 0, 2, 0);
  // In production group 1, A takes group 1's rule of its view; B falls back to group 0's.
  engine.useGroup(1);
  Geometry left1, right1;
  ASSERT_FALSE(bool(engine.interpret(left1, 0)));
  ASSERT_FALSE(bool(engine.interpret(right1, 1)));
  ASSERT_EQ(left1.segments.size(), 1u);
  EXPECT_V3(left1.segments[0].to, 0, 4, 0);
  ASSERT_EQ(right1.segments.size(), 1u);
  EXPECT_V3(right1.segments[0].to, 0, 2, 0);
  engine.useGroup(0);
}

}  // namespace
