// The view file reader (runtime/files/ViewFile): every command of manual §8.2 plus lpfg's extra
// ones, lpfg's defaults, warnings (with file:line through cpp line markers), garbage input.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "runtime/files/ViewFile.h"

using namespace lcjit::runtime;

namespace {

ViewSettings parse(std::string_view text, std::vector<ViewFileWarning>& warnings) {
  return parseViewFile(text, "test.v", warnings);
}
ViewSettings parseClean(std::string_view text) {
  std::vector<ViewFileWarning> warnings;
  ViewSettings vs = parse(text, warnings);
  for (const auto& w : warnings) ADD_FAILURE() << w.file << ":" << w.line << ":" << w.column << ": " << w.message;
  return vs;
}

#define EXPECT_V3(v, X, Y, Z)      \
  do {                             \
    EXPECT_FLOAT_EQ((v).x, (X));   \
    EXPECT_FLOAT_EQ((v).y, (Y));   \
    EXPECT_FLOAT_EQ((v).z, (Z));   \
  } while (0)
#define EXPECT_V3_NEAR(v, X, Y, Z)     \
  do {                                 \
    EXPECT_NEAR((v).x, (X), 1e-6f);    \
    EXPECT_NEAR((v).y, (Y), 1e-6f);    \
    EXPECT_NEAR((v).z, (Z), 1e-6f);    \
  } while (0)
#define EXPECT_RGB(c, R, G, B)     \
  do {                             \
    EXPECT_FLOAT_EQ((c).r, (R));   \
    EXPECT_FLOAT_EQ((c).g, (G));   \
    EXPECT_FLOAT_EQ((c).b, (B));   \
  } while (0)

}  // namespace

TEST(ViewFileDefaults, EmptyFileGivesLpfgDefaults) {
  ViewSettings vs = parseClean("");
  EXPECT_EQ(vs.projection, Projection::Parallel);
  EXPECT_FLOAT_EQ(vs.scale, 0.9f);
  EXPECT_FLOAT_EQ(vs.minZoom, 0.0005f);
  EXPECT_FLOAT_EQ(vs.maxZoom, 5000.0f);
  EXPECT_EQ(vs.lineStyle, LineStyle::Pixel);
  EXPECT_FALSE(vs.frontDistance);
  EXPECT_FALSE(vs.backDistance);
  EXPECT_EQ(vs.generateOnViewChange, ViewSettings::Regenerate::Off);
  EXPECT_TRUE(vs.views.empty() && vs.boxes.empty() && vs.windows.empty());
  EXPECT_EQ(vs.windowBorderSize, 1);
  EXPECT_RGB(vs.windowBorderColor, 0, 0, 0);
  EXPECT_FALSE(vs.zBuffer);
  EXPECT_EQ(vs.renderMode, RenderMode::Filled);
  EXPECT_TRUE(vs.lights.empty());
  EXPECT_EQ(vs.shadowMapSize, 1024);
  EXPECT_RGB(vs.shadowColor, 0.2f, 0.2f, 0.4f);
  EXPECT_FLOAT_EQ(vs.shadowOffsetFactor, 5);
  EXPECT_FLOAT_EQ(vs.shadowOffsetUnits, 10);
  EXPECT_TRUE(vs.stationaryLights);
  EXPECT_EQ(vs.contourSides, 16);
  EXPECT_FALSE(vs.backfaceCulling);
  EXPECT_FALSE(vs.concavePolygons);
  EXPECT_EQ(vs.gradientDirection, 0);
  EXPECT_EQ(vs.antialiasingSamples, 0);
  EXPECT_FLOAT_EQ(vs.wireframeLineWidth, 1);
  EXPECT_FALSE(vs.cappedCylinders || vs.taperedCylinders || vs.automaticNormals);
  EXPECT_TRUE(vs.surfaces.empty() && vs.meshes.empty() && vs.textures.empty());
  EXPECT_TRUE(vs.tropisms.empty());
  EXPECT_FALSE(vs.simpleTropism);
  EXPECT_EQ(vs.winFont, "Times");
  EXPECT_EQ(vs.winFontSize, 12);
  EXPECT_TRUE(vs.correctedRotation);
  EXPECT_FALSE(vs.correctedRotationGiven);
}

TEST(ViewFileDefaults, DefaultLightIsLpfgs) {
  Light l;  // what the renderer uses when vs.lights is empty
  EXPECT_EQ(l.kind, Light::Kind::Directional);
  EXPECT_V3(l.position, 0, 0, 1);
  EXPECT_RGB(l.ambient, 1, 1, 1);
  EXPECT_RGB(l.diffuse, 1, 1, 1);
  EXPECT_RGB(l.specular, 1, 1, 1);
  EXPECT_FLOAT_EQ(l.spotCutoff, 180);
  EXPECT_FLOAT_EQ(l.attenuation[0], 1);
  EXPECT_FLOAT_EQ(l.attenuation[1], 0);
}

