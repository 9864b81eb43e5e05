// Exporters: the turtle's geometry (Geometry.h) written to files other programs open.
//
//   .obj (+ .mtl)  Wavefront: triangles with normals (and uv when textured), one material per
//                  colour index (`s001`, lpfg's names; `s001_t0` with a texture) and per explicit
//                  colour (`rgb_FF8000`), pixel segments as `l` polylines in objects `lines_s001`
//                  (one per colour).
//   .ply           binary little-endian (ASCII with `ascii`): vertices with normal, colour (and
//                  s/t when textured), triangle faces, segments as `edge` elements.
//   .stl           binary (ASCII with `ascii`): triangles only — STL holds nothing else, so
//                  segments and labels are left out; colours as VisCAM/SolidView 15-bit RGB.
//   .gltf / .glb   glTF 2.0 (tinygltf; .gltf writes NAME.gltf.bin beside it): one TRIANGLES primitive
//                  per material (colour index, texture), segments as LINES primitives.
//   .svg           the 2D picture the renderer shows: projected with frameView/projectToWindow,
//                  painter-sorted back to front (coplanar things in drawing order), flat colours
//                  as lpfg's PostScript (`gradient:` applied), segments with stroke-width = pixel
//                  width, discs as circles, labels as text.
//   .ps / .eps     the same 2D drawing in PostScript (lpfg's page layout for .ps; .eps has a
//                  tight %%BoundingBox at 1 pt per pixel).
//   .pdf           the same 2D drawing as one PDF page (1 pt per pixel, labels as glyph outlines).
//                  Each 2D format draws every view of a multi-view model in its rectangle
//                  (ExportInput::views).
//   .pov           a POV-Ray scene: camera, lights, background, a mesh2 with a texture list,
//                  segments as cylinders, discs and labels.
//
// Discs (CircleFront*) become camera-facing triangle fans/rings in the mesh formats; labels appear
// only in SVG, PostScript and POV-Ray. Colours come from the Palette (colormap or materials);
// an explicit colour (kRgbColor | 0xRRGGBB, Geometry.h) is written as it is, flat, as lpfg draws it.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Geometry.h"
#include "runtime/turtle/ViewLayout.h"
#include "runtime/files/Palette.h"
#include "runtime/files/ViewFile.h"
#include <llvm/Support/Error.h>

namespace lcjit::runtime {

enum class ExportFormat { Obj, Ply, Stl, Gltf, Glb, Svg, Ps, Eps, Pdf, Pov };

struct ExportInput {
  const Geometry* geometry = nullptr;  // required
  const Palette* palette = nullptr;    // nullptr: lpfg's default colours
  const ViewSettings* view = nullptr;  // nullptr: view-file defaults

  // TriangleRun::texture → image file, as the view file names it (relative names are taken
  // relative to `textureDirectory`); written relative to the output file's directory.
  std::vector<std::string> textureFiles;
  std::string textureDirectory;

  // The picture: frameView(view, geometry.bounds(), geometry.camera, width, height, viewId, adjust)
  // unless `camera` is given (e.g. the viewer's current camera).
  int width = 800, height = 800;
  int viewId = 0;
  ViewAdjustment adjust;
  std::optional<CameraMatrices> camera;

  // A multi-view model's views (manual §7.3; one per `window:` line of the view file, as the
  // picture lays them out), or nullptr. The formats that draw a page (exportDrawsPage) draw every
  // view in its rectangle of the width × height page (paneRects, paneCamera), the view file's
  // window border colour between them, as the picture does. The 3D formats write `geometry`,
  // view 0, as lpfg's window saves an OBJ: they have no page to place views on, and the views
  // draw one model in one space, so together they would overlap; for a view file of several
  // `window:` lines, `note` says so.
  const std::vector<ViewPane>* views = nullptr;

  // When given: what the file leaves out of a picture that has it, for the user (an STL of a
  // model drawn only with lines holds no triangle: said, not written silently). "" otherwise.
  std::string* note = nullptr;

  bool ascii = false;     // PLY/STL: ASCII instead of binary
  bool shade = false;     // SVG/PS: Lambert-shade triangles with the view's lights (lpfg: flat)
  int discSegments = 32;  // sides of a triangulated disc (mesh formats)
};

// Format from a file name or a bare extension ("obj", ".OBJ", "out/tree.glb"); case-insensitive.
std::optional<ExportFormat> exportFormatFor(std::string_view pathOrExtension);
bool isExportFormat(std::string_view pathOrExtension);
// "obj", "ply", … (the canonical extension, no dot).
const char* exportFormatExtension(ExportFormat format);
// SVG, PostScript/EPS, PDF: a 2D page, which holds every view of a multi-view model
// (ExportInput::views); the others are 3D scenes, which hold view 0.
bool exportDrawsPage(ExportFormat format);

// Writes `in` to `path` in the format its extension names. Errors name the file.
llvm::Error exportGeometry(const std::string& path, const ExportInput& in);
llvm::Error exportGeometry(const std::string& path, ExportFormat format, const ExportInput& in);

}  // namespace lcjit::runtime
