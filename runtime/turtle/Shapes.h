// The shapes a view file names (manual §8.2.3, §10.1), loaded: Bézier surfaces, meshes and
// B-spline surfaces with their per-line options. The Surface/Mesh/BSurface modules refer to them
// by id in view-file order.
#pragma once
#include <memory>
#include <mutex>
#include <vector>

#include "runtime/files/BSplineSurfaces.h"
#include "runtime/files/MeshFiles.h"
#include "runtime/files/Surfaces.h"

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
  struct BSpline {
    BSplineNet net;
    int sdiv = 0, tdiv = 0;  // 0: not given
    int texture = -1;
    // lpfg computes a B-spline surface's vertices at its first draw and reuses them for every
    // later draw until the file is read again, whatever precision those ask for (their texture
    // coordinates do follow it). Shared by copies of the library.
    struct Cache {
      std::once_flag once;
      BSplineNet::Grid grid;
    };
    std::shared_ptr<Cache> cache = std::make_shared<Cache>();
    const BSplineNet::Grid& grid(int uDiv, int vDiv) const {
      std::call_once(cache->once, [&] { cache->grid = net.sample(uDiv, vDiv); });
      return cache->grid;
    }
  };
  std::vector<Surface> surfaces;
  std::vector<Mesh> meshes;
  std::vector<BSpline> bsplines;
};

}  // namespace lcjit::runtime
