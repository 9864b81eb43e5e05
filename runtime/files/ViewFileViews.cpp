// The view file's layout commands (manual §8.2, as lpfg's DrawParams and winparams.cpp read
// them): view: (and its items on the lines after it), box: and window:; and viewLine, a view:
// line written back for the window's layout file.
//
// Sections, in order (each begins with a `// ----` rule): Views, boxes, windows · viewLine.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "runtime/files/Quaternion.h"
#include "runtime/files/ViewFileParser.h"

namespace lcjit::runtime::viewfile {

namespace {
// The deprecated view: form's rotations (lpfg: DrawParams, Vector3d::RotateBy).
Quat axisAngle(float degrees, float ax, float ay, float az) {
  constexpr float kPi = 3.14159265358979f;
  float half = 0.5f * degrees * kPi / 180.0f;
  float s = std::sin(half);
  return {std::cos(half), s * ax, s * ay, s * az};
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Views, boxes, windows

// lpfg accepts a view:/box: id that indexes its window list, or 0 (the first view:/box: with
// no window: before it creates an unnamed full-size window 0).
bool Parser::checkViewId(long id, const char* at) {
  if (id < 0 || (id != 0 && id >= lpfgWindows_)) {
    warn(at, "invalid view id " + std::to_string(id) + " (" + std::to_string(lpfgWindows_) +
                 " window(s) declared before this line)");
    return false;
  }
  if (lpfgWindows_ == 0) lpfgWindows_ = 1;
  return true;
}

ViewDefinition& Parser::viewFor(int id) {
  for (auto& v : vs_.views)
    if (v.id == id) return v;
  vs_.views.push_back(ViewDefinition{});
  vs_.views.back().id = id;
  return vs_.views.back();
}

void Parser::readView(const char* arg) {
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

int Parser::viewItem(const char* p) {
  for (int i = 0; i < 6; ++i)
    if (std::strncmp(p, kViewItems[i], std::strlen(kViewItems[i])) == 0) return i;
  return -1;
}

void Parser::applyViewItems(ViewDefinition& view, const char* p) {
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

void Parser::readBox(const char* arg) {
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

void Parser::readWindow(const char* arg) {
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

}  // namespace lcjit::runtime::viewfile

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// viewLine

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