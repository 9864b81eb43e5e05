// The view file's terrain (lpfg manual §10.3): a height field with levels of detail, drawn by the
// Terrain module, queried and changed by model functions (terrainHeightAt & co.).
//
// lpfg's algorithm (vlab lpfg/terrain.cpp, terrainPatch.cpp, quadTree.h; after McRoberts and
// Hardy, "Level of detail for terrain geometry images", 2007), restated:
//  - Level l of `levels` cuts its grid into 2^l × 2^l patches; a patch is a node of a quadtree
//    (children: NW, NE, SW, SE = the lower/higher u and v halves; u runs along columns, v along
//    rows; north = lower v). Every level's points are the finest level's, taken every 2^k-th
//    (lpfg overwrites the coarser levels' points); normals stay each level's own. Points are
//    multiplied by the `terrain:` scale when read. A patch keeps its box (min/max x and z, y = the
//    middle of its heights), its midpoint and its highest y, and texture coordinates
//    (u·UTiling/(numU−1), v·VTiling/(numV−1)) of the whole level.
//  - Drawing: the camera point is position + s·head with s = |position|·(1 − 1/scale) (float),
//    from the Terrain module's CameraPosition. A patch of level l is split into its children when
//    |camera − midpoint with y = 0| ≤ (R_l + D_l·offset)/2, D_l = √2·width/2^l (width × scale),
//    R_l = Σ_{k=l+1}^{levels−1} √2·width/2^k with the width as the file gives it (lpfg computes R
//    before scaling). A drawn patch of level ≥ 2 whose outward neighbour's parent is drawn (a
//    coarser neighbour) has a crack on that side: its border row there is re-triangulated on
//    every other point, with corner triangles. Patches are drawn as lpfg's triangle strips (the
//    diagonal chosen by the normals, normals negated on one of the two diagonals so that winding
//    and normal agree), in the order NE, NW, SE, SW. With `grid` on, each drawn patch also gets
//    its box shrunk to 95% as four lines (red on a cracked side, else yellow), unlit, modulated by
//    the texture at the last texture coordinate drawn (lpfg leaves texturing on for them).
//  - terrainHeightAt/NormalAt: the finest patch whose box holds (x, z) (NW, NE, SW, SE first
//    match), a ray down from its highest y, the first of its triangles (u, then v; per cell the
//    two triangles (u,v)(u,v+1)(u+1,v+1) and (u,v)(u+1,v)(u+1,v+1)) that the plane point passes
//    lpfg's area test, lpfg's double arithmetic operation for operation (its quirks kept: the
//    second triangle of a cell reuses the first one's plane point, and its normal is the one
//    returned).
//  - terrainVisibilityPatch: the patch drawn last (or finest) under the point, with its subtree.
//    scaleTerrainBy: patches reloaded from the file's data, then scaled (the width becomes the
//    file's width × factor; R stays).
// Modes: Hidden patches are not drawn; Wireframe ones are outlined, Shaded ones filled, whatever
// the render mode (they start as Wireframe under `render mode: wireframe`, else Shaded).
#pragma once
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "runtime/turtle/Geometry.h"
#include "runtime/files/TerrainPatches.h"
#include "runtime/files/ViewFile.h"
#include "runtime/include/lcjit/types.h"

namespace lcjit::runtime {

struct Image;

class Terrain {
 public:
  // `wireframe`: the view file's render mode is wireframe.
  Terrain(const TerrainDeclaration& declaration, TerrainPatchFile file, bool wireframe);
  // Reads `path` (the declaration's file, resolved) with the declaration's number of levels.
  static llvm::Expected<std::shared_ptr<Terrain>> load(const TerrainDeclaration& declaration, const std::string& path,
                                                      bool wireframe);

  // The model functions (manual §10.3); the results are lpfg's bits.
  bool heightAt(V3f world, V3f& onTerrain);
  bool normalAt(V3f world, V3f& normal);
  void visibilityAll(VisibilityMode mode);
  void visibilityPatch(VisibilityMode mode, V3f world);
  void scaleBy(float factor);

  // Draws the patches the camera calls for into `out`, in the terrain's own coordinates, colour
  // `color`, textured with the `terrain:` texture; `texture` is that texture's image if loaded
  // (the grid's colours), else null.
  void draw(const CameraPosition& camera, int color, const Image* texture, Geometry& out);
  // What lpfg's bounding box takes from the terrain: every patch's box corners.
  void addExtent(Bounds& b) const;
  int textureId() const { return declaration_.texture; }

 private:
  struct Cracks {
    bool n = false, e = false, s = false, w = false;
  };
  struct Patch {
    int numU = 0, numV = 0;
    std::vector<V3d> points, normals;
    std::vector<V2d> uvs;
    V3d topLeft, bottomRight, midPoint;
    double maxHeight = 0;
    bool drawn = false;  // chosen by the last draw
    VisibilityMode mode = Shaded;
    size_t at(int u, int v) const { return size_t(u) * size_t(numV) + size_t(v); }
  };
  struct Node {
    int level, row, col;
  };
  class Writer;

  Patch& patch(Node n) { return levels_[n.level][size_t(n.row) * (size_t(1) << n.level) + size_t(n.col)]; }
  const Patch& patch(Node n) const {
    return levels_[n.level][size_t(n.row) * (size_t(1) << n.level) + size_t(n.col)];
  }
  static Node child(Node n, int quadrant);  // 0 NW, 1 NE, 2 SW, 3 SE
  void fill();
  void measureExtent();
  void loadPatch(Patch& p, const TerrainGrid& grid, int patches, int row, int col);
  std::optional<Node> under(V3d point, Node n, bool drawnCounts);
  bool rayCast(V3f world, V3f& point, V3f& normal);
  bool split(const Patch& p, int level) const;
  void choose(Node n);
  // Which sides of drawn patch n meet a coarser drawn patch (after choose()).
  Cracks cracksOf(Node n) const;
  void drawPatches(Node n, Writer& w);
  void setMode(Node n, VisibilityMode mode);

  TerrainDeclaration declaration_;
  std::vector<TerrainGrid> grids_;  // the file's levels, points scaled, coarser ones resampled
  std::vector<std::vector<Patch>> levels_;
  Bounds extent_;  // of every patch's corners, kept by measureExtent() after fill() and scaleBy()
  float fileWidth_ = 0, width_ = 0;
  std::vector<double> reach_;  // R_l
  V3d camera_;
  mutable std::mutex mutex_;  // model functions and drawing may run on different threads
};

}  // namespace lcjit::runtime