TEST(ViewFileSetting, ViewCommands) {
  ViewSettings vs = parseClean(
      "projection: perspective\n"
      "scale factor: 1.25\n"
      "min zoom: 0.1\n"
      "max zoom: 20\n"
      "line style: cylinder\n"
      "front distance: -5\n"
      "back distance: 7.5\n"
      "generate on view change: triggered\n");
  EXPECT_EQ(vs.projection, Projection::Perspective);
  EXPECT_FLOAT_EQ(vs.scale, 1.25f);
  EXPECT_FLOAT_EQ(vs.minZoom, 0.1f);
  EXPECT_FLOAT_EQ(vs.maxZoom, 20);
  EXPECT_EQ(vs.lineStyle, LineStyle::Cylinder);
  EXPECT_FLOAT_EQ(*vs.frontDistance, -5);
  EXPECT_FLOAT_EQ(*vs.backDistance, 7.5f);
  EXPECT_EQ(vs.generateOnViewChange, ViewSettings::Regenerate::Triggered);

  vs = parseClean("scale: 0.5\nscale factor: 2\nprojection: parallel\nline style: polygon\n"
                  "generate on view change: on\n");
  EXPECT_FLOAT_EQ(vs.scale, 2);  // the last one wins
  EXPECT_EQ(vs.projection, Projection::Parallel);
  EXPECT_EQ(vs.lineStyle, LineStyle::Polygon);
  EXPECT_EQ(vs.generateOnViewChange, ViewSettings::Regenerate::On);
}

TEST(ViewFileSetting, BadValuesWarnAndKeepDefaults) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "scale: 0\n"
      "line style: dotted\n"
      "projection: fisheye\n"
      "generate on view change: sometimes\n"
      "min zoom: small\n",
      w);
  ASSERT_EQ(w.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(w[i].line, i + 1);
    EXPECT_EQ(w[i].file, "test.v");
  }
  EXPECT_EQ(w[1].column, 13);  // "dotted"
  EXPECT_FLOAT_EQ(vs.scale, 0.9f);
  EXPECT_EQ(vs.lineStyle, LineStyle::Pixel);
  EXPECT_EQ(vs.projection, Projection::Parallel);
  EXPECT_FLOAT_EQ(vs.minZoom, 0.0005f);
}

TEST(ViewFileViews, NewFormItemsMergePerId) {
  ViewSettings vs = parseClean(
      "view: 0 dir: 0 0 1 up: 1 0 0\n"
      "view: 0 pan: 1.5 -2 3e-1 fov: 30 shift: 8 scale: 2\n");
  ASSERT_EQ(vs.views.size(), 1u);
  const ViewDefinition& v = vs.views[0];
  EXPECT_EQ(v.id, 0);
  EXPECT_V3(*v.dir, 0, 0, 1);
  EXPECT_V3(*v.up, 1, 0, 0);
  EXPECT_V3(*v.pan, 1.5f, -2, 0.3f);
  EXPECT_FLOAT_EQ(*v.fov, 30);
  EXPECT_FLOAT_EQ(*v.shift, 8);
  EXPECT_FLOAT_EQ(*v.scale, 2);

  vs = parseClean("view: 0 shift: 8 fov: 90\n");
  ASSERT_EQ(vs.views.size(), 1u);
  EXPECT_FALSE(vs.views[0].dir);
  EXPECT_FALSE(vs.views[0].scale);
  EXPECT_FLOAT_EQ(*vs.views[0].shift, 8);
  EXPECT_FLOAT_EQ(*vs.views[0].fov, 90);
}

TEST(ViewFileViews, ItemsOnFollowingLines) {
  // The manual's table lists the items one per line; lpfg reads only the view: line. They are
  // applied to the view: just above, with a warning each; `scale:` alone stays the global command.
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("view: 0\ndir: 0 0 1\n  up: 1 0 0 fov: 20\nscale: 2\npan: 1 1 1\n", w);
  ASSERT_EQ(vs.views.size(), 1u);
  EXPECT_V3(*vs.views[0].dir, 0, 0, 1);
  EXPECT_V3(*vs.views[0].up, 1, 0, 0);
  EXPECT_FLOAT_EQ(*vs.views[0].fov, 20);
  EXPECT_FALSE(vs.views[0].scale);
  EXPECT_FLOAT_EQ(vs.scale, 2);
  EXPECT_FALSE(vs.views[0].pan);  // not right after the view: lines any more
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].line, 2);
  EXPECT_EQ(w[1].line, 3);
  EXPECT_EQ(w[1].column, 3);
  EXPECT_EQ(w[2].line, 5);
}

TEST(ViewFileViews, DeprecatedForm) {
  // view: id rx ry rz zoom px py pz; lpfg's zoom is the reciprocal of scale:.
  ViewSettings vs = parseClean("view: 0 0 0 0 4 0.977504 -1.38001 0\n");
  ASSERT_EQ(vs.views.size(), 1u);
  const ViewDefinition& v = vs.views[0];
  EXPECT_FLOAT_EQ(*v.scale, 0.25f);
  EXPECT_V3(*v.pan, 0.977504f, -1.38001f, 0);
  EXPECT_V3_NEAR(*v.dir, 0, 0, -1);
  EXPECT_V3_NEAR(*v.up, 0, 1, 0);
  EXPECT_FALSE(v.shift);

  // rx = 90: lpfg rotates with q⁻¹ v q, i.e. by -90° about x: (0,0,-1) -> (0,-1,0), (0,1,0) -> (0,0,-1).
  vs = parseClean("view: 0 90 0 0 1 0 0 0\n");
  EXPECT_V3_NEAR(*vs.views[0].dir, 0, -1, 0);
  EXPECT_V3_NEAR(*vs.views[0].up, 0, 0, -1);
  // rz = 90 leaves dir along z and turns up (0,1,0) by -90° about z to (1,0,0).
  vs = parseClean("view: 0 0 0 90 1 0 0 0\n");
  EXPECT_V3_NEAR(*vs.views[0].dir, 0, 0, -1);
  EXPECT_V3_NEAR(*vs.views[0].up, 1, 0, 0);
}

