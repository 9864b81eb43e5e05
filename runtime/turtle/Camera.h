// Framing: lpfg's rule for turning a view file and a model's bounding box into a camera
// (bounding box centred and scaled by `scale:`, `view:`/`box:` overrides, projection, clipping
// planes, the Camera module). Shared by the OpenGL renderer and the 2D exporters (SVG,
// PostScript) so every output shows the same picture.
#pragma once
#include <optional>

#include <glm/glm.hpp>

#include "runtime/turtle/Geometry.h"
#include "runtime/files/ViewFile.h"

namespace lcjit::runtime {

struct CameraMatrices {
  glm::mat4 view{1}, projection{1};
  int width = 800, height = 800;  // viewport in pixels
  glm::vec3 eye{0, 0, 1}, viewDirection{0, 0, -1};
  bool perspective = false;
  // Details of lpfg's framing the renderer and the viewer need.
  glm::vec3 lookAt{0}, up{0, 1, 0};
  float zShift = 1, halfDepth = 1;  // eye to look-at distance; half the clipped depth
  float unitsPerPixel = 1;          // model units per pixel at the look-at distance
  // `stationary lights: on` (lpfg's default): light positions are taken through this matrix (a
  // translation only: the initial view without its rotation) instead of `view`, so lights stay
  // fixed relative to the camera.
  glm::mat4 stationaryLights{1};
  Bounds bounds;                    // the framed volume (the box: entry, or the model's bounds)
};

// `viewId` selects `view:`/`box:` entries of the view file (multi-view, manual §7.3); 0 for the
// main view. `zoom`/`rotation`/`pan` are the interactive adjustments (identity for batch output).
struct ViewAdjustment {
  float zoom = 1;
  glm::mat4 rotation{1};
  glm::vec3 pan{0};
};

// lpfg's projection scale of a view (Projection::Reset, SetModifiers): 1 / its `view:` line's
// scale if it has one, else 1 / the file's `scale:` (1/0.9 for a zero one). The user's zoom
// divides it; vvScale() is its inverse.
float projectionScale(const ViewSettings& view, int viewId);

CameraMatrices frameView(const ViewSettings& view, const Bounds& bounds, const std::optional<CameraPose>& camera,
                         int width, int height, int viewId = 0, const ViewAdjustment& adjust = {});

// Window coordinates of a model-space point: x right, y down, in pixels; z = depth in [0,1].
glm::vec3 projectToWindow(const CameraMatrices& camera, V3f p);

// Picking (MouseIns, manual §5.9): the source module (Geometry::trackSources) of the nearest
// triangle, segment or disc under window pixel (x, y); none when the pixel shows background.
std::optional<uint32_t> pickSource(const Geometry& geometry, const CameraMatrices& camera, float x, float y);

}  // namespace lcjit::runtime
