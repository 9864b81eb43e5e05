// The view file (.v, manual §8.2). Keywords, defaults and parsing tolerance follow lpfg's
// DrawParams (drawparam.cpp) and the readers it calls (lightsrc.cpp, tropism.cpp, surface.cpp,
// mesh.h, winparams.cpp, tropismdata.cpp): numbers are read the way lpfg's sscanf/ReadFloats
// read them, a command lpfg rejects is left out with a warning, everything else still applies.
#include "runtime/files/ViewFile.h"

#include <cstdio>

#include "runtime/files/TerrainPatches.h"
#include "runtime/files/Quaternion.h"
#include "runtime/files/TextLines.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <set>

namespace lcjit::runtime {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }
bool isAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

const char* skipBlanks(const char* p) {
  while (isBlank(*p)) ++p;
  return p;
}
const char* skipNonBlanks(const char* p) {
  while (*p && !isBlank(*p)) ++p;
  return p;
}

// sscanf("%f")-style: blanks, then the longest number prefix.
bool scanFloat(const char*& p, float& v) {
  const char* start = skipBlanks(p);
  char* end = nullptr;
  float x = std::strtof(start, &end);
  if (end == start) return false;
  v = x;
  p = end;
  return true;
}
// sscanf("%d")-style; base 0 is %i's (0x and 0 prefixes).
bool scanInt(const char*& p, int& v, int base = 10) {
  const char* start = skipBlanks(p);
  char* end = nullptr;
  errno = 0;
  long x = std::strtol(start, &end, base);
  if (end == start) return false;
  if (errno == ERANGE || x > INT_MAX || x < INT_MIN) x = x < 0 ? INT_MIN : INT_MAX;
  v = (int)x;
  p = end;
  return true;
}
int scanFloats(const char*& p, float* out, int n) {
  int i = 0;
  while (i < n && scanFloat(p, out[i])) ++i;
  return i;
}

// lpfg's Utils::ReadFloats: `n` blank-separated tokens, each read as a number prefix (the rest of
// a token such as "1,2" is skipped, so commas do not separate); leaves `p` on the next token.
bool tokenFloats(const char*& p, float* out, int n) {
  for (int i = 0; i < n; ++i) {
    p = skipBlanks(p);
    if (!*p) return false;
    char* end = nullptr;
    out[i] = std::strtof(p, &end);
    if (end == p) return false;
    p = skipNonBlanks(p);
  }
  p = skipBlanks(p);
  return true;
}

// After an item letter of light:/tropism:/mesh: (lpfg skips two characters: the letter and ':').
const char* afterItemLetter(const char* p) {
  ++p;
  if (*p == ':') ++p;
  return p;
}

// The next item label of view:/shadow map: lines: two letters in a row (so exponents such as
// 1.2e-009 are passed over), as lpfg looks for it.
const char* nextLabel(const char* p) {
  while (*p && !(isAlpha(p[0]) && (isAlpha(p[1]) || p[1] == 0))) ++p;
  return p;
}

std::string trimmed(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && isBlank(s[b])) ++b;
  while (e > b && isBlank(s[e - 1])) --e;
  return std::string(s.substr(b, e - b));
}

// The deprecated view: form's rotations (lpfg: DrawParams, Vector3d::RotateBy).
Quat axisAngle(float degrees, float ax, float ay, float az) {
  constexpr float kPi = 3.14159265358979f;
  float half = 0.5f * degrees * kPi / 180.0f;
  float s = std::sin(half);
  return {std::cos(half), s * ax, s * ay, s * az};
}

enum class Cmd {
  Preproc, LineStyle, ZBuffer, RenderMode, Light, Surface, Texture, FrontDist, BackDist, Tropism,
  Torque, Projection, Scale, ScaleFactor, MinZoom, MaxZoom, Rotation, Font, WinFont, STropism,
  Window, WindowBorder, ContourSides, GenerateOnViewChange, View, BSurface, Box,
  CorrectedRotation, BackfaceCulling, Terrain, ConcavePolygons, Gradient, Function, Gallery,
  ShadowMap, PSLinecap, StationaryLights, AutoNormals, TaperedCylinders, Antialiasing, Mesh,
  AnimatedMesh, CappedCylinders, WireframeLineWidth
};

