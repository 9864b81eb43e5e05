// The view file (.v, manual §8.2): viewing, rendering, lights, external files, tropisms, fonts.
// Parsed from already-preprocessed text; unknown or malformed lines become warnings with
// file:line and the rest of the file still applies.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

struct Rgb {
  float r = 0, g = 0, b = 0;
};

enum class Projection { Parallel, Perspective };
enum class LineStyle { Pixel, Polygon, Cylinder };
enum class RenderMode { Filled, Wireframe, Shaded, Shadows };

// A default-constructed Light is lpfg's default light (LightSource::Default): directional from
// V: 0 0 1, ambient = diffuse = specular = 1 (lpfg's light ambient is white, not OpenGL's black).
// lpfg feeds these straight to glLight*: `position` has w = 0 for Directional, 1 otherwise.
struct Light {
  // O: makes the light positional, V: directional (the last of the two wins). P: sets the spot
  // parameters; the light is a Spot only if it is also positional (OpenGL ignores the spot
  // parameters of a directional light, so `light: P: …` alone stays Directional at V: 0 0 1).
  enum class Kind { Directional, Point, Spot } kind = Kind::Directional;
  V3f position{0, 0, 1};  // direction (V:, towards the light) or origin (O:)
  V3f spotDirection{0, 0, -1};
  float spotExponent = 0, spotCutoff = 180;  // degrees; 180 = no spot
  Rgb ambient{1, 1, 1}, diffuse{1, 1, 1}, specular{1, 1, 1};
  float attenuation[3] = {1, 0, 0};  // constant, linear, quadratic
};

// `view: id …` (new and deprecated forms): every field optional. Several `view:` lines with the
// same id merge into one entry (lpfg edits the window's modifiers in place). lpfg's defaults for
// an unset field once any is set: dir 0 0 -1, up 0 1 0, pan 0 0 0, fov 45, shift 0 (= computed
// from the bounding box), scale: the global `scale:`.
struct ViewDefinition {
  int id = 0;
  std::optional<V3f> dir, up, pan;
  std::optional<float> fov, shift;
  // In the sense of `scale:` (image size; lpfg's zoom is 1/scale). The deprecated form
  // `view: id rx ry rz zoom px py pz` gives the zoom itself, so it is stored here as 1/zoom; its
  // rotation angles (degrees about x, then y, then z) are applied to dir/up as lpfg does.
  std::optional<float> scale;
};
struct BoxDefinition {  // `box: id xmin xmax ymin ymax zmin zmax` (min < max on every axis)
  int id = 0;
  V3f min, max;
};
struct WindowDefinition {  // relative to the main window, 0,0 = top left
  std::string name;
  float left = 0, top = 0, width = 1, height = 1;
};

// `tropism:`/`torque:` T: A: I: E: S:. Values as written: `direction` is not multiplied by the
// intensity (lpfg stores direction*I), `angle` is in degrees (-180..180; lpfg stores radians).
// lpfg accepts a missing T: (default 0 -1 0), rejects a null T:, I: 0 and A: on torque.
struct Tropism {
  bool torque = false;  // `torque:` rotates about the heading only
  V3f direction{0, -1, 0};
  float angle = 0, intensity = 1, elasticity = 0, step = 0;
};
// `stropism: x y z, e` (the comma is required, as in lpfg): one simple tropism, the last wins.
// lpfg's default when none is given: direction 0 1 0, elasticity 0.
struct SimpleTropism {
  V3f direction{0, 1, 0};
  float elasticity = 0;
};

// `surface: file [scale [sdiv tdiv [texture]]]` (lpfg rejects 3 values; sdiv/tdiv in 2..64).
// A line repeating an earlier surface:/mesh: line exactly is not added again (lpfg rereads it).
struct SurfaceDeclaration {
  std::string file;  // as written, relative to the model directory
  float scale = 1;
  int sdiv = 0, tdiv = 0;  // 0: the surface's default precision
  int texture = -1;
};
// `bsurface: file [scale [sdiv tdiv [texture]]]` (manual §10.1): lpfg checks the values as for
// surface: (3 values, scale <= 0 or sdiv/tdiv outside 2..64 reject the line) but uses no scale.
// Every line adds a surface, repeated or not.
struct BSplineDeclaration {
  std::string file;
  int sdiv = 0, tdiv = 0;  // 0: not given
  int texture = -1;
};
// `terrain: file.patch levels scale offset grid txid UTiling VTiling` (manual §10.3), read as
// lpfg reads it (sscanf "%s %i %f %f %s %i %f %f": the values that read, the rest keep lpfg's
// defaults, which are not all the manual's: a missing tiling is 0, not 1). `grid` is on when the
// word starts with "on". lpfg rejects levels < 1, scale <= 0, a texture id below -1 and a negative
// tiling.
struct TerrainDeclaration {
  std::string file;
  int levels = 1;
  float scale = 1;
  float distance = 1;  // `offset`: the level-of-detail distance factor
  bool grid = false;
  int texture = -1;
  float uTiling = 0, vTiling = 0;
};
struct MeshDeclaration {
  std::string file;
  float scale = 1;
  int texture = -1;
  V3f contact{0, 0, 0};
};

