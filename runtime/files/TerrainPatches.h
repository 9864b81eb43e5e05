// Terrain height fields (.patch files of vlab's Terrain Editor), read for the view file's
// `terrain:` line (lpfg manual §10.3). The manual gives no format; this is what lpfg reads
// (vlab lpfg/terrain.cpp, restated):
//
//   width                     the terrain's side length (a float; used only for level of detail)
//   numU numV                 level 0: the grid's size (integers)
//   x y z  nx ny nz           numU·numV entries, u-major (u = 0: v = 0 … numV−1, then u = 1 …):
//   …                         a point and its vertex normal, six numbers (doubles)
//   numU numV                 level 1, then its entries, and so on: one grid per level,
//   …                         from the coarsest to the finest
//
// Everything is whitespace-separated; line breaks do not matter. lpfg reads as many levels as the
// `terrain:` line asks for and ignores whatever follows. In the Terrain Editor's files u runs
// along x, v along z, y is the height, and each level doubles the previous one's resolution
// (numU = 2·(previous numU − 1) + 1).
//
// What lpfg does with a damaged file (reads zeros or garbage, or crashes) is not reproduced: a
// file that is not as above is an error naming the line, and nothing is loaded. So that lpfg's
// level-of-detail drawing stays inside its arrays, each level must hold at least two points per
// patch side at that level (numU − 1 ≥ 2^level) and enough points for the coarser level to be
// taken from every other one of its points (numU − 1 ≥ 2·(coarser numU − 1)); the same for numV.
// Bounds: at most kMaxTerrainLevels levels and kMaxTerrainPoints points in all, and a large grid
// is allocated only when the rest of the file is long enough to hold it.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

constexpr int kMaxTerrainLevels = 10;
constexpr size_t kMaxTerrainPoints = size_t(1) << 21;

struct TerrainGrid {
  int numU = 0, numV = 0;
  std::vector<V3d> points, normals;  // entry (u, v) at u·numV + v
  size_t at(int u, int v) const { return size_t(u) * size_t(numV) + size_t(v); }
};

struct TerrainPatchFile {
  float width = 0;
  std::vector<TerrainGrid> levels;  // coarsest first
};

// Reads the first `levels` levels (1..kMaxTerrainLevels). Errors: "file:line: error: …".
llvm::Expected<TerrainPatchFile> parseTerrainPatches(std::string_view text, const std::string& fileName, int levels);
llvm::Expected<TerrainPatchFile> loadTerrainPatches(const std::string& path, int levels);

}  // namespace lcjit::runtime