// lpfg's label table (DrawParams::_strLabels), matched as prefixes in this order.
const struct {
  const char* label;
  Cmd cmd;
} kCommands[] = {
    {"#", Cmd::Preproc},
    {"line style:", Cmd::LineStyle},
    {"z buffer:", Cmd::ZBuffer},
    {"render mode:", Cmd::RenderMode},
    {"light:", Cmd::Light},
    {"surface:", Cmd::Surface},
    {"texture:", Cmd::Texture},
    {"front distance:", Cmd::FrontDist},
    {"back distance:", Cmd::BackDist},
    {"tropism:", Cmd::Tropism},
    {"torque:", Cmd::Torque},
    {"projection:", Cmd::Projection},
    {"scale:", Cmd::Scale},
    {"scale factor:", Cmd::ScaleFactor},
    {"min zoom:", Cmd::MinZoom},
    {"max zoom:", Cmd::MaxZoom},
    {"rotation:", Cmd::Rotation},
    {"font:", Cmd::Font},
    {"winfont:", Cmd::WinFont},
    {"stropism:", Cmd::STropism},
    {"window:", Cmd::Window},
    {"window border:", Cmd::WindowBorder},
    {"contour sides:", Cmd::ContourSides},
    {"generate on view change:", Cmd::GenerateOnViewChange},
    {"view:", Cmd::View},
    {"bsurface:", Cmd::BSurface},
    {"box:", Cmd::Box},
    {"corrected rotation:", Cmd::CorrectedRotation},
    {"backface culling:", Cmd::BackfaceCulling},
    {"terrain:", Cmd::Terrain},
    {"concave polygons:", Cmd::ConcavePolygons},
    {"gradient:", Cmd::Gradient},
    {"function:", Cmd::Function},
    {"gallery:", Cmd::Gallery},
    {"shadow map:", Cmd::ShadowMap},
    {"PS linecap:", Cmd::PSLinecap},
    {"stationary lights:", Cmd::StationaryLights},
    {"auto normals:", Cmd::AutoNormals},
    {"tapered cylinders:", Cmd::TaperedCylinders},
    {"antialiasing:", Cmd::Antialiasing},
    {"mesh:", Cmd::Mesh},
    {"animated mesh:", Cmd::AnimatedMesh},
    {"capped cylinders:", Cmd::CappedCylinders},
    {"wireframe line width:", Cmd::WireframeLineWidth},
};

constexpr size_t kMaxLights = 8;
constexpr int kMinContourSides = 3, kMaxContourSides = 10000;  // LPFGParams
constexpr int kMinSurfaceDiv = 2, kMaxSurfaceDiv = 64;         // UVPrecision

class Parser {
 public:
  Parser(ViewSettings& vs, std::vector<ViewFileWarning>& warnings, std::string file)
      : vs_(vs), warnings_(warnings), file_(std::move(file)) {}

  void run(std::string_view text) {
    size_t pos = 0;
    const size_t warningsBefore = warnings_.size();
    while (pos <= text.size()) {
      size_t nl = text.find('\n', pos);
      if (nl == std::string_view::npos) nl = text.size();
      std::string_view raw = text.substr(pos, nl - pos);
      if (line_ < INT_MAX) ++line_;
      handleLine(raw);
      if (nl == text.size()) break;
      pos = nl + 1;
    }
    // Not one command in it (a binary file, another program's file given as the view file): one
    // warning at its first line rather than one per line of garbage.
    if (commands_ == 0 && unrecognized_ > 1) {
      ViewFileWarning first = warnings_[firstUnrecognized_];
      warnings_.resize(warningsBefore);
      warnings_.push_back({first.file, first.line, first.column,
                           "this is not a view file: none of its " + std::to_string(unrecognized_) +
                               " lines is a view-file command; it is ignored"});
    }
  }

 private:
  ViewSettings& vs_;
  std::vector<ViewFileWarning>& warnings_;
  std::string file_;
  int line_ = 0;
  std::string text_;  // the current line without leading and trailing blanks
  size_t indent_ = 0;  // how many leading blanks were removed (for columns)
  int lpfgWindows_ = 0;  // lpfg's window list length, for its view id check (see checkViewId)
  int lastViewId_ = -1;  // the view: on the previous command line, for item continuation lines
  int commands_ = 0, unrecognized_ = 0;  // lines read as commands, and lines that are not
  size_t firstUnrecognized_ = 0;          // the first one's warning
  std::set<std::string> surfaceLines_, meshLines_;

  void warn(const char* at, const std::string& message) {
    int column = 1;
    if (at && at >= text_.c_str() && at <= text_.c_str() + text_.size())
      column = int(at - text_.c_str() + indent_) + 1;
    warnings_.push_back({file_, line_, column, message});
  }

  // GNU cpp line markers: `# N "file" flags…` and `#line N "file"`. The next line is line N.
  void lineMarker(const char* p) { textfile::lineMarker(p, file_, line_); }

  void handleLine(std::string_view raw) {
    size_t b = 0;
    while (b < raw.size() && isBlank(raw[b])) ++b;
    indent_ = b;
    text_ = trimmed(raw.substr(b));
    if (text_.empty()) return;
    const char* s = text_.c_str();
    for (const auto& c : kCommands) {
      size_t len = std::strlen(c.label);
      if (std::strncmp(s, c.label, len) == 0) {
        if (c.cmd != Cmd::Preproc) lastViewId_ = -1, ++commands_;
        dispatch(c.cmd, s + len);
        return;
      }
    }
    if (lastViewId_ >= 0 && viewItem(s) >= 0) {
      // The manual's table shows view: items one per line; lpfg reads only the view: line itself
      // ("Unrecognized command"). Applied to the view: above, with a warning.
      warn(s, "view: items belong on the view: line (lpfg ignores this line); applied to view " +
                  std::to_string(lastViewId_));
      applyViewItems(viewFor(lastViewId_), s);
      return;
    }
    lastViewId_ = -1;
    if (unrecognized_++ == 0) firstUnrecognized_ = warnings_.size();
    // Shown as text: bytes that are not printable ASCII become '?'.
    std::string shown = text_.size() > 60 ? text_.substr(0, 60) + "..." : text_;
    for (char& c : shown)
      if ((unsigned char)c < 32 || (unsigned char)c > 126) c = '?';
    warn(s, "unrecognized command: " + shown);
  }

