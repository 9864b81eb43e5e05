// Framing: lpfg's rule (vlab lpfg/projection.cpp, view.cpp, winparams.h, drawparam.cpp), restated.
//
//  - The framed volume is the model's bounding box, or the `box:` entry of the view. Its centre is
//    the look-at point. minWidth/minHeight are half its x/y extents (a zero extent becomes 0.1 of
//    the other one, both zero: 0.1), halfDepth = 0.525 × its diagonal (0 → 0.5).
//  - Without `box:` and with a `view:` direction other than ±(0,0,-1), the box is first rotated
//    (about its centre) by the rotation between the view direction and -Z and the extents are
//    those of the rotated box.
//  - `front distance:`/`back distance:` (both given) only replace halfDepth by |back-front|/2.
//  - lpfg's internal scale is 1/`scale:` (default 1/0.9); a `view:` scale likewise.
//  - zShift (eye to look-at) = minWidth·scale / tan(fov/2) + halfDepth, fov 45° unless `view:`
//    gives one; `view: … shift:` is overwritten by this (lpfg sets the volume after the modifiers).
//  - Default view: along -Z, up +Y. `view:` dir/up are re-orthogonalised (up ∥ dir → (0,-dz,dy)).
//  - The Camera module (only without `box:`): view direction = heading, up = up, eye at its
//    position (pan = pos + zShift·dir − centre); if the camera is inside the volume, halfDepth
//    grows to zShift.
//  - Clipping planes: near = max(zShift − halfDepth, 0.001), far = zShift + halfDepth.
//  - Parallel: if the window is relatively wider than the volume (w/h > minWidth/minHeight) the
//    half height is minHeight·scale and the half width follows the window's ratio; else the half
//    width is minWidth·scale. Perspective: fov' = 2·atan(scale·tan(fov/2)) is the vertical fov in
//    the first case, the horizontal one in the second.
#include "runtime/turtle/Camera.h"