TEST(ViewFileViews, WindowsBoxesAndIds) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "window: FlowerHead 0 0 0.4 1.0\n"
      "window: Histogram 0.4 0.0 0.6 1.0\n"
      "window border: 15 0 255 255\n"
      "box: 1 -16 16 -16 16 -1 1\n"
      "box: 0 0 1 0 2 0 3\n"
      "view: 1 dir: 0 0 -1\n"
      "view: 2 fov: 10\n"             // only windows 0 and 1 exist
      "box: 0 1 0 0 1 0 1\n"          // xmin >= xmax
      "box: x: -50,50 y: -50,50\n"    // cpfg syntax
      "view: zero dir: 0 0 1\n",
      w);
  ASSERT_EQ(vs.windows.size(), 2u);
  EXPECT_EQ(vs.windows[0].name, "FlowerHead");
  EXPECT_FLOAT_EQ(vs.windows[0].width, 0.4f);
  EXPECT_EQ(vs.windows[1].name, "Histogram");
  EXPECT_FLOAT_EQ(vs.windows[1].left, 0.4f);
  EXPECT_FLOAT_EQ(vs.windows[1].top, 0);
  EXPECT_FLOAT_EQ(vs.windows[1].width, 0.6f);
  EXPECT_FLOAT_EQ(vs.windows[1].height, 1);
  EXPECT_EQ(vs.windowBorderSize, 15);
  EXPECT_RGB(vs.windowBorderColor, 0, 1, 1);
  ASSERT_EQ(vs.boxes.size(), 2u);
  EXPECT_EQ(vs.boxes[0].id, 1);
  EXPECT_V3(vs.boxes[0].min, -16, -16, -1);
  EXPECT_V3(vs.boxes[0].max, 16, 16, 1);
  EXPECT_EQ(vs.boxes[1].id, 0);
  EXPECT_V3(vs.boxes[1].min, 0, 0, 0);
  EXPECT_V3(vs.boxes[1].max, 1, 2, 3);
  ASSERT_EQ(vs.views.size(), 1u);
  EXPECT_EQ(vs.views[0].id, 1);
  ASSERT_EQ(w.size(), 4u);
  EXPECT_EQ(w[0].line, 7);
  EXPECT_EQ(w[1].line, 8);
  EXPECT_EQ(w[2].line, 9);
  EXPECT_EQ(w[3].line, 10);

  // view:/box: before any window: only id 0 is valid.
  w.clear();
  vs = parse("view: 1 fov: 10\nbox: 0 0 1 0 1 0 1\n", w);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(vs.boxes.size(), 1u);
}

TEST(ViewFileViews, BadViewItemKeepsWhatWasRead) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("view: 0 dir: 1 0 0 zoom: 3 up: 0 0 1\nview: 0 pan: 1 2\n", w);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(w[0].column, 20);  // "zoom:"
  EXPECT_EQ(w[1].line, 2);
  ASSERT_EQ(vs.views.size(), 1u);
  EXPECT_V3(*vs.views[0].dir, 1, 0, 0);  // lpfg applies items as it reads them
  EXPECT_FALSE(vs.views[0].up);
  EXPECT_FALSE(vs.views[0].pan);
}

TEST(ViewFileLights, EachKind) {
  ViewSettings vs = parseClean(
      "light: V: 0 1 0 D: 0.3 0.5 0.3\n"
      "light: O: 10 10 -5\n"
      "light: O: 4.0 5.0 8.0  A:0 0 0 D: 1 0.3 0.3  P: -4 -4 -8 2 40 \n"
      "light: P: 0 0 -1 1 30\n"
      "light: V: -0.5 -1.0 -3.0 A: 0.6 0.6 0.6 D 0.6 0.6 0.6 S: 0.1 0.2 0.3 T: 1 0.5 0.25\n");
  ASSERT_EQ(vs.lights.size(), 5u);
  const Light& d = vs.lights[0];
  EXPECT_EQ(d.kind, Light::Kind::Directional);
  EXPECT_V3(d.position, 0, 1, 0);
  EXPECT_RGB(d.diffuse, 0.3f, 0.5f, 0.3f);
  EXPECT_RGB(d.ambient, 1, 1, 1);  // lpfg's light default
  EXPECT_RGB(d.specular, 1, 1, 1);

  const Light& p = vs.lights[1];
  EXPECT_EQ(p.kind, Light::Kind::Point);
  EXPECT_V3(p.position, 10, 10, -5);

  const Light& s = vs.lights[2];
  EXPECT_EQ(s.kind, Light::Kind::Spot);
  EXPECT_V3(s.position, 4, 5, 8);
  EXPECT_RGB(s.ambient, 0, 0, 0);
  EXPECT_RGB(s.diffuse, 1, 0.3f, 0.3f);
  EXPECT_V3(s.spotDirection, -4, -4, -8);
  EXPECT_FLOAT_EQ(s.spotExponent, 2);
  EXPECT_FLOAT_EQ(s.spotCutoff, 40);

  // P: without O: keeps lpfg's directional position (0,0,1): OpenGL ignores the spot.
  const Light& ps = vs.lights[3];
  EXPECT_EQ(ps.kind, Light::Kind::Directional);
  EXPECT_V3(ps.position, 0, 0, 1);
  EXPECT_FLOAT_EQ(ps.spotCutoff, 30);

  const Light& all = vs.lights[4];
  EXPECT_EQ(all.kind, Light::Kind::Directional);
  EXPECT_V3(all.position, -0.5f, -1, -3);
  EXPECT_RGB(all.ambient, 0.6f, 0.6f, 0.6f);
  EXPECT_RGB(all.diffuse, 0.6f, 0.6f, 0.6f);  // "D 0.6…" without the colon: lpfg reads it
  EXPECT_RGB(all.specular, 0.1f, 0.2f, 0.3f);
  EXPECT_FLOAT_EQ(all.attenuation[0], 1);
  EXPECT_FLOAT_EQ(all.attenuation[1], 0.5f);
  EXPECT_FLOAT_EQ(all.attenuation[2], 0.25f);
}

