// Pictures of the model: `-out FILE` and OutputFrame("FILE") from model code. The extension
// chooses: .png/.jpg/.jpeg/.bmp render headless through EGL with the viewer's renderer (in a build
// with LCJIT_WITH_RENDERING); .obj, .ply, .stl, .gltf, .glb, .svg, .ps, .eps and .pov go through
// the exporters; a video's frames (.mp4, .webm) are the pictures, written by FrameSequence.
// Every output is the same interpreted Geometry framed by the same camera; a multi-view model's
// pictures and 2D exports (.svg, .ps, .eps, .pdf) hold every view, laid out alike (interpretViews).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "viewer/ImageFiles.h"
#include "viewer/Renderer.h"
#include <llvm/Support/Error.h>

namespace lcjit::runtime {
class ModelRun;
struct DrawingFiles;
}  // namespace lcjit::runtime
namespace lcjit::viewer {
class HeadlessRenderer;
}

namespace lcjit::app {

// What an output file's name asks for, by its extension (case aside): a picture, a video or an
// export is drawn (FrameWriter, FrameSequence); a string is written as lpfg's binary string (.strb
// .bin) or as text (.str .txt). Nothing for another extension.
enum class OutputKind { Picture, Video, Export, BinaryString, TextString };
std::optional<OutputKind> outputKindOf(const std::string& path);
// The extensions outputKindOf knows, for messages.
extern const char* const kOutputFileTypes;
// A picture, a video or an export: what the model's drawing makes.
bool isFrameOutput(const std::string& path);

// Why WIDTH x HEIGHT (-w, a REPL's -w) is no size of a picture or a window, or "": less than
// 1 x 1 (a picture of nothing), or past what an int holds. Pictures also have the renderer's
// upper bound (GL's, some 16384), which it reports when it cannot make one.
std::string badPictureSize(double width, double height);

// Multi-view (manual §7.3): a view file with `window:` lines lays the picture out as lpfg's window
// does, one pane per line, in the file's order. The views the model opened with UseView are
// interpreted by their view group; a window no view was opened for is its background (in lpfg, an
// empty widget holds its place), so are all of them when the model opened none. Empty for a
// view file without `window:` lines (one view). Also records each view's bounding box (vvXmin …).
llvm::Expected<std::vector<viewer::ViewPane>> interpretViews(runtime::ModelRun& engine, const runtime::ViewSettings& view);
// The window's picture of the current string, as the window and a sandboxed window's child make
// it: the main view into `main` (its bounding box is view 0's, for vvXmin …) and the views the
// model opened (interpretViews) into `panes`. A fault in an interpretation rule is the error.
llvm::Error interpretWindowPicture(runtime::ModelRun& engine, const runtime::ViewSettings& view, runtime::Geometry& main,
                                   std::vector<viewer::ViewPane>& panes);

// The model's colours as the renderer takes them, and its textures, made once per loaded
// DrawingFiles rather than for every picture: a reload replaces the DrawingFiles object, which is
// what `of` notices.
class RenderLook {
 public:
  const RenderLook& of(const runtime::DrawingFiles& drawing);
  viewer::RenderPalette palette;
  std::vector<runtime::Image> textures;

 private:
  const runtime::DrawingFiles* source_ = nullptr;
};

struct FrameTimes {
  double interpretMs = 0, renderMs = 0;
  size_t triangles = 0, segments = 0;
};

class FrameWriter {
 public:
  FrameWriter(int width = 800, int height = 800);
  ~FrameWriter();
  // Draws where the run has got to (an L-system: its current string, interpreted) into `path`.
  llvm::Error write(const std::string& path, runtime::ModelRun& engine, const runtime::DrawingFiles& drawing,
                    FrameTimes* times = nullptr);
  // The same picture as `write` makes of a picture file (a video's frame).
  llvm::Expected<runtime::Image> picture(runtime::ModelRun& engine, const runtime::DrawingFiles& drawing,
                                         FrameTimes* times = nullptr);

 private:
  llvm::Expected<runtime::Image> render(const runtime::Geometry& geometry, runtime::ModelRun& engine,
                                        const runtime::DrawingFiles& drawing, FrameTimes* times);
  int width_, height_;
#if LCJIT_HAVE_RENDERING
  std::unique_ptr<viewer::HeadlessRenderer> renderer_;  // created on the first picture, reused
  RenderLook look_;
#endif
};

// OutputFrame("file") from model code names a file; it is written once the step (or Start, or
// End) is over, never in the middle of the model's code: lpfg only records the name there, and
// a picture drawn at once would run the interpretation rules before the rest of EndEach. Each
// name once per step, in the order named.
class NamedFrames {
 public:
  void name(const char* path);
  bool empty() const { return paths_.empty(); }
  // Writes every file named since the last call (each interprets the current string), then
  // forgets them; the first failure is the error, the others are still tried. After a fault of
  // the run (engine.faulted()) nothing is written: the string is not the step's.
  llvm::Error writeAll(FrameWriter& frames, runtime::ModelRun& engine, const runtime::DrawingFiles& drawing);

 private:
  std::vector<std::string> paths_;
};

}  // namespace lcjit::app