#include <optional>

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace lcjit::runtime {
namespace {

constexpr float kMinimumNearClipping = 0.001f;
constexpr float kEpsilon = 0.0001f;
constexpr float kMinDim = 0.1f;
constexpr float kHalfDepthCoef = 0.525f;
constexpr float kMinHalfDepth = 0.5f;

glm::vec3 toGlm(V3f v) { return {v.x, v.y, v.z}; }

}  // namespace

float projectionScale(const ViewSettings& view, int viewId) {
  float scale = std::fabs(view.scale) > 1e-6f ? 1.0f / view.scale : 1.0f / 0.9f;
  for (const ViewDefinition& d : view.views)
    if (d.id == viewId && d.scale && std::fabs(*d.scale) > 1e-6f) scale = 1.0f / *d.scale;
  return scale;
}

CameraMatrices frameView(const ViewSettings& view, const Bounds& modelBounds, const std::optional<CameraPose>& camera,
                         int width, int height, int viewId, const ViewAdjustment& adjust) {
  width = std::max(width, 1);
  height = std::max(height, 1);

  // Projection::Reset + SetModifiers.
  float fov = 45.0f;
  float scale = projectionScale(view, viewId);
  glm::vec3 dir(0, 0, -1), up(0, 1, 0), pan(0);
  const ViewDefinition* def = nullptr;
  for (const ViewDefinition& d : view.views)
    if (d.id == viewId) def = &d;
  if (def) {
    if (def->fov) fov = *def->fov;
    if (def->pan) pan = toGlm(*def->pan);
    if (def->dir) dir = toGlm(*def->dir);
    if (def->up) up = toGlm(*def->up);
    if (glm::length(dir) < 1e-12f) dir = {0, 0, -1};
    dir = glm::normalize(dir);
    if (glm::length(up) < 1e-12f || std::fabs(glm::dot(dir, glm::normalize(up))) >= 1.0f - kEpsilon)
      up = glm::vec3(0, -dir.z, dir.y);
    glm::vec3 left = glm::normalize(glm::cross(dir, up));
    up = glm::normalize(glm::cross(left, dir));
  }
  const glm::vec3 initialDir = dir;

  // SetVolume (box: given) or SetVolumeAndPos (the model's bounds and the Camera module).
  const BoxDefinition* box = nullptr;
  for (const BoxDefinition& b : view.boxes)
    if (b.id == viewId) box = &b;
  Bounds volume;
  if (box) {
    volume.add(box->min);
    volume.add(box->max);
  } else if (!modelBounds.empty()) {
    volume = modelBounds;
  } else {
    volume.add(V3f(0, 0, 0));  // lpfg's clean Volume: a point at the origin
  }
  const glm::vec3 center = toGlm(volume.center());
  glm::vec3 vmin = toGlm(volume.min), vmax = toGlm(volume.max);
  const bool adjustVolume = box == nullptr;
  if (adjustVolume && std::fabs(glm::dot(dir, glm::vec3(0, 0, -1))) < 1.0f - kEpsilon) {
    // Rotate the centred box so that the view direction becomes -Z (the extents of a centred box
    // do not depend on the rotation's sense) and take the rotated box's extents.
    glm::vec3 axis = glm::cross(dir, glm::vec3(0, 0, -1));
    float angle = std::acos(std::clamp(glm::dot(dir, glm::vec3(0, 0, -1)), -1.0f, 1.0f));
    glm::mat4 rot = glm::rotate(glm::mat4(1), angle, glm::normalize(axis));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int i = 0; i < 8; ++i) {
      glm::vec3 p((i & 1) ? vmax.x : vmin.x, (i & 2) ? vmax.y : vmin.y, (i & 4) ? vmax.z : vmin.z);
      p = glm::vec3(rot * glm::vec4(p - center, 1));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    vmin = lo + center;
    vmax = hi + center;
  }
  float minWidth = 0.5f * (vmax.x - vmin.x);
  float minHeight = 0.5f * (vmax.y - vmin.y);
  if (minWidth == 0.0f) minWidth = kMinDim * minHeight;
  if (minHeight == 0.0f) minHeight = kMinDim * minWidth;
  if (minWidth == 0.0f) minWidth = minHeight = kMinDim;
  float halfDepth = kHalfDepthCoef * glm::distance(vmin, vmax);
  if (halfDepth == 0.0f) halfDepth = kMinHalfDepth;
  if (view.frontDistance && view.backDistance) halfDepth = std::fabs((*view.backDistance - *view.frontDistance) * 0.5f);
  float fovRad = glm::radians(fov);
  float zShift = minWidth * scale / std::tan(fovRad * 0.5f) + halfDepth;
  const float vratio = minWidth / minHeight;

  if (!box && camera) {
    glm::vec3 pos = toGlm(camera->position);
    glm::vec3 h = toGlm(camera->heading), u = toGlm(camera->up);
    if (glm::length(h) > 1e-12f) dir = glm::normalize(h);
    if (glm::length(u) > 1e-12f) up = glm::normalize(u);
    if (glm::length(center - pos) < halfDepth) halfDepth = std::max(halfDepth, zShift);
    pan = (pos + zShift * dir) - center;
  }

  CameraMatrices cam;
  cam.width = width;
  cam.height = height;
  cam.perspective = view.projection == Projection::Perspective;
  // Stationary lights (View::ResetOpenGL): the light positions see only the translation of the
  // initial view: −lookAt + pan + zShift·dir0 = −centre + zShift·dir0.
  cam.stationaryLights = glm::translate(glm::mat4(1), -center + zShift * initialDir);

  // Interactive adjustments (ZoomBy, RotateBy, PanBy).
  if (adjust.zoom != 1.0f && adjust.zoom > 0.0f) {
    scale /= adjust.zoom;
    scale = std::clamp(scale, std::min(view.minZoom, view.maxZoom), std::max(view.minZoom, view.maxZoom));
  }
  if (adjust.rotation != glm::mat4(1)) {
    glm::mat3 r(adjust.rotation);
    dir = glm::normalize(r * dir);
    up = glm::normalize(r * up);
  }
  pan += adjust.pan;

  const glm::vec3 lookAt = center + pan;
  const glm::vec3 eye = lookAt - zShift * dir;
  cam.view = glm::lookAt(eye, lookAt, up);
  cam.eye = eye;
  cam.viewDirection = dir;
  cam.lookAt = lookAt;
  cam.up = up;
  cam.zShift = zShift;
  cam.halfDepth = halfDepth;
  cam.bounds = volume;

  float nearClip = std::max(zShift - halfDepth, kMinimumNearClipping);
  float farClip = zShift + halfDepth;
  const float sratio = float(width) / float(height);
  if (!cam.perspective) {
    float xSize, ySize;
    if (sratio > vratio) {
      ySize = minHeight * scale;
      xSize = ySize * sratio;
    } else {
      xSize = minWidth * scale;
      ySize = xSize / sratio;
    }
    cam.projection = glm::ortho(-xSize, xSize, -ySize, ySize, nearClip, farClip);
    cam.unitsPerPixel = 2 * ySize / height;
  } else {
    float f = 2.0f * std::atan(scale * std::tan(fovRad * 0.5f));
    float fovy = sratio > vratio ? f : 2.0f * std::atan(std::tan(f * 0.5f) / sratio);
    fovy = std::clamp(fovy, 1e-4f, glm::radians(179.9f));
    cam.projection = glm::perspective(fovy, sratio, nearClip, farClip);
    cam.unitsPerPixel = 2.0f * zShift * std::tan(fovy * 0.5f) / height;
  }
  return cam;
}

glm::vec3 projectToWindow(const CameraMatrices& camera, V3f p) {
  glm::vec4 c = camera.projection * camera.view * glm::vec4(p.x, p.y, p.z, 1);
  if (c.w == 0) c.w = 1e-30f;
  glm::vec3 n = glm::vec3(c) / c.w;
  return {(n.x + 1) * 0.5f * camera.width, (1 - n.y) * 0.5f * camera.height, (n.z + 1) * 0.5f};
}

}  // namespace lcjit::runtime

