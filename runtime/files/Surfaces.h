// Bézier surfaces (.s files of bezieredit/stedit, vlab tools manual §5.4; lpfg manual §5.6, §6.3,
// §7.1, §8.2.3). Behaviour follows lpfg's reader:
//
// File: a bounding-box line (ignored); an optional "PRECISION S: s T: t" line (kept, but lpfg
// ignores it); CONTACT POINT, END POINT, HEADING, UP (each "X: x Y: y Z: z") and SIZE; then one
// group per patch: a name line, a colour line, three neighbour lines (all ignored), and 16 control
// points "x y z" (four rows of four, the layout does not matter).
//
// Frame: at load every control point p becomes p' = q.x·(-L) + q.y·H + q.z·U with
// q = (p - contact) / size, H and U the file's heading and up (normalised) and L = U × H (exactly
// what lpfg computes). Control points are then in the turtle's frame: x along the turtle's right
// (-left), y along its heading, z along its up; the Surface module draws them with
// position + R·(scale·fileScale·p'), R's columns being -left, heading, up.
//
// Control point order (GetSurface / DSurface / SurfaceObj::points): index 4·i + j is the j-th point
// of the i-th row in the file; i runs along u, j along v:
// P(u,v) = Σ_ij B_i(u) B_j(v) points[4i+j], B the cubic Bernstein polynomials. The normal is
// ∂P/∂u × ∂P/∂v, normalised.
//
// Tessellation: u = i/uDiv, v = j/vDiv. Texture coordinates (s,t) = (v, 1-u) for a one-patch
// surface (lpfg turns textures this way to match cpfg); for several patches lpfg maps the texture
// over the whole surface instead: s = (x - minX)/(maxX - minX), t = 1 - (y - minY)/(maxY - minY),
// over the bounding box of all (transformed) control points.
//
// Precision: the Surface module uses SetUPrecision/SetVPrecision if set, else the view file's
// sdiv/tdiv of the `surface:` line, else 10 × 10 (kDefaultDivisions). Valid range 2..64.
// Ids: view-file order from 0; lpfg skips a surface that fails to load (later ids shift down), and
// defines each surface's name (the file name up to its first '.') as its id for the preprocessor.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>
#include "runtime/include/lcjit/types.h"
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

constexpr int kDefaultSurfaceDivisions = 10;
constexpr int kMinSurfaceDivisions = 2, kMaxSurfaceDivisions = 64;

// A tessellated patch: (uDiv+1)·(vDiv+1) vertices, vertex (i,j) (u = i/uDiv, v = j/vDiv) at
// at(i,j) = i·(vDiv+1) + j. `indices` holds 2·uDiv·vDiv triangles, counter-clockwise seen from
// the side the normals point to: (i,j) (i+1,j) (i+1,j+1) and (i,j) (i+1,j+1) (i,j+1).
struct PatchGrid {
  int uDiv = 0, vDiv = 0;
  std::vector<V3f> positions, normals;
  std::vector<V2f> uvs;
  std::vector<uint32_t> indices;
  size_t at(int i, int j) const { return size_t(i) * size_t(vDiv + 1) + size_t(j); }
};

// Evaluation of one bicubic Bézier patch (control points as above). Divisions are clamped to
// 1..1024. uvs are (v, 1-u).
V3f bezierPoint(const SurfaceObj& patch, float u, float v);
V3f bezierNormal(const SurfaceObj& patch, float u, float v);  // unit, or 0 where degenerate
PatchGrid tessellatePatch(const SurfaceObj& patch, int uDiv, int vDiv);

struct BezierSurface {
  std::string name;  // lpfg's identifier: the file name without directories, up to its first '.'
  V3f contact, end, heading, up;  // as in the file (heading, up normalised)
  float size = 1;
  std::optional<int> precisionS, precisionT;  // PRECISION line, if any (lpfg ignores it)
  std::vector<std::string> patchNames;
  std::vector<SurfaceObj> patches;  // control points, already in the turtle frame (see above)
  V3f boundsMin, boundsMax;         // of all transformed control points

  SurfaceObj first() const { return patches.empty() ? SurfaceObj() : patches[0]; }  // GetSurface
  // GetSurfacePoint(id, k): point k%16 of patch k/16; (0,0,0) if out of range.
  V3f controlPoint(int k) const;
  // Tessellates patch k with lpfg's texture coordinates for this surface (see above).
  PatchGrid tessellate(size_t k, int uDiv, int vDiv) const;
};

llvm::Expected<BezierSurface> parseSurface(std::string_view text, const std::string& fileName);
llvm::Expected<BezierSurface> loadSurface(const std::string& path);

}  // namespace lcjit::runtime