  // ---- small value readers --------------------------------------------------------------------

  bool onOff(const char* arg, bool& flag, const char* what) {
    std::string v = trimmed(arg);
    if (v == "on" || v == "off") {
      flag = v == "on";
      return true;
    }
    warn(skipBlanks(arg), std::string(what) + " must be 'on' or 'off', not '" + v + "'");
    return false;
  }
  bool oneFloat(const char* arg, float& v, const char* what) {
    const char* p = arg;
    if (scanFloat(p, v)) return true;
    warn(skipBlanks(arg), std::string(what) + " needs a number");
    return false;
  }
  bool oneInt(const char* arg, int& v, const char* what) {
    const char* p = arg;
    if (scanInt(p, v)) return true;
    warn(skipBlanks(arg), std::string(what) + " needs an integer");
    return false;
  }

  void dispatch(Cmd cmd, const char* arg) {
    const char* at = skipBlanks(arg);
    std::string word = trimmed(arg);
    switch (cmd) {
      case Cmd::Preproc:
        lineMarker(text_.c_str());
        break;
      case Cmd::LineStyle:
        if (word == "pixel") vs_.lineStyle = LineStyle::Pixel;
        else if (word == "polygon") vs_.lineStyle = LineStyle::Polygon;
        else if (word == "cylinder") vs_.lineStyle = LineStyle::Cylinder;
        else warn(at, "invalid line style '" + word + "' (pixel, polygon or cylinder)");
        break;
      case Cmd::ZBuffer:
        onOff(arg, vs_.zBuffer, "z buffer");
        break;
      case Cmd::RenderMode:
        if (word == "filled") vs_.renderMode = RenderMode::Filled;
        else if (word == "wireframe") vs_.renderMode = RenderMode::Wireframe;
        else if (word == "shaded") vs_.renderMode = RenderMode::Shaded;
        else if (word == "shadows") vs_.renderMode = RenderMode::Shadows;
        else warn(at, "invalid render mode '" + word + "' (filled, wireframe, shaded or shadows)");
        break;
      case Cmd::Light:
        readLight(arg);
        break;
      case Cmd::Surface:
        readSurface(arg);
        break;
      case Cmd::Texture:
        if (word.empty()) warn(at, "texture: needs a file name");
        else vs_.textures.push_back(word);
        break;
      case Cmd::FrontDist: {
        float v;
        if (oneFloat(arg, v, "front distance")) vs_.frontDistance = v;
        break;
      }
      case Cmd::BackDist: {
        float v;
        if (oneFloat(arg, v, "back distance")) vs_.backDistance = v;
        break;
      }
      case Cmd::Tropism:
        readTropism(arg, false);
        break;
      case Cmd::Torque:
        readTropism(arg, true);
        break;
      case Cmd::Projection:
        // lpfg compares prefixes here.
        if (std::strncmp(at, "parallel", 8) == 0) vs_.projection = Projection::Parallel;
        else if (std::strncmp(at, "perspective", 11) == 0) vs_.projection = Projection::Perspective;
        else warn(at, "invalid projection '" + word + "' (parallel or perspective)");
        break;
      case Cmd::Scale:
      case Cmd::ScaleFactor: {
        float v;
        if (!oneFloat(arg, v, "scale")) break;
        if (std::fabs(v) < 0.0001f) warn(at, "invalid scale " + word + ": must not be less than 0.0001");
        else vs_.scale = v;
        break;
      }
      case Cmd::MinZoom:
        oneFloat(arg, vs_.minZoom, "min zoom");
        break;
      case Cmd::MaxZoom:
        oneFloat(arg, vs_.maxZoom, "max zoom");
        break;
      case Cmd::Rotation:  // in lpfg's label table but ignored by it
      case Cmd::Function:  // cpfg's function/gallery declarations: lpfg ignores them
      case Cmd::Gallery:
        break;
      case Cmd::Font:
        readXFont(arg);
        break;
      case Cmd::WinFont:
        readWinFont(arg);
        break;
      case Cmd::STropism: {
        const char* p = arg;
        float v[4];
        bool ok = scanFloats(p, v, 3) == 3;
        p = skipBlanks(p);
        ok = ok && *p == ',';
        if (ok) ++p;
        ok = ok && scanFloat(p, v[3]);
        if (ok) vs_.simpleTropism = SimpleTropism{{v[0], v[1], v[2]}, v[3]};
        else warn(at, "stropism: expects 'x y z, elasticity'");
        break;
      }
      case Cmd::Window:
        readWindow(arg);
        break;
      case Cmd::WindowBorder: {
        const char* p = arg;
        int size;
        if (!scanInt(p, size)) {
          warn(at, "window border: expects 'size r g b'");
          break;
        }
        float rgb[3] = {0, 0, 0};
        int n = scanFloats(p, rgb, 3);
        if (n < 3 && *skipBlanks(p)) warn(skipBlanks(p), "window border: colour components must be numbers 0..255");
        vs_.windowBorderSize = size;
        vs_.windowBorderColor = {rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f};
        break;
      }
      case Cmd::ContourSides: {
        int v;
        if (!oneInt(arg, v, "contour sides")) break;
        if (v < kMinContourSides || v > kMaxContourSides) {
          int c = std::clamp(v, kMinContourSides, kMaxContourSides);
          warn(at, "invalid contour sides " + std::to_string(v) + ", using " + std::to_string(c));
          v = c;
        }
        if (v > kMaxDrawnSphereSlices)
          warn(at, "contour sides " + std::to_string(v) + ": lcjit draws spheres with at most " +
                       std::to_string(kMaxDrawnSphereSlices) + " and cylinders with at most " +
                       std::to_string(kMaxDrawnRingSides) + " sides, already finer than a pixel");
        vs_.contourSides = v;
        break;
      }
      case Cmd::GenerateOnViewChange:
        if (word == "on") vs_.generateOnViewChange = ViewSettings::Regenerate::On;
        else if (word == "off") vs_.generateOnViewChange = ViewSettings::Regenerate::Off;
        else if (word == "triggered") vs_.generateOnViewChange = ViewSettings::Regenerate::Triggered;
        else warn(at, "generate on view change must be on, off or triggered, not '" + word + "'");
        break;
      case Cmd::View:
        readView(arg);
        break;
      case Cmd::BSurface:
        readBSurface(arg);
        break;
      case Cmd::Box:
        readBox(arg);
        break;
      case Cmd::CorrectedRotation:
        onOff(arg, vs_.correctedRotation, "corrected rotation");
        vs_.correctedRotationGiven = true;
        break;
      case Cmd::BackfaceCulling:
        onOff(arg, vs_.backfaceCulling, "backface culling");
        break;
      case Cmd::Terrain:
        readTerrain(arg);
        break;
      case Cmd::ConcavePolygons:
        onOff(arg, vs_.concavePolygons, "concave polygons");
        break;
      case Cmd::Gradient: {
        const char* p = arg;
        int type;
        float amount;
        if (!scanInt(p, type) || !scanFloat(p, amount)) warn(at, "gradient: expects 'direction magnitude'");
        else if (type < 0 || type > 2) warn(at, "gradient direction must be 0, 1 or 2");
        else {
          vs_.gradientDirection = type;
          vs_.gradientMagnitude = amount;
        }
        break;
      }
      case Cmd::ShadowMap:
        readShadowMap(arg);
        break;
      case Cmd::PSLinecap: {
        int v;
        if (!oneInt(arg, v, "PS linecap")) break;
        if (v < 0 || v > 2) warn(at, "PS linecap must be 0, 1 or 2");
        else vs_.postscriptLinecap = v;
        break;
      }
      case Cmd::StationaryLights:
        onOff(arg, vs_.stationaryLights, "stationary lights");
        break;
      case Cmd::AutoNormals:
        onOff(arg, vs_.automaticNormals, "auto normals");
        break;
      case Cmd::TaperedCylinders:
        onOff(arg, vs_.taperedCylinders, "tapered cylinders");
        break;
      case Cmd::Antialiasing: {
        int v;
        if (!oneInt(arg, v, "antialiasing")) break;
        if (v < 0 || v > 10) warn(at, "antialiasing samples must be an integer between 0 and 10");
        else vs_.antialiasingSamples = v;
        break;
      }
      case Cmd::Mesh:
        readMesh(arg);
        break;
      case Cmd::AnimatedMesh:
        warn(at, "animated mesh: is not supported (lpfg rejects it too)");
        break;
      case Cmd::CappedCylinders:
        onOff(arg, vs_.cappedCylinders, "capped cylinders");
        break;
      case Cmd::WireframeLineWidth: {
        float v;
        if (!oneFloat(arg, v, "wireframe line width")) break;
        if (std::fabs(v) < 0.0001f) warn(at, "invalid wireframe line width " + word);
        else vs_.wireframeLineWidth = v;
        break;
      }
    }
  }

