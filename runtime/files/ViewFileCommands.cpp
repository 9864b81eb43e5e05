// The view file's commands with items or files of their own (manual §8.2, as lpfg's
// lightsrc.cpp, tropism.cpp, surface.cpp, mesh.h and DrawParams read them): light:, tropism: and
// torque:, surface:, bsurface:, terrain:, mesh:, shadow map:, font: and winfont:. ViewFile.cpp's
// dispatch calls them; a command lpfg rejects is left out with a warning.
//
// Sections, in order (each begins with a `// ----` rule): Lights · Tropisms · External files
// (surface:, bsurface:, terrain:, mesh:) · Shadow map · Fonts.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "runtime/files/TerrainPatches.h"
#include "runtime/files/ViewFileParser.h"

namespace lcjit::runtime::viewfile {

constexpr size_t kMaxLights = 8;
constexpr int kMinSurfaceDiv = 2, kMaxSurfaceDiv = 64;         // UVPrecision

// ---------------------------------------------------------------------------------------------
// Lights

void Parser::readLight(const char* arg) {
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

// ---------------------------------------------------------------------------------------------
// Tropisms

void Parser::readTropism(const char* arg, bool torque) {
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

// ---------------------------------------------------------------------------------------------
// External files

// The values of a surface: or bsurface: line (SurfaceArgs, ViewFileParser.h); false after a warning.
bool Parser::readSurfaceArgs(const char* at, const char* what, SurfaceArgs& a) {
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

void Parser::readSurface(const char* arg) {
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
void Parser::readBSurface(const char* arg) {
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
void Parser::readTerrain(const char* arg) {
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

void Parser::readMesh(const char* arg) {
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

// ---------------------------------------------------------------------------------------------
// Shadow map

void Parser::readShadowMap(const char* arg) {
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

// ---------------------------------------------------------------------------------------------
// Fonts

// `font: -foundry-family-weight-slant-setwidth-style-pixels-points-…` (lpfg's Qt build reads
// the family, weight, slant and pixel size; fewer than 8 fields leave the label font as is).
void Parser::readXFont(const char* arg) {
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
void Parser::readWinFont(const char* arg) {
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

}  // namespace lcjit::runtime::viewfile