namespace lcjit::runtime {

std::optional<uint32_t> pickSource(const Geometry& g, const CameraMatrices& camera, float x, float y) {
  float best = 2;  // depth of the nearest hit so far (window depth is in [0,1])
  std::optional<uint32_t> found;
  auto hit = [&](float depth, uint32_t source) {
    if (depth < best) best = depth, found = source;
  };
  if (g.triangleSources.size() == g.triangleCount())
    for (size_t t = 0; t < g.triangleCount(); ++t) {
      glm::vec3 a = projectToWindow(camera, g.vertices[g.indices[3 * t]].position);
      glm::vec3 b = projectToWindow(camera, g.vertices[g.indices[3 * t + 1]].position);
      glm::vec3 c = projectToWindow(camera, g.vertices[g.indices[3 * t + 2]].position);
      float d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
      if (std::fabs(d) < 1e-12f) continue;
      float u = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / d;
      float v = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / d;
      if (u < 0 || v < 0 || u + v > 1) continue;
      hit(u * a.z + v * b.z + (1 - u - v) * c.z, g.triangleSources[t]);
    }
  if (g.segmentSources.size() == g.segments.size())
    for (size_t i = 0; i < g.segments.size(); ++i) {
      glm::vec3 a = projectToWindow(camera, g.segments[i].from), b = projectToWindow(camera, g.segments[i].to);
      glm::vec2 ab(b.x - a.x, b.y - a.y), ap(x - a.x, y - a.y);
      float len2 = glm::dot(ab, ab), t = len2 > 0 ? glm::clamp(glm::dot(ap, ab) / len2, 0.f, 1.f) : 0.f;
      float reach = std::max(g.segments[i].width / 2, 2.f);  // a pixel line is hard to hit exactly
      if (glm::length(ap - ab * t) <= reach) hit(a.z + (b.z - a.z) * t, g.segmentSources[i]);
    }
  if (g.discSources.size() == g.discs.size())
    for (size_t i = 0; i < g.discs.size(); ++i) {
      const Disc& disc = g.discs[i];
      glm::vec3 c = projectToWindow(camera, disc.center);
      // The radius in pixels, measured along the camera's right vector.
      glm::vec3 right = glm::vec3(glm::inverse(camera.view)[0]) * disc.outer;
      glm::vec3 e = projectToWindow(camera, disc.center + V3f(right.x, right.y, right.z));
      float r = glm::length(glm::vec2(e.x - c.x, e.y - c.y));
      float dist = glm::length(glm::vec2(x - c.x, y - c.y));
      if (dist <= r && dist >= r * (disc.outer > 0 ? disc.inner / disc.outer : 0)) hit(c.z, g.discSources[i]);
    }
  return found;
}

}  // namespace lcjit::runtime
