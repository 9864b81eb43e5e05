// B-spline surfaces (manual §10.1): the `bsurface:` files of the view file and the arithmetic
// behind the dynamic BsurfaceObjS/BsurfaceObjM (GetBsurfaceS/M, operator+, Interpolate,
// DBSurfaceS/M). Everything is restated from lpfg's own source (its splineEdit surface class and
// b_wrapper) so that the numbers reaching a model are lpfg's, bit for bit: control points are
// doubles, and every formula below is evaluated in lpfg's order.
//
// File (splineEdit's format, read the way lpfg reads it, with `>>`): "rows columns", the degree
// (lpfg warns unless it is 3 and evaluates a cubic anyway), then rows·columns points "x y z",
// row by row. Reading stops at the first word that is not a number; a point not read keeps the
// value of lpfg's initial net, point (i,j) = ((float)i/rows − 0.5 + 1e-6, (float)j/columns −
// 0.5 + 1e-6, 0). A file that cannot be opened leaves lpfg with that initial 10 × 10 net.
// The view file's scale is checked (> 0) and otherwise ignored, as in lpfg.
//
// Rows run along u, columns along v. A surface point (u,v), u in [3, rows], v in [3, columns],
// is a cubic B-spline with clamped ends: four column curves evaluated at u, then combined along
// v (lpfg's de Boor triangle with its own end rules, see BSplineNet::point). Normals are the
// normalised cross product of one-sided differences 0.05 apart.
//
// Refinement (lpfg's DoubleU/DoubleV): a line of n ≥ 6 points becomes 2n − 3 (cubic B-spline
// subdivision with lpfg's end masks; lines of 4 or 5 points give 9, lpfg's index arithmetic).
// Coarsening (HalveU/HalveV): reverse subdivision, n → (n + 3)/2, refused when that is below 10.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "runtime/files/Surfaces.h"  // PatchGrid
#include <functional>

#include <llvm/Support/Error.h>
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

// lpfg's Vector3d arithmetic is V3td's, operation for operation (products c·p per coordinate,
// sums left to right).
using BSplinePoint = V3td;

class BSplineNet {
 public:
  BSplineNet() = default;
  // lpfg's initial net of rows × columns points (see above).
  BSplineNet(int rows, int columns);

  int rows() const { return rows_; }
  int columns() const { return columns_; }
  bool empty() const { return rows_ <= 0 || columns_ <= 0; }
  const BSplinePoint& at(int i, int j) const { return points_[size_t(i) * size_t(columns_) + size_t(j)]; }
  BSplinePoint& at(int i, int j) { return points_[size_t(i) * size_t(columns_) + size_t(j)]; }

  // lpfg's DoubleU / DoubleV. Lines of fewer than 4 points are left alone (lpfg reads outside
  // them); returns whether the net grew.
  bool refineRows();
  bool refineColumns();
  // lpfg's HalveU / HalveV; false (and no change) when the result would have fewer than 10.
  bool coarsenRows();
  bool coarsenColumns();
  // lpfg's Resize(rows, columns): coarsens while the target is smaller and at least 10, then
  // refines while the target is at least 2n − 3. Where lpfg would loop for ever (a coarsening
  // it refuses) this stops; `stuck` then says so.
  void resize(int rows, int columns, bool* stuck = nullptr);

  // lpfg's operator+: the smaller net of the two is refined, rows then columns, until it is at
  // least as large as the other; the sum has the left operand's (refined) size.
  static BSplineNet add(const BSplineNet& l, const BSplineNet& r);
  BSplineNet scaled(double c) const;
  // lpfg's Interpolate: both resized to rows × columns, then l·(1−alpha) + r·alpha.
  static BSplineNet interpolate(const BSplineNet& l, const BSplineNet& r, double alpha, int rows, int columns);

  // Evaluation (parameters as above; clamped to the surface's range).
  BSplinePoint point(double u, double v) const;
  BSplinePoint normal(double u, double v) const;

  // The surface at (uDiv+1)·(vDiv+1) parameter points u = 3 + i·(rows−3)/uDiv, v likewise,
  // vertex (i,j) at i·(vDiv+1) + j, and lpfg's triangles: each quad is cut along the diagonal
  // whose end normals agree more. Texture coordinates (i/uTex, j/vTex): lpfg's come from the
  // precision of the draw that asks, the vertices from the first one (see ShapeLibrary).
  struct Grid {
    int uDiv = 0, vDiv = 0;
    std::vector<BSplinePoint> positions, normals;
  };
  Grid sample(int uDiv, int vDiv) const;
  static PatchGrid mesh(const Grid& g, int uTex, int vTex);

 private:
  // Replaces each column (`downRows`: the points down the rows) or each row by f of it; f gives
  // every line the same new length.
  void mapLines(bool downRows, const std::function<std::vector<BSplinePoint>(const std::vector<BSplinePoint>&)>& f);
  // The normal at clamped (u, v), whose point `at` is: one-sided differences of the surface.
  BSplinePoint normalAt(double u, double v, const BSplinePoint& at) const;

  int rows_ = 0, columns_ = 0;
  std::vector<BSplinePoint> points_;  // row-major
};

// A BsurfaceObjNM's net (`points`: rows of maxColumns floats x,y,z; rows × columns used, clamped
// to the record), as lpfg's b_wrapper takes it.
BSplineNet bsplineFromRecord(const float* points, int maxRows, int maxColumns, int rows, int columns);
// lpfg's GetControlNet into a BsurfaceObjNM: a net larger than the record is first resized to
// fit (lpfg's Resize), then its points go to `points` as floats; the size to rows/columns.
// Returns false where lpfg would not return (a coarsening it refuses: it loops); the net is then
// cut to the record.
bool bsplineToRecord(BSplineNet net, int maxRows, int maxColumns, float* points, int* rows, int* columns);

struct BSplineFile {
  BSplineNet net;
  int degree = 3;
};

// Parses a file as lpfg does (see above); `name` is for messages. Warnings (a degree other than
// 3) go to `warnings`.
BSplineFile parseBSpline(std::string_view text, const std::string& name, std::vector<std::string>& warnings);
// Reads `path`; a file that cannot be read is lpfg's initial 10 × 10 net and a warning.
BSplineFile loadBSpline(const std::string& path, std::vector<std::string>& warnings);

}  // namespace lcjit::runtime