  // ---- lights ---------------------------------------------------------------------------------

  void readLight(const char* arg) {
    const char* p = skipBlanks(arg);
    if (vs_.lights.size() >= kMaxLights) {
      warn(p, "too many lights: at most " + std::to_string(kMaxLights));
      return;
    }
    Light light;
    bool positional = false, spot = false;
    do {
      char c = *p;
      const char* at = p;
      if (!c || !std::strchr("OVPADST", c)) {
        warn(at, c ? std::string("unknown light parameter '") + c + "' (O: V: P: A: D: S: T:)"
                   : std::string("light: needs O:, V: or P: and/or A: D: S: T:"));
        return;
      }
      int n = c == 'P' ? 5 : 3;
      float v[5];
      p = afterItemLetter(p);
      if (!tokenFloats(p, v, n)) {
        warn(at, std::string("light ") + c + ": needs " + std::to_string(n) + " numbers separated by blanks");
        return;
      }
      switch (c) {
        case 'O':
        case 'V':
          light.position = {v[0], v[1], v[2]};
          positional = c == 'O';
          break;
        case 'P':
          light.spotDirection = {v[0], v[1], v[2]};
          light.spotExponent = v[3];
          light.spotCutoff = v[4];
          spot = true;
          break;
        case 'A': light.ambient = {v[0], v[1], v[2]}; break;
        case 'D': light.diffuse = {v[0], v[1], v[2]}; break;
        case 'S': light.specular = {v[0], v[1], v[2]}; break;
        case 'T': std::copy(v, v + 3, light.attenuation); break;
      }
    } while (*p);
    light.kind = !positional ? Light::Kind::Directional : spot ? Light::Kind::Spot : Light::Kind::Point;
    vs_.lights.push_back(light);
  }

