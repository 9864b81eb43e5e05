// The view file (.v, manual §8.2). Keywords, defaults and parsing tolerance follow lpfg's
// DrawParams (drawparam.cpp) and the readers it calls (lightsrc.cpp, tropism.cpp, surface.cpp,
// mesh.h, winparams.cpp, tropismdata.cpp): numbers are read the way lpfg's sscanf/ReadFloats
// read them, a command lpfg rejects is left out with a warning, everything else still applies.
//
// Where each part lives (each section begins with a `// ----` rule):
//   This file: Number and word readers · The command table · Lines (run, handleLine, warnings) ·
//     Small value readers and the commands of one line (dispatch) · parseViewFile.
//   ViewFileParser.h: what the parts share (the readers, Cmd, the Parser's state).
//   ViewFileCommands.cpp: Lights · Tropisms · External files (surface:, bsurface:, terrain:,
//     mesh:) · Shadow map · Fonts.
//   ViewFileViews.cpp: Views, boxes, windows · viewLine.
#include "runtime/files/ViewFile.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "runtime/files/TextLines.h"
#include "runtime/files/ViewFileParser.h"

namespace lcjit::runtime::viewfile {

// ---------------------------------------------------------------------------------------------
// Number and word readers

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
bool scanInt(const char*& p, int& v, int base) {
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

// ---------------------------------------------------------------------------------------------
// The command table

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

constexpr int kMinContourSides = 3, kMaxContourSides = 10000;  // LPFGParams

// ---------------------------------------------------------------------------------------------
// Lines

void Parser::run(std::string_view text) {
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

void Parser::warn(const char* at, const std::string& message) {
  int column = 1;
  if (at && at >= text_.c_str() && at <= text_.c_str() + text_.size())
    column = int(at - text_.c_str() + indent_) + 1;
  warnings_.push_back({file_, line_, column, message});
}

// GNU cpp line markers: `# N "file" flags…` and `#line N "file"`. The next line is line N.
void Parser::lineMarker(const char* p) { textfile::lineMarker(p, file_, line_); }

void Parser::handleLine(std::string_view raw) {
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

// ---------------------------------------------------------------------------------------------
// Small value readers and the commands of one line

bool Parser::onOff(const char* arg, bool& flag, const char* what) {
  std::string v = trimmed(arg);
  if (v == "on" || v == "off") {
    flag = v == "on";
    return true;
  }
  warn(skipBlanks(arg), std::string(what) + " must be 'on' or 'off', not '" + v + "'");
  return false;
}
bool Parser::oneFloat(const char* arg, float& v, const char* what) {
  const char* p = arg;
  if (scanFloat(p, v)) return true;
  warn(skipBlanks(arg), std::string(what) + " needs a number");
  return false;
}
bool Parser::oneInt(const char* arg, int& v, const char* what) {
  const char* p = arg;
  if (scanInt(p, v)) return true;
  warn(skipBlanks(arg), std::string(what) + " needs an integer");
  return false;
}

void Parser::dispatch(Cmd cmd, const char* arg) {
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

}  // namespace lcjit::runtime::viewfile

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// parseViewFile

ViewSettings parseViewFile(std::string_view text, const std::string& fileName,
                           std::vector<ViewFileWarning>& warnings) {
  ViewSettings vs;
  viewfile::Parser(vs, warnings, fileName).run(text);
  return vs;
}

}  // namespace lcjit::runtime