TEST(ViewFileLights, MalformedAndTooMany) {
  std::vector<ViewFileWarning> w;
  std::string text =
      "light: V: 0.5,1.0,3.0\n"  // lpfg's ReadFloats does not split at commas
      "light: Q: 1 2 3\n"
      "light: V: 1 2\n"
      "light:\n";
  for (int i = 0; i < 9; ++i) text += "light: V: " + std::to_string(i) + " 0 1\n";
  ViewSettings vs = parse(text, w);
  ASSERT_EQ(w.size(), 5u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(w[0].column, 8);  // "V:"
  EXPECT_EQ(w[1].line, 2);
  EXPECT_EQ(w[2].line, 3);
  EXPECT_EQ(w[3].line, 4);
  EXPECT_EQ(w[4].line, 13);  // the 9th light
  ASSERT_EQ(vs.lights.size(), 8u);
  EXPECT_V3(vs.lights[7].position, 7, 0, 1);
}

TEST(ViewFileRendering, ContourSidesPastWhatIsDrawnWarn) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("contour sides: 65536\n", w);
  // lpfg's clamp to 10000, then lcjit's note that it draws fewer.
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(vs.contourSides, 10000);
  EXPECT_NE(w[0].message.find("using 10000"), std::string::npos) << w[0].message;
  EXPECT_NE(w[1].message.find("at most 128"), std::string::npos) << w[1].message;
  w.clear();
  parse("contour sides: 128\n", w);
  EXPECT_TRUE(w.empty());
}

TEST(ViewFileRendering, Commands) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "z buffer: on\n"
      "render mode: shadows\n"
      "shadow map: size: 513 color: 1.5 0.5 -1 offset: 2.5 -3\n"
      "stationary lights: off\n"
      "contour sides: 2\n"
      "backface culling: on\n"
      "concave polygons: on\n"
      "gradient: 2 -0.5\n"
      "corrected rotation: off\n"
      "antialiasing: 4\n"
      "wireframe line width: 2.5\n"
      "capped cylinders: on\n"
      "tapered cylinders: on\n"
      "auto normals: on\n"
      "PS linecap: 1\n"
      "rotation: 1 2 3\n"
      "function: f.func\n",
      w);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].line, 3);  // odd shadow map size
  EXPECT_EQ(w[0].column, 13);
  EXPECT_EQ(w[1].line, 5);  // contour sides below 3
  EXPECT_TRUE(vs.zBuffer);
  EXPECT_EQ(vs.renderMode, RenderMode::Shadows);
  EXPECT_EQ(vs.shadowMapSize, 514);
  EXPECT_RGB(vs.shadowColor, 1, 0.5f, 0);
  EXPECT_FLOAT_EQ(vs.shadowOffsetFactor, 2.5f);
  EXPECT_FLOAT_EQ(vs.shadowOffsetUnits, 0);
  EXPECT_FALSE(vs.stationaryLights);
  EXPECT_EQ(vs.contourSides, 3);
  EXPECT_TRUE(vs.backfaceCulling);
  EXPECT_TRUE(vs.concavePolygons);
  EXPECT_EQ(vs.gradientDirection, 2);
  EXPECT_FLOAT_EQ(vs.gradientMagnitude, -0.5f);
  EXPECT_FALSE(vs.correctedRotation);
  EXPECT_TRUE(vs.correctedRotationGiven);
  EXPECT_EQ(vs.antialiasingSamples, 4);
  EXPECT_FLOAT_EQ(vs.wireframeLineWidth, 2.5f);
  EXPECT_TRUE(vs.cappedCylinders && vs.taperedCylinders && vs.automaticNormals);
  EXPECT_EQ(vs.postscriptLinecap, 1);

  vs = parseClean("render mode: wireframe\ncontour sides: 24\nshadow map: size: 4096\n");
  EXPECT_EQ(vs.renderMode, RenderMode::Wireframe);
  EXPECT_EQ(vs.contourSides, 24);
  EXPECT_EQ(vs.shadowMapSize, 4096);
  EXPECT_RGB(vs.shadowColor, 0.2f, 0.2f, 0.4f);

  w.clear();
  vs = parse("z buffer: yes\nbackface culling: on off\nrender mode: filled extra\ngradient: 3 1\n"
             "shadow map: size: big\nshadow map: blur: 3\n",
             w);
  EXPECT_EQ(w.size(), 6u);
  EXPECT_FALSE(vs.zBuffer);
  EXPECT_FALSE(vs.backfaceCulling);
  EXPECT_EQ(vs.gradientDirection, 0);
}