  // ---- tropisms -------------------------------------------------------------------------------

  void readTropism(const char* arg, bool torque) {
    const char* name = torque ? "torque" : "tropism";
    const char* p = skipBlanks(arg);
    Tropism t;
    t.torque = torque;
    do {
      char c = *p;
      const char* at = p;
      if (!c || !std::strchr("TAIES", c)) {
        warn(at, std::string(name) + (c ? std::string(": unknown parameter '") + c + "'"
                                        : std::string(": needs T: x y z")));
        return;
      }
      if (c == 'A' && torque) {
        warn(at, "A: is not allowed for torque");
        return;
      }
      float v[3];
      int n = c == 'T' ? 3 : 1;
      p = afterItemLetter(p);
      if (!tokenFloats(p, v, n)) {
        warn(at, std::string(name) + " " + c + ": needs " + std::to_string(n) + " number(s) separated by blanks");
        return;
      }
      switch (c) {
        case 'T':
          if (v[0] == 0 && v[1] == 0 && v[2] == 0) {
            warn(at, std::string(name) + " vector is null");
            return;
          }
          t.direction = {v[0], v[1], v[2]};
          break;
        case 'A':
          if (v[0] > 180 || v[0] < -180) {
            warn(at, "tropism angle must be between -180 and 180");
            return;
          }
          t.angle = v[0];
          break;
        case 'I':
          if (v[0] == 0) {
            warn(at, std::string(name) + " intensity is 0");
            return;
          }
          t.intensity = v[0];
          break;
        case 'E': t.elasticity = v[0]; break;
        case 'S': t.step = v[0]; break;
      }
    } while (*p);
    vs_.tropisms.push_back(t);
  }

  // ---- external files -------------------------------------------------------------------------

  // `file scale sdiv tdiv texture` as lpfg's sscanf("%s %f %d %d %d") reads a surface: how many
  // values read (1 to 5; 3 is an error: divisions come in pairs) and those values. `what` names
  // the command in warnings; false after a warning.
  struct SurfaceArgs {
    std::string file;
    int count = 0;
    float scale = 1;
    int sdiv = 0, tdiv = 0, texture = -1;
  };
  bool readSurfaceArgs(const char* at, const char* what, SurfaceArgs& a) {
    const char* p = skipNonBlanks(at);
    a.file.assign(at, p);
    if (a.file.empty()) {
      warn(at, std::string(what) + ": needs a file name");
      return false;
    }
    a.count = 1;
    if (scanFloat(p, a.scale)) {
      ++a.count;
      if (scanInt(p, a.sdiv)) {
        ++a.count;
        if (scanInt(p, a.tdiv)) {
          ++a.count;
          if (scanInt(p, a.texture)) ++a.count;
        }
      }
    }
    if (a.count == 3) {
      warn(at, std::string(what) + ": sdiv and tdiv must be given together");
      return false;
    }
    if (a.count >= 4 && (a.sdiv < kMinSurfaceDiv || a.sdiv > kMaxSurfaceDiv || a.tdiv < kMinSurfaceDiv ||
                         a.tdiv > kMaxSurfaceDiv)) {
      warn(at, std::string(what) + ": sdiv and tdiv must be between 2 and 64");
      return false;
    }
    return true;
  }

  void readSurface(const char* arg) {
    const char* at = skipBlanks(arg);
    SurfaceArgs a;
    if (!readSurfaceArgs(at, "surface", a)) return;
    SurfaceDeclaration s;
    s.file = a.file;
    if (a.count >= 4) s.sdiv = a.sdiv, s.tdiv = a.tdiv;
    if (a.count >= 2) s.scale = a.scale;
    if (a.count >= 5) s.texture = a.texture;
    if (!surfaceLines_.insert(trimmed(arg)).second) return;  // lpfg rereads, adds nothing
    vs_.surfaces.push_back(s);
  }

