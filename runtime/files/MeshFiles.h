// Meshes of the view file's `mesh:` lines (lpfg manual §5.6, §8.2.3): Wavefront OBJ and PLY
// (ascii, binary little/big endian).
//
// lpfg's own mesh reader (OBJ only) does, and this one follows it:
//  - positions are multiplied by the `S:` scale, then the `C:` contact point is subtracted
//    (p' = p·scale - contact), before anything else;
//  - normals are always computed, never read: each triangle's normal is normalize((b-a)×(c-a)),
//    and a vertex's normal is the normalised plain sum of the normals of the triangles that use
//    its position (smooth shading, also across texture seams). MeshLoadOptions::fileNormals uses
//    the file's normals instead when every corner has one (not lpfg);
//  - texture coordinates are the file's (u,v), unchanged (images load bottom row first, so v = 0
//    is the image's bottom).
// Differences: lpfg's quads lose their second triangle and it rejects faces of 5+ corners; here
// every polygon is triangulated as a fan (0,1,2), (0,2,3), …. lpfg has no PLY reader.
// Drawing (lpfg): vertex p at position + (-left)·p.x + heading·p.y + up·p.z, times the Mesh
// module's scale. Ids: view-file order from 0; lpfg skips a mesh that fails to load.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

struct MeshLoadOptions {
  float scale = 1;        // `S:`
  V3f contact{0, 0, 0};   // `C:`
  bool fileNormals = false;
};

// Indexed triangles. Every array but `indices` has one entry per vertex (uvs/colors may be empty).
// A vertex is a distinct (position, texture coordinate) pair of the file.
struct MeshData {
  std::vector<V3f> positions;
  std::vector<V3f> normals;     // unit (zero where all adjacent triangles are degenerate)
  std::vector<V2f> uvs;         // empty if the file has none
  std::vector<V3f> colors;      // PLY red/green/blue in [0,1]; empty if none
  std::vector<uint32_t> indices;  // 3 per triangle, in the file's winding
  V3f boundsMin, boundsMax;     // of the positions after scale/contact
  size_t triangleCount() const { return indices.size() / 3; }
};

// By extension (.obj, .ply, any case); otherwise a file starting with "ply" is PLY, else OBJ.
llvm::Expected<MeshData> loadMesh(const std::string& path, const MeshLoadOptions& options = {});
// From memory; `fileName` appears in errors (with the line number for text formats).
llvm::Expected<MeshData> parseObj(std::string_view text, const std::string& fileName,
                                  const MeshLoadOptions& options = {});
llvm::Expected<MeshData> parsePly(std::string_view bytes, const std::string& fileName,
                                  const MeshLoadOptions& options = {});

}  // namespace lcjit::runtime