TEST(ViewFileExternal, MeshTextureIdOutOfRange) {
  // Found by fuzz_view: the id was converted to int unchecked (UBSan: 3.3e+27 outside int).
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("mesh: a.obj T: 3333333333333333333333333330 S: 2\nmesh: b.obj T: nan\n", w);
  ASSERT_EQ(vs.meshes.size(), 2u);
  EXPECT_EQ(vs.meshes[0].texture, -1);
  EXPECT_FLOAT_EQ(vs.meshes[0].scale, 2);
  EXPECT_EQ(vs.meshes[1].texture, -1);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_NE(w[0].message.find("texture id"), std::string::npos) << w[0].message;
  EXPECT_EQ(w[1].line, 2);
}

TEST(ViewFileExternal, SurfacesMeshesTextures) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "surface: leaf.s\n"
      "surface: petal.s 0.5\n"
      "surface: sepal.s 2 8 12\n"
      "surface: stem.s 1.5 4 4 1\n"
      "surface: leaf.s\n"           // the same line again: lpfg rereads, adds nothing
      "surface: bad.s 1 8\n"        // sdiv without tdiv
      "surface: bad2.s 1 65 8\n"    // sdiv > 64
      "mesh: bunny.obj S: 2 T: 1 C: 0.5 0 -1\n"
      "mesh: cube.ply\n"
      "mesh: odd.obj S: 2 Q: 1\n"   // lpfg complains and still loads it
      "mesh: broken.obj C: 1 2\n"
      "texture: bark.rgb\n"
      "texture: leaf.png\n"
      "bsurface: b.s\n"
      "terrain: ground.ter\n",
      w);
  ASSERT_EQ(vs.surfaces.size(), 4u);
  EXPECT_EQ(vs.surfaces[0].file, "leaf.s");
  EXPECT_FLOAT_EQ(vs.surfaces[0].scale, 1);
  EXPECT_EQ(vs.surfaces[0].sdiv, 0);
  EXPECT_EQ(vs.surfaces[0].texture, -1);
  EXPECT_FLOAT_EQ(vs.surfaces[1].scale, 0.5f);
  EXPECT_FLOAT_EQ(vs.surfaces[2].scale, 2);
  EXPECT_EQ(vs.surfaces[2].sdiv, 8);
  EXPECT_EQ(vs.surfaces[2].tdiv, 12);
  EXPECT_EQ(vs.surfaces[2].texture, -1);
  EXPECT_EQ(vs.surfaces[3].file, "stem.s");
  EXPECT_EQ(vs.surfaces[3].texture, 1);
  ASSERT_EQ(vs.meshes.size(), 3u);
  EXPECT_EQ(vs.meshes[0].file, "bunny.obj");
  EXPECT_FLOAT_EQ(vs.meshes[0].scale, 2);
  EXPECT_EQ(vs.meshes[0].texture, 1);
  EXPECT_V3(vs.meshes[0].contact, 0.5f, 0, -1);
  EXPECT_EQ(vs.meshes[1].file, "cube.ply");
  EXPECT_FLOAT_EQ(vs.meshes[1].scale, 1);
  EXPECT_EQ(vs.meshes[1].texture, -1);
  EXPECT_EQ(vs.meshes[2].file, "odd.obj");
  EXPECT_FLOAT_EQ(vs.meshes[2].scale, 2);
  ASSERT_EQ(vs.textures.size(), 2u);
  EXPECT_EQ(vs.textures[1], "leaf.png");
  ASSERT_EQ(vs.bsurfaces.size(), 1u);
  EXPECT_EQ(vs.bsurfaces[0].file, "b.s");
  ASSERT_TRUE(vs.terrain);
  EXPECT_EQ(vs.terrain->file, "ground.ter");
  ASSERT_EQ(w.size(), 4u);
  EXPECT_EQ(w[0].line, 6);
  EXPECT_EQ(w[1].line, 7);
  EXPECT_EQ(w[2].line, 10);
  EXPECT_EQ(w[2].column, 20);  // "Q:"
  EXPECT_EQ(w[3].line, 11);
}

// `bsurface:` lines as lpfg's b_wrapper reads them: 1, 2, 4 or 5 values; a positive scale;
// sdiv/tdiv in 2..64; every line adds a surface, a repeated one too.
TEST(ViewFileExternal, BSurfaceLines) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "bsurface: a.s\n"
      "bsurface: b.s 2.5\n"
      "bsurface: c.s 1 8 6\n"
      "bsurface: d.s 1 12 12 3\n"
      "bsurface: a.s\n"
      "bsurface: e.s 1 8\n"       // sdiv without tdiv
      "bsurface: f.s 0\n"         // scale 0
      "bsurface: g.s 1 1 8\n"     // sdiv < 2
      "bsurface: h.s 1 8 65 0\n"  // tdiv > 64
      "bsurface:\n",
      w);
  ASSERT_EQ(vs.bsurfaces.size(), 5u);
  EXPECT_EQ(vs.bsurfaces[0].file, "a.s");
  EXPECT_EQ(vs.bsurfaces[0].sdiv, 0);
  EXPECT_EQ(vs.bsurfaces[0].texture, -1);
  EXPECT_EQ(vs.bsurfaces[1].file, "b.s");
  EXPECT_EQ(vs.bsurfaces[1].sdiv, 0);
  EXPECT_EQ(vs.bsurfaces[2].sdiv, 8);
  EXPECT_EQ(vs.bsurfaces[2].tdiv, 6);
  EXPECT_EQ(vs.bsurfaces[2].texture, -1);
  EXPECT_EQ(vs.bsurfaces[3].sdiv, 12);
  EXPECT_EQ(vs.bsurfaces[3].texture, 3);
  EXPECT_EQ(vs.bsurfaces[4].file, "a.s");
  ASSERT_EQ(w.size(), 5u);
  EXPECT_EQ(w[0].line, 6);
  EXPECT_EQ(w[4].line, 10);
}