  // b_wrapper's reading: the same values, a positive scale (which it does not use).
  void readBSurface(const char* arg) {
    const char* at = skipBlanks(arg);
    SurfaceArgs a;
    if (!readSurfaceArgs(at, "bsurface", a)) return;
    if (a.count >= 2 && a.scale <= 0) {
      warn(at, "bsurface: the scale must be positive");
      return;
    }
    BSplineDeclaration b;
    b.file = a.file;
    if (a.count >= 4) b.sdiv = a.sdiv, b.tdiv = a.tdiv;
    if (a.count >= 5) b.texture = a.texture;
    vs_.bsurfaces.push_back(b);
  }

  // lpfg replaces its terrain with every `terrain:` line, so a bad line leaves none.
  void readTerrain(const char* arg) {
    const char* at = skipBlanks(arg);
    vs_.terrain.reset();
    if (!*at) {
      warn(at, "terrain: needs a file name");
      return;
    }
    TerrainDeclaration t;
    const char* p = skipNonBlanks(at);
    t.file.assign(at, p);
    // sscanf("%i %f %f %s %i %f %f") semantics: values are read in order until one does not
    // convert. where[i]: value i's column, for warnings.
    auto scanWord = [&](std::string& w) {
      const char* start = skipBlanks(p);
      if (!*start) return false;
      p = skipNonBlanks(start);
      w.assign(start, p);
      return true;
    };
    std::string grid = "off";
    const char* where[7] = {at, at, at, at, at, at, at};
    auto next = [&](int i) { return where[i] = skipBlanks(p), true; };
    (void)(next(0) && scanInt(p, t.levels, 0) && next(1) && scanFloat(p, t.scale) && next(2) &&
           scanFloat(p, t.distance) && next(3) && scanWord(grid) && next(4) && scanInt(p, t.texture, 0) && next(5) &&
           scanFloat(p, t.uTiling) && next(6) && scanFloat(p, t.vTiling));
    t.grid = grid.compare(0, 2, "on") == 0;
    if (t.levels < 1) return warn(where[0], "terrain: invalid number of levels " + std::to_string(t.levels));
    if (t.levels > kMaxTerrainLevels)
      return warn(where[0], "terrain: at most " + std::to_string(kMaxTerrainLevels) + " levels, not " +
                                std::to_string(t.levels));
    if (t.scale <= 0) return warn(where[1], "terrain: the scale must be positive");
    if (t.texture < -1) return warn(where[4], "terrain: invalid texture id " + std::to_string(t.texture));
    if (t.uTiling < 0) return warn(where[5], "terrain: the U tiling must not be negative");
    if (t.vTiling < 0) return warn(where[6], "terrain: the V tiling must not be negative");
    vs_.terrain = std::move(t);
  }

  void readMesh(const char* arg) {
    const char* at = skipBlanks(arg);
    std::string command = trimmed(arg);
    if (command.empty()) {
      warn(at, "mesh: needs a file name");
      return;
    }
    MeshDeclaration m;
    const char* p = skipNonBlanks(at);
    m.file.assign(at, p);
    p = skipBlanks(p);
    while (*p) {
      char c = *p;
      const char* item = p;
      if (!std::strchr("STC", c)) {
        // lpfg reports the error and still loads the mesh with what it read so far.
        warn(item, std::string("mesh: unknown parameter '") + c + "' (S: T: C:)");
        break;
      }
      float v[3];
      int n = c == 'C' ? 3 : 1;
      p = afterItemLetter(p);
      if (!tokenFloats(p, v, n)) {
        warn(item, std::string("mesh ") + c + ": needs " + std::to_string(n) + " number(s) separated by blanks");
        return;
      }
      if (c == 'S') {
        m.scale *= v[0];
      } else if (c == 'T') {
        // lpfg converts the number to int unchecked; one beyond int (or NaN) names no texture.
        if (v[0] > -2147483648.0f && v[0] < 2147483648.0f) m.texture = int(v[0]);
        else warn(item, "mesh T: texture id " + std::to_string(v[0]) + " out of range");
      } else {
        m.contact = {v[0], v[1], v[2]};
      }
    }
    if (!meshLines_.insert(command).second) return;
    vs_.meshes.push_back(m);
  }

  // ---- views, boxes, windows ------------------------------------------------------------------

  // lpfg accepts a view:/box: id that indexes its window list, or 0 (the first view:/box: with
  // no window: before it creates an unnamed full-size window 0).
  bool checkViewId(long id, const char* at) {
    if (id < 0 || (id != 0 && id >= lpfgWindows_)) {
      warn(at, "invalid view id " + std::to_string(id) + " (" + std::to_string(lpfgWindows_) +
                   " window(s) declared before this line)");
      return false;
    }
    if (lpfgWindows_ == 0) lpfgWindows_ = 1;
    return true;
  }

  ViewDefinition& viewFor(int id) {
    for (auto& v : vs_.views)
      if (v.id == id) return v;
    vs_.views.push_back(ViewDefinition{});
    vs_.views.back().id = id;
    return vs_.views.back();
  }

