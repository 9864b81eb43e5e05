// A path's outline as a list of vertices, shared by the engine that builds paths (Paths.h) and
// the canvas that paints them (Canvas.h).
#pragma once

namespace lcjit::runtime::cfdg {

// A path's outline as AGG's path_storage holds it: one vertex per point, each with AGG's command
// (agg_basics.h): a curve3 is two vertices (control, end) marked kCurve3, a curve4 three
// (control, control, end) marked kCurve4; a sub-path closed by CLOSEPOLY ends with a vertex
// kEndPoly | kClose (coordinates unused). Coordinates are the path's own units.
enum PathCommand : unsigned { kMoveTo = 1, kLineTo = 2, kCurve3 = 3, kCurve4 = 4, kEndPoly = 0x0F, kClose = 0x40 };
struct PathVertex {
  double x = 0, y = 0;
  unsigned command = kMoveTo;
};

}  // namespace lcjit::runtime::cfdg