// `terrain: file.patch levels scale offset grid txid UTiling VTiling` (manual §10.3), read with
// lpfg's sscanf("%s %i %f %f %s %i %f %f"): the values that read, the rest lpfg's defaults.
TEST(ViewFileExternal, Terrain) {
  ViewSettings vs = parseClean("terrain: Terrain.patch 5 1 10 on 0 1.0 1.0\n");  // TerrainDemo's line
  ASSERT_TRUE(vs.terrain);
  EXPECT_EQ(vs.terrain->file, "Terrain.patch");
  EXPECT_EQ(vs.terrain->levels, 5);
  EXPECT_EQ(vs.terrain->scale, 1);
  EXPECT_EQ(vs.terrain->distance, 10);
  EXPECT_TRUE(vs.terrain->grid);
  EXPECT_EQ(vs.terrain->texture, 0);
  EXPECT_EQ(vs.terrain->uTiling, 1);
  EXPECT_EQ(vs.terrain->vTiling, 1);
  // Only the file: lpfg's defaults (the tiling is 0 in lpfg, not the manual's 1).
  vs = parseClean("terrain: hills.patch\n");
  ASSERT_TRUE(vs.terrain);
  EXPECT_EQ(vs.terrain->levels, 1);
  EXPECT_EQ(vs.terrain->scale, 1);
  EXPECT_EQ(vs.terrain->distance, 1);
  EXPECT_FALSE(vs.terrain->grid);
  EXPECT_EQ(vs.terrain->texture, -1);
  EXPECT_EQ(vs.terrain->uTiling, 0);
  EXPECT_EQ(vs.terrain->vTiling, 0);
  // %i reads 0x and 0 prefixes; "on" is a prefix test; reading stops at the first bad value.
  vs = parseClean("terrain: h.patch 0x3 2.5 0.5 onward 010 x 3\n");
  ASSERT_TRUE(vs.terrain);
  EXPECT_EQ(vs.terrain->levels, 3);
  EXPECT_EQ(vs.terrain->scale, 2.5f);
  EXPECT_EQ(vs.terrain->distance, 0.5f);
  EXPECT_TRUE(vs.terrain->grid);
  EXPECT_EQ(vs.terrain->texture, 8);
  EXPECT_EQ(vs.terrain->uTiling, 0);
  EXPECT_EQ(vs.terrain->vTiling, 0);
  // The last terrain: line wins.
  vs = parseClean("terrain: a.patch 2\nterrain: b.patch 3 1 1 off\n");
  ASSERT_TRUE(vs.terrain);
  EXPECT_EQ(vs.terrain->file, "b.patch");
  EXPECT_FALSE(vs.terrain->grid);
}