  void readView(const char* arg) {
    const char* at = skipBlanks(arg);
    const char* p = arg;
    int id;
    if (!scanInt(p, id)) {
      warn(at, "could not find the view id in the view: command");
      return;
    }
    if (!checkViewId(id, at)) return;
    ViewDefinition& view = viewFor(id);
    float old[7];
    const char* q = p;
    if (scanFloats(q, old, 7) == 7) {
      // Deprecated: view: id rx ry rz zoom px py pz.
      Quat rot = axisAngle(old[0], 1, 0, 0) * axisAngle(old[1], 0, 1, 0) * axisAngle(old[2], 0, 0, 1);
      view.dir = rotatedBy(view.dir.value_or(V3f{0, 0, -1}), rot);
      view.up = rotatedBy(view.up.value_or(V3f{0, 1, 0}), rot);
      view.pan = V3f{old[4], old[5], old[6]};
      view.shift.reset();  // lpfg sets 0: computed from the bounding box
      if (old[3] == 0) warn(at, "view: zoom 0 ignored");
      else view.scale = 1.0f / old[3];
      return;
    }
    applyViewItems(view, p);
    lastViewId_ = id;
  }

  static int viewItem(const char* p) {
    for (int i = 0; i < 6; ++i)
      if (std::strncmp(p, kViewItems[i], std::strlen(kViewItems[i])) == 0) return i;
    return -1;
  }

  void applyViewItems(ViewDefinition& view, const char* p) {
    const char* const* labels = kViewItems;
    for (p = nextLabel(p); *p; p = nextLabel(p)) {
      int which = viewItem(p);
      if (which < 0) {
        warn(p, "unrecognized view: item '" + std::string(p, skipNonBlanks(p)) + "' (dir: up: pan: fov: shift: scale:)");
        return;
      }
      const char* item = p;
      p += std::strlen(labels[which]);
      float v[3];
      int n = which <= 2 ? 3 : 1;
      if (scanFloats(p, v, n) != n) {
        warn(item, std::string("could not parse ") + labels[which] + " in view: (needs " + std::to_string(n) +
                       (n == 1 ? " number)" : " numbers)"));
        return;
      }
      switch (which) {
        case 0: view.dir = V3f{v[0], v[1], v[2]}; break;
        case 1: view.pan = V3f{v[0], v[1], v[2]}; break;
        case 2: view.up = V3f{v[0], v[1], v[2]}; break;
        case 3: view.fov = v[0]; break;
        case 4: view.shift = v[0]; break;
        case 5: view.scale = v[0]; break;
      }
    }
  }

  static constexpr const char* kViewItems[] = {"dir:", "pan:", "up:", "fov:", "shift:", "scale:"};

  void readBox(const char* arg) {
    const char* at = skipBlanks(arg);
    const char* p = arg;
    int id;
    float v[6];
    if (!scanInt(p, id) || scanFloats(p, v, 6) != 6) {
      warn(at, "box: expects 'id xmin xmax ymin ymax zmin zmax'");
      return;
    }
    if (!checkViewId(id, at)) return;
    for (int axis = 0; axis < 3; ++axis)
      if (v[2 * axis] >= v[2 * axis + 1]) {
        warn(at, std::string("box: ") + "xyz"[axis] + "min >= " + "xyz"[axis] + "max");
        return;
      }
    BoxDefinition box{id, {v[0], v[2], v[4]}, {v[1], v[3], v[5]}};
    for (auto& b : vs_.boxes)
      if (b.id == id) {
        b = box;
        return;
      }
    vs_.boxes.push_back(box);
  }

  void readWindow(const char* arg) {
    const char* p = skipBlanks(arg);
    if (!*p) {
      warn(p, "window: expects 'name left top width height'");
      return;
    }
    WindowDefinition w;
    const char* e = skipNonBlanks(p);
    w.name.assign(p, e);
    p = e;
    float v[4] = {w.left, w.top, w.width, w.height};
    int n = scanFloats(p, v, 2);
    const char* size = p;
    n += n == 2 ? scanFloats(p, v + 2, 2) : 0;
    if (n < 4 && *skipBlanks(p)) warn(skipBlanks(p), "window: position and size must be numbers");
    // A fraction of the picture: 0 or less shows nothing (the renderer would make it 1 pixel).
    if (!(v[2] > 0 && v[3] > 0)) warn(skipBlanks(size), "window: the width and height must be above 0 (fractions of the picture)");
    w.left = v[0];
    w.top = v[1];
    w.width = v[2];
    w.height = v[3];
    vs_.windows.push_back(w);
    ++lpfgWindows_;
  }

  // ---- shadow map -----------------------------------------------------------------------------

