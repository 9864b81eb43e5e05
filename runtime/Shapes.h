// The shapes a view file names (manual §8.2.3), loaded: Bézier surfaces and meshes with their
// per-line options. The Surface/Mesh modules refer to them by id in view-file order.
#pragma once
#include <vector>

#include "files/MeshFiles.h"
#include "files/Surfaces.h"

namespace lcjit::runtime {

struct ShapeLibrary {
  struct Surface {
    BezierSurface surface;
    float scale = 1;
    int sdiv = 0, tdiv = 0;  // 0: kDefaultSurfaceDivisions
    int texture = -1;
  };
  struct Mesh {
    MeshData data;
    int texture = -1;
  };
  std::vector<Surface> surfaces;
  std::vector<Mesh> meshes;
};

}  // namespace lcjit::runtime