TEST(ViewFileExternal, BadTerrainLinesWarnAndLeaveNone) {
  // lpfg rejects these values (an exception while reading the line); its terrain is then
  // unusable, so there is none here.
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("terrain: a.patch 0\n"
                          "terrain: a.patch 11\n"
                          "terrain: a.patch 2 0\n"
                          "terrain: a.patch 2 1 1 on -2\n"
                          "terrain: a.patch 2 1 1 on 0 -1 1\n"
                          "terrain: a.patch 2 1 1 on 0 1 -1\n"
                          "terrain:\n",
                          w);
  EXPECT_FALSE(vs.terrain);
  ASSERT_EQ(w.size(), 7u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(w[0].column, 18);  // the levels
  EXPECT_EQ(w[0].message, "terrain: invalid number of levels 0");
  EXPECT_EQ(w[1].message, "terrain: at most 10 levels, not 11");
  EXPECT_EQ(w[2].column, 20);  // the scale
  EXPECT_EQ(w[2].message, "terrain: the scale must be positive");
  EXPECT_EQ(w[3].column, 27);  // the texture id
  EXPECT_EQ(w[3].message, "terrain: invalid texture id -2");
  EXPECT_EQ(w[4].column, 29);
  EXPECT_EQ(w[4].message, "terrain: the U tiling must not be negative");
  EXPECT_EQ(w[5].column, 31);
  EXPECT_EQ(w[5].message, "terrain: the V tiling must not be negative");
  EXPECT_EQ(w[6].line, 7);
  EXPECT_EQ(w[6].message, "terrain: needs a file name");
  // A bad line after a good one: no terrain (lpfg drops the first when it reads the second).
  w.clear();
  vs = parse("terrain: a.patch 2\nterrain: a.patch -1\n", w);
  EXPECT_FALSE(vs.terrain);
  EXPECT_EQ(w.size(), 1u);
}

TEST(ViewFileTropisms, TropismTorqueSimple) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(
      "tropism: T: 0.0  1.0 0.0  A:90 I: 2 E: 0.2 S: 0.01\n"
      "torque:  T: 0.0  0.0 1.0 E: 0.5\n"
      "tropism: E: 0.1\n"             // no T: lpfg keeps its default direction
      "torque: T: 0 1 0 A: 10\n"      // A: not allowed for torque
      "tropism: T: 0 0 0\n"           // null vector
      "tropism: T: 0 1 0 A: 200\n"
      "tropism: T: 0 1 0 I: 0\n"
      "tropism: T: 0,1,0 E: 0.2\n"    // commas: rejected as by lpfg
      "stropism: 0.0 1.0 0, 0.05\n"
      "stropism: 1 0 0 0.5\n",        // the comma is required
      w);
  ASSERT_EQ(vs.tropisms.size(), 3u);
  const Tropism& t = vs.tropisms[0];
  EXPECT_FALSE(t.torque);
  EXPECT_V3(t.direction, 0, 1, 0);
  EXPECT_FLOAT_EQ(t.angle, 90);
  EXPECT_FLOAT_EQ(t.intensity, 2);
  EXPECT_FLOAT_EQ(t.elasticity, 0.2f);
  EXPECT_FLOAT_EQ(t.step, 0.01f);
  const Tropism& q = vs.tropisms[1];
  EXPECT_TRUE(q.torque);
  EXPECT_V3(q.direction, 0, 0, 1);
  EXPECT_FLOAT_EQ(q.elasticity, 0.5f);
  EXPECT_FLOAT_EQ(q.intensity, 1);
  EXPECT_FLOAT_EQ(q.angle, 0);
  EXPECT_V3(vs.tropisms[2].direction, 0, -1, 0);
  EXPECT_FLOAT_EQ(vs.tropisms[2].elasticity, 0.1f);
  ASSERT_TRUE(vs.simpleTropism);
  EXPECT_V3(vs.simpleTropism->direction, 0, 1, 0);
  EXPECT_FLOAT_EQ(vs.simpleTropism->elasticity, 0.05f);
  ASSERT_EQ(w.size(), 6u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(w[i].line, i + 4);
  EXPECT_EQ(w[5].line, 10);
  EXPECT_EQ(w[0].column, 18);  // "A:" on the torque line
}

// The label font as lpfg's Linux build reads it (lpfg/drawparam.cpp, DrawParams::Font): an XLFD
// `font:` gives family, weight (medium is Qt's DemiBold), slant and size; `winfont:` only counts
// with flags after the size, and then its weight is the reverse of its b flag.
TEST(ViewFileFonts, XFontAndWinFont) {
  ViewSettings vs = parseClean("font: -adobe-helvetica-bold-italic-normal-*-24-*-*-*-*-*-*-*\n");
  EXPECT_EQ(vs.font, "-adobe-helvetica-bold-italic-normal-*-24-*-*-*-*-*-*-*");
  EXPECT_EQ(vs.winFont, "helvetica");
  EXPECT_EQ(vs.winFontSize, 24);
  EXPECT_EQ(vs.winFontWeight, 75);
  EXPECT_TRUE(vs.winFontItalic);

  vs = parseClean("font: -*-courier_new-medium-r-*-*-26-*-*-*-*-*-*-*\n");
  EXPECT_EQ(vs.winFont, "courier new");
  EXPECT_EQ(vs.winFontSize, 26);
  EXPECT_EQ(vs.winFontWeight, 63);
  EXPECT_FALSE(vs.winFontItalic);

  vs = parseClean("font: -*-*-*-r-*-*-10-*-*-*-*-*-*-*\n");
  EXPECT_EQ(vs.winFont, "Times");  // "*" family: the default
  EXPECT_EQ(vs.winFontSize, 10);
  EXPECT_EQ(vs.winFontWeight, 50);

  vs = parseClean("winfont: \"Times New Roman\" 18 bi\n");
  EXPECT_EQ(vs.winFont, "Times New Roman");
  EXPECT_EQ(vs.winFontSize, 18);
  EXPECT_EQ(vs.winFontWeight, 50);  // b: normal, in lpfg
  EXPECT_TRUE(vs.winFontItalic);

  vs = parseClean("winfont: Arial 9 i\n");
  EXPECT_EQ(vs.winFont, "Arial");
  EXPECT_EQ(vs.winFontWeight, 75);  // no b: bold, in lpfg
  EXPECT_TRUE(vs.winFontItalic);

  // Without flags lpfg keeps the font it had.
  vs = parseClean("winfont: Arial 9 i\nwinfont: Courier 11\n");
  EXPECT_EQ(vs.winFont, "Arial");
  EXPECT_EQ(vs.winFontSize, 9);
  vs = parseClean("winfont: \"Times\" 24\n");
  EXPECT_EQ(vs.winFontSize, 12);

  std::vector<ViewFileWarning> w;
  vs = parse("winfont: \"Times\"\nwinfont:\nfont:\n", w);
  EXPECT_EQ(w.size(), 3u);
  EXPECT_EQ(vs.winFont, "Times");
  EXPECT_EQ(vs.winFontSize, 12);
}

TEST(ViewFileLineMarkers, WarningsMapToSourceFiles) {
  std::ifstream in(std::string(LCJIT_TEST_DATA) + "/view/plant.i");
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parseViewFile(ss.str(), "plant.i", w);
  EXPECT_EQ(vs.projection, Projection::Perspective);
  EXPECT_FLOAT_EQ(vs.scale, 1.5f);
  ASSERT_EQ(vs.lights.size(), 1u);
  EXPECT_RGB(vs.lights[0].diffuse, 0.3f, 0.5f, 0.3f);
  ASSERT_EQ(vs.windows.size(), 2u);
  ASSERT_EQ(vs.views.size(), 1u);
  EXPECT_EQ(vs.views[0].id, 1);
  EXPECT_FLOAT_EQ(*vs.views[0].fov, 30);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_EQ(w[0].file, "lights.vh");
  EXPECT_EQ(w[0].line, 2);
  EXPECT_EQ(w[0].column, 20);  // "X:"
  EXPECT_EQ(w[1].file, "plant.v");
  EXPECT_EQ(w[1].line, 9);
  EXPECT_EQ(w[1].column, 11);  // "maybe"
}

TEST(ViewFileLineMarkers, LineDirectiveAndNoFileName) {
  std::vector<ViewFileWarning> w;
  // (A command last: a file with none is one warning, AFileWithNoCommandIsOneWarning.)
  parse("#line 40 \"dir/my view.v\"\nbogus\n# 7\n\nbogus again\n#pragma once\nbogus 3\nscale: 1\n", w);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].file, "dir/my view.v");
  EXPECT_EQ(w[0].line, 40);
  EXPECT_EQ(w[1].file, "dir/my view.v");
  EXPECT_EQ(w[1].line, 8);
  EXPECT_EQ(w[2].line, 10);
}