  void readShadowMap(const char* arg) {
    static const char* const labels[] = {"size:", "color:", "offset:"};
    for (const char* p = nextLabel(arg); *p; p = nextLabel(p)) {
      int which = -1;
      for (int i = 0; i < 3 && which < 0; ++i)
        if (std::strncmp(p, labels[i], std::strlen(labels[i])) == 0) which = i;
      if (which < 0) {
        warn(p, "unrecognized shadow map item '" + std::string(p, skipNonBlanks(p)) + "' (size: color: offset:)");
        return;
      }
      const char* item = p;
      p += std::strlen(labels[which]);
      if (which == 0) {
        int size;
        if (!scanInt(p, size)) {
          warn(item, "could not parse size: in shadow map:");
          return;
        }
        if (size % 2 != 0) {
          warn(item, "shadow map size should not be an odd number, using " + std::to_string(size + 1));
          size += 1;
        }
        vs_.shadowMapSize = size;
      } else {
        float v[3];
        int n = which == 1 ? 3 : 2;
        if (scanFloats(p, v, n) != n) {
          warn(item, std::string("could not parse ") + labels[which] + " in shadow map:");
          return;
        }
        if (which == 1) {
          vs_.shadowColor = {std::clamp(v[0], 0.0f, 1.0f), std::clamp(v[1], 0.0f, 1.0f), std::clamp(v[2], 0.0f, 1.0f)};
        } else {
          vs_.shadowOffsetFactor = std::max(v[0], 0.0f);
          vs_.shadowOffsetUnits = std::max(v[1], 0.0f);
        }
      }
    }
  }

  // ---- fonts ----------------------------------------------------------------------------------

  // `font: -foundry-family-weight-slant-setwidth-style-pixels-points-…` (lpfg's Qt build reads
  // the family, weight, slant and pixel size; fewer than 8 fields leave the label font as is).
  void readXFont(const char* arg) {
    std::string spec = trimmed(arg);
    if (spec.empty()) {
      warn(skipBlanks(arg), "font: needs an X font name");
      return;
    }
    vs_.font = spec;
    std::vector<std::string> fields;
    std::string cur;
    for (char c : spec) {
      if (c != '-') {
        cur += c;
      } else {
        fields.push_back(cur.empty() ? "*" : cur);
        cur.clear();
      }
    }
    if (!cur.empty()) fields.push_back(cur);
    if (fields.size() < 8) return;
    auto sizeOf = [](const std::string& f) {
      char* end = nullptr;
      long v = std::strtol(f.c_str(), &end, 10);
      return end != f.c_str() && v > 0 && v <= 100 ? int(v) : 0;
    };
    int size = sizeOf(fields[7]);
    if (!size) size = sizeOf(fields[6]);
    if (size) vs_.winFontSize = size;
    std::string family;
    for (char c : fields[2]) family += c == '_' ? ' ' : c;
    if (family != "*") vs_.winFont = family;  // lpfg passes "*" to Qt, i.e. its default family
    const std::string& w = fields[3];
    vs_.winFontWeight = w == "light" ? 25 : w == "medium" ? 63 : w == "bold" ? 75 : w == "black" ? 87 : 50;
    vs_.winFontItalic = fields[4] == "italic";
  }

  // `winfont: name size [flags]`: name in quotes if it has blanks; flags: b and/or i (lpfg looks at
  // the first two characters only). lpfg's Linux build applies it only when flags are given, and
  // then makes it bold unless a b flag asks for bold (its test is inverted); italic stays on once
  // set.
  void readWinFont(const char* arg) {
    const char* p = skipBlanks(arg);
    const char* at = p;
    std::string name;
    if (*p == '"') {
      for (++p; *p && *p != '"'; ++p) name += *p;
      if (*p == '"') ++p;
    } else {
      const char* e = skipNonBlanks(p);
      name.assign(p, e);
      p = e;
    }
    if (name.empty()) {
      warn(at, "winfont: needs a font name and a size");
      return;
    }
    p = skipBlanks(p);
    if (!*p) {
      warn(p, "winfont: needs a font size after the name");
      return;
    }
    int size = std::atoi(p);
    p = skipBlanks(skipNonBlanks(p));
    if (!*p) return;  // no flags: lpfg keeps the font it had
    bool boldFlag = false;
    for (int i = 0; i < 2 && p[i] && !isBlank(p[i]); ++i) {
      char c = (char)std::toupper((unsigned char)p[i]);
      if (c == 'I') vs_.winFontItalic = true;
      if (c == 'B') boldFlag = true;
    }
    vs_.winFont = name;
    vs_.winFontSize = size;
    vs_.winFontWeight = boldFlag ? 50 : 75;
  }
};

}  // namespace

ViewSettings parseViewFile(std::string_view text, const std::string& fileName,
                           std::vector<ViewFileWarning>& warnings) {
  ViewSettings vs;
  Parser(vs, warnings, fileName).run(text);
  return vs;
}

}  // namespace lcjit::runtime

namespace lcjit::runtime {

std::string viewLine(const ViewDefinition& v) {
  auto num = [](float x) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", (double)x);
    return std::string(b);
  };
  auto vec = [&](const char* key, const std::optional<V3f>& p) {
    return p ? std::string(" ") + key + " " + num(p->x) + " " + num(p->y) + " " + num(p->z) : std::string();
  };
  auto one = [&](const char* key, const std::optional<float>& x) {
    return x ? std::string(" ") + key + " " + num(*x) : std::string();
  };
  return "view: " + std::to_string(v.id) + vec("dir:", v.dir) + vec("up:", v.up) + vec("pan:", v.pan) +
         one("fov:", v.fov) + one("shift:", v.shift) + one("scale:", v.scale) + "\n";
}

}  // namespace lcjit::runtime
