// Multi-view (manual §7.3): the views a model opened with UseView, each drawn by its view group in
// its `window:` rectangle, and where those rectangles fall in a picture. Shared by the renderer
// (pictures and the window) and the 2D exporters (SVG, PostScript/EPS, PDF), so every output lays
// the views out alike.
#pragma once
#include <array>
#include <vector>

#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Geometry.h"
#include "runtime/files/ViewFile.h"

namespace lcjit::runtime {

// One view of a multi-view model (manual §7.3): what its view group draws, in its `window:`
// rectangle (fractions of the picture, from the top left).
struct ViewPane {
  Geometry geometry;
  struct Rect {
    float left = 0, top = 0, width = 1, height = 1;
    // A view file's `window:` fractions, kept inside the picture. Only a window that reaches past
    // an edge is cut at it: `0.8 0 0.2 0.5` ends at 1 in float, and its width stays 0.2 (20 of
    // lpfg's 100 cells), where 1 - 0.8 would be 0.19999999 (19 cells).
    static Rect inside(float left, float top, float width, float height);
  } rect;
  int viewId = 0;
};

// The views' rectangles in pixels of a w×h picture, each {x0, top y0, width, height}, laid out as
// lpfg's window lays them out (a grid of 100 × 100 cells; the view file's `window border:` width
// between views that meet; a part of the picture no view covers goes to the views).
std::vector<std::array<int, 4>> paneRects(const std::vector<ViewPane::Rect>& rects, int w, int h, int border);

// A view's camera: the view file's framing of its geometry, in its rectangle of the picture
// (paneRects' {x0, y0, width, height}).
CameraMatrices paneCamera(const ViewSettings& view, const ViewPane& pane, const std::array<int, 4>& rect,
                          const ViewAdjustment& adjust = {});

}  // namespace lcjit::runtime