TEST(ViewFileSyntax, CaseIndentationAndLineEnds) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("Z Buffer: on\r\n   z buffer: on\r\n\trender mode: shaded   \r\n\r\n", w);
  ASSERT_EQ(w.size(), 1u);  // keywords are case-sensitive, as in lpfg
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(w[0].column, 1);
  EXPECT_TRUE(vs.zBuffer);
  EXPECT_EQ(vs.renderMode, RenderMode::Shaded);
}

TEST(ViewFileSyntax, EveryCommandWithoutArgumentsAndGarbage) {
  static const char* const labels[] = {
      "line style:", "z buffer:", "render mode:", "light:", "surface:", "texture:", "front distance:",
      "back distance:", "tropism:", "torque:", "projection:", "scale:", "scale factor:", "min zoom:",
      "max zoom:", "font:", "winfont:", "stropism:", "window:", "window border:", "contour sides:",
      "generate on view change:", "view:", "bsurface:", "box:", "corrected rotation:", "backface culling:",
      "terrain:", "concave polygons:", "gradient:", "PS linecap:", "stationary lights:", "auto normals:",
      "tapered cylinders:", "antialiasing:", "mesh:", "animated mesh:", "capped cylinders:",
      "wireframe line width:"};
  std::string text;
  for (const char* l : labels) text += std::string(l) + "\n" + l + " \x01\xff%s\"\n" + l + " 1e999 -nan ,,, :\n";
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse(text, w);
  EXPECT_GE(w.size(), std::size(labels));  // every empty command warns
  for (const auto& x : w) {
    EXPECT_GE(x.line, 1);
    EXPECT_LE(x.line, int(3 * std::size(labels)));
    EXPECT_GE(x.column, 1);
  }
  EXPECT_TRUE(vs.lights.empty());
  EXPECT_TRUE(vs.tropisms.empty());

  // Random bytes, NULs and very long lines.
  std::mt19937 rng(42);
  for (int round = 0; round < 50; ++round) {
    std::string junk;
    int n = int(rng() % 4000);
    for (int i = 0; i < n; ++i) {
      unsigned r = rng() % 100;
      if (r < 5) junk += '\n';
      else if (r < 10) junk += labels[rng() % std::size(labels)];
      else if (r < 15) junk += ' ';
      else if (r < 20) junk += "# ";
      else junk += char(rng() % 256);
    }
    std::vector<ViewFileWarning> ww;
    parseViewFile(junk, "junk.v", ww);
  }
  std::vector<ViewFileWarning> ww;
  parseViewFile(std::string(100000, 'x') + "\nlight: " + std::string(50000, '9'), "long.v", ww);
  EXPECT_EQ(ww.size(), 2u);
}

TEST(ViewFileWrite, ViewLineReadsBack) {
  ViewDefinition v;
  v.id = 0;
  v.dir = V3f(0, -0.5f, -1);
  v.up = V3f(0, 1, 0);
  v.pan = V3f(0.25f, 0, 0);
  v.scale = 1.5f;
  std::string line = viewLine(v);
  EXPECT_EQ(line, "view: 0 dir: 0 -0.5 -1 up: 0 1 0 pan: 0.25 0 0 scale: 1.5\n");
  std::vector<ViewFileWarning> warnings;
  ViewSettings s = parseViewFile(line, "saved.v", warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(s.views.size(), 1u);
  EXPECT_FLOAT_EQ(s.views[0].dir->y, -0.5f);
  EXPECT_FLOAT_EQ(s.views[0].pan->x, 0.25f);
  EXPECT_FLOAT_EQ(*s.views[0].scale, 1.5f);
  EXPECT_FALSE(s.views[0].fov.has_value());
}

// A file with no view-file command at all (random bytes gave a warning per line,
// raw bytes and all): one warning, at its first line.
TEST(ViewFileWarnings, AFileWithNoCommandIsOneWarning) {
  std::vector<ViewFileWarning> w;
  ViewSettings vs = parse("abc\x01\x7f def\nxyz 1 2\n\nq!\n", w);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].line, 1);
  EXPECT_EQ(w[0].column, 1);
  EXPECT_EQ(w[0].message, "this is not a view file: none of its 3 lines is a view-file command; it is ignored");
  EXPECT_EQ(vs.renderMode, ViewSettings().renderMode);
}

// With a command in it, each bad line is its own warning, shown as text: bytes that are not
// printable ASCII become '?'.
TEST(ViewFileWarnings, UnprintableBytesAreShownAsQuestionMarks) {
  std::vector<ViewFileWarning> w;
  parse("scale: 2\nab\x01\xff" "c\n", w);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].line, 2);
  EXPECT_EQ(w[0].message, "unrecognized command: ab??c");
}