// lpfg draws as many sides as asked (up to 10000) in immediate mode and keeps nothing; lcjit
// keeps the geometry, and a sphere costs sides² (10000 sides took a small tree past
// 12 GB). Past these, more sides change no pixel (a 1000-pixel sphere of 128 slices is within
// 0.3 px of round), so the turtle draws at most these many.
constexpr int kMaxDrawnRingSides = 1000;
constexpr int kMaxDrawnSphereSlices = 128;

struct ViewSettings {
  Projection projection = Projection::Parallel;
  float scale = 0.9f;  // as written (`scale:`/`scale factor:`); lpfg's zoom is 1/scale
  // lpfg's source defaults (drawparam.cpp); the manual's table says 0.05 and 50.
  float minZoom = 0.0005f, maxZoom = 5000;
  LineStyle lineStyle = LineStyle::Pixel;
  std::optional<float> frontDistance, backDistance;  // both or neither
  enum class Regenerate { Off, On, Triggered } generateOnViewChange = Regenerate::Off;
  std::vector<ViewDefinition> views;
  std::vector<BoxDefinition> boxes;
  std::vector<WindowDefinition> windows;
  int windowBorderSize = 1;
  Rgb windowBorderColor{0, 0, 0};

  bool zBuffer = false;
  RenderMode renderMode = RenderMode::Filled;
  // Empty: lpfg's default light, Light{}. At most 8 (the manual; lpfg itself rejects the 8th).
  std::vector<Light> lights;
  int shadowMapSize = 1024;          // an odd size is made even (+1), as lpfg does
  Rgb shadowColor{0.2f, 0.2f, 0.4f};  // clamped to 0..1
  float shadowOffsetFactor = 5, shadowOffsetUnits = 10;  // clamped to >= 0
  bool stationaryLights = true;
  int contourSides = 16;  // lpfg's drawparam.cpp default (the manual gives none); clamped to 3..10000
  bool backfaceCulling = false;
  bool concavePolygons = false;
  int gradientDirection = 0;  // 0 off, 1 left to right, 2 bottom to top (PostScript output)
  float gradientMagnitude = 0;
  // Further lpfg commands (drawparam.cpp) not in the manual's tables:
  int antialiasingSamples = 0;       // `antialiasing: n` (0..10; multisampling)
  float wireframeLineWidth = 1;      // `wireframe line width: w` (glLineWidth in wireframe mode)
  bool cappedCylinders = false;      // `capped cylinders: on|off`
  bool taperedCylinders = false;     // `tapered cylinders: on|off`
  bool automaticNormals = false;     // `auto normals: on|off`
  int postscriptLinecap = 0;         // `PS linecap: 0|1|2`

  std::vector<SurfaceDeclaration> surfaces;
  std::vector<MeshDeclaration> meshes;
  std::vector<std::string> textures;  // texture ids in order, from 0
  std::vector<BSplineDeclaration> bsurfaces;  // `bsurface:` (B-spline surfaces)
  std::optional<TerrainDeclaration> terrain;  // the last `terrain:` line

  std::vector<Tropism> tropisms;
  std::optional<SimpleTropism> simpleTropism;  // `stropism:`
  std::string font;                    // `font:` (X font name, as written)
  // The label font, as lpfg's Qt build makes it on Linux: `font:` (an XLFD name: family,
  // weight, slant, size in points) sets it; `winfont: name size` changes it only when flags
  // follow the size (then its weight is bold without a b flag, normal with one: lpfg's quirk).
  // The default is Times, 12 points. Weights are Qt's: 25 light, 50 normal, 63 demibold
  // (XLFD "medium"), 75 bold, 87 black.
  std::string winFont = "Times";
  int winFontSize = 12;
  int winFontWeight = 50;
  bool winFontItalic = false;
  bool winFontBold() const { return winFontWeight >= 63; }
  bool correctedRotation = true;
  bool correctedRotationGiven = false;  // lpfg warns when `corrected rotation:` is missing
};

struct ViewFileWarning {
  std::string file;
  int line = 0, column = 1;
  std::string message;
};

// A `view:` line for `v` (the new form, only the fields it has): what Save as… writes as "view
// parameters", and what parseViewFile reads back.
std::string viewLine(const ViewDefinition& v);

// `text` is the preprocessed view file; line markers (`# N "file"`, `#line N "file"`) map lines
// back to the source. Keywords are case-sensitive and matched at the start of the line (leading
// blanks are tolerated); a command that lpfg would reject is left out with a warning.
ViewSettings parseViewFile(std::string_view text, const std::string& fileName,
                           std::vector<ViewFileWarning>& warnings);

}  // namespace lcjit::runtime
