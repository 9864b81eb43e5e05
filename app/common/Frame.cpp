// Pictures of the model (see Frame.h).
#include "app/common/Frame.h"

#include <cstdio>

#include <algorithm>
#include <chrono>
#include <climits>
#include <filesystem>

#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Drawing.h"
#include "runtime/ModelRun.h"
#include "viewer/ImageFiles.h"
#if LCJIT_HAVE_RENDERING
#include "viewer/Headless.h"
#endif
#include "runtime/WindowInput.h"
#include "runtime/export/Export.h"
#include "support/Elapsed.h"
#include "llvm/Support/Path.h"

namespace lcjit::app {

const RenderLook& RenderLook::of(const runtime::DrawingFiles& d) {
  if (source_ == &d) return *this;
  source_ = &d;
  palette = viewer::RenderPalette::fromPalette(d.palette);
  textures = d.textures;
  return *this;
}

std::optional<OutputKind> outputKindOf(const std::string& path) {
  if (viewer::isImageFileName(path)) return OutputKind::Picture;
  if (viewer::isVideoFileName(path)) return OutputKind::Video;
  if (runtime::isExportFormat(path)) return OutputKind::Export;
  std::string ext = llvm::sys::path::extension(path).lower();
  if (ext == ".strb" || ext == ".bin") return OutputKind::BinaryString;
  if (ext == ".str" || ext == ".txt") return OutputKind::TextString;
  return std::nullopt;
}

const char* const kOutputFileTypes = ".str .strb, .png .jpg .bmp, .obj .ply .stl .gltf .glb .svg .ps .eps .pov";

bool isFrameOutput(const std::string& path) {
  std::optional<OutputKind> k = outputKindOf(path);
  return k == OutputKind::Picture || k == OutputKind::Video || k == OutputKind::Export;
}

std::string badPictureSize(double width, double height) {
  // Written as tests that NaN fails too.
  if (!(width >= 1 && height >= 1)) return "the size must be at least 1 x 1";
  if (!(width <= INT_MAX && height <= INT_MAX)) return "the size must be at most " + std::to_string(INT_MAX) + " x " + std::to_string(INT_MAX);
  return "";
}

namespace {
// What the command line checks first (badPictureSize), again where every picture is made: a
// size that reached a FrameWriter another way must not become a picture of 1 x 1.
std::string sizeProblem(int width, int height) {
  std::string bad = badPictureSize(width, height);
  return bad.empty() ? bad : "a picture of " + std::to_string(width) + "x" + std::to_string(height) + ": " + bad;
}
}  // namespace

llvm::Expected<std::vector<viewer::ViewPane>> interpretViews(runtime::ModelRun& engine, const runtime::ViewSettings& view) {
  std::vector<viewer::ViewPane> panes;
  const auto& windows = view.windows;
  const std::vector<int>& opened = engine.views();
  for (int id = 0; id < (int)windows.size(); ++id) {
    viewer::ViewPane pane;
    if (std::find(opened.begin(), opened.end(), id) != opened.end()) {
      if (auto e = engine.interpret(pane.geometry, id)) return std::move(e);
      runtime::Bounds b = pane.geometry.framingBounds();
      if (runtime::WindowInput* w = engine.windowInput(); w && !b.empty()) w->views.setBox(id, b.min, b.max);
    }
    const auto& w = windows[size_t(id)];
    pane.rect = viewer::ViewPane::Rect::inside(w.left, w.top, w.width, w.height);
    pane.viewId = id;
    panes.push_back(std::move(pane));
  }
  return panes;
}

llvm::Error interpretWindowPicture(runtime::ModelRun& engine, const runtime::ViewSettings& view, runtime::Geometry& main,
                                   std::vector<viewer::ViewPane>& panes) {
  if (auto e = engine.interpret(main)) return e;
  runtime::Bounds b = main.framingBounds();
  if (runtime::WindowInput* w = engine.windowInput(); w && !b.empty()) w->views.setBox(0, b.min, b.max);
  auto opened = interpretViews(engine, view);
  if (!opened) return opened.takeError();
  panes = std::move(*opened);
  return llvm::Error::success();
}

FrameWriter::FrameWriter(int width, int height) : width_(width), height_(height) {}
FrameWriter::~FrameWriter() = default;

llvm::Expected<runtime::Image> FrameWriter::picture(runtime::ModelRun& engine, const runtime::DrawingFiles& drawing,
                                                    FrameTimes* times) {
  if (std::string bad = sizeProblem(width_, height_); !bad.empty()) return llvm::createStringError("cannot make " + bad);
  auto t0 = std::chrono::steady_clock::now();
  runtime::Geometry geometry;
  if (auto e = engine.interpret(geometry)) return std::move(e);
  if (times) {
    times->interpretMs = support::msSince(t0);
    times->triangles = geometry.triangleCount();
    times->segments = geometry.segments.size();
  }
  return render(geometry, engine, drawing, times);
}

llvm::Expected<runtime::Image> FrameWriter::render(const runtime::Geometry& geometry, runtime::ModelRun& engine,
                                                   const runtime::DrawingFiles& drawing, FrameTimes* times) {
#if !LCJIT_HAVE_RENDERING
  (void)geometry, (void)engine, (void)drawing, (void)times;
  return llvm::createStringError("this lcjit was built without pictures (LCJIT_WITH_RENDERING=OFF); strings, -dtf "
                                 "and the exports (.obj, .gltf, .svg …) work");
#else
  auto t0 = std::chrono::steady_clock::now();
  if (!renderer_) {
    auto r = viewer::HeadlessRenderer::create();
    if (!r) return r.takeError();
    renderer_ = std::move(*r);
  }
  viewer::HeadlessOptions options;
  options.width = width_;
  options.height = height_;
  const RenderLook& look = look_.of(drawing);
  auto panes = interpretViews(engine, drawing.view);
  if (!panes) return panes.takeError();
  auto image = panes->empty() ? renderer_->render(geometry, drawing.view, look.palette, look.textures, options)
                              : renderer_->renderPanes(*panes, drawing.view, look.palette, look.textures, options);
  if (times) times->renderMs = support::msSince(t0);
  return image;
#endif
}

llvm::Error FrameWriter::write(const std::string& path, runtime::ModelRun& engine, const runtime::DrawingFiles& drawing,
                               FrameTimes* times) {
  if (viewer::isVideoFileName(path))
    return llvm::createStringError("cannot write " + path + ": a video is made of many frames: name it with -out (every "
                                   "step of a batch run) or --record (the window's Start recording)");
  if (std::string bad = sizeProblem(width_, height_); !bad.empty())
    return llvm::createStringError("cannot write " + path + ": " + bad);
  auto t0 = std::chrono::steady_clock::now();
  runtime::Geometry geometry;
  if (auto e = engine.interpret(geometry)) return e;
  if (times) {
    times->interpretMs = support::msSince(t0);
    times->triangles = geometry.triangleCount();
    times->segments = geometry.segments.size();
  }
  t0 = std::chrono::steady_clock::now();
  if (viewer::isImageFileName(path)) {
    auto image = render(geometry, engine, drawing, nullptr);
    if (!image) return llvm::createStringError("cannot write " + path + ": " + llvm::toString(image.takeError()));
    if (auto e = viewer::writeImage(*image, path)) return e;
  } else {
    runtime::ExportInput in;
    in.geometry = &geometry;
    // A multi-view model's views, for the formats that lay them out on a page as the picture does.
    std::vector<viewer::ViewPane> panes;
    if (std::optional<runtime::ExportFormat> f = runtime::exportFormatFor(path); f && runtime::exportDrawsPage(*f)) {
      auto views = interpretViews(engine, drawing.view);
      if (!views) return views.takeError();
      panes = std::move(*views);
    }
    if (!panes.empty()) in.views = &panes;
    in.palette = &drawing.palette;
    in.view = &drawing.view;
    in.textureFiles = drawing.textureFiles;
    in.width = width_;
    in.height = height_;
    std::string note;
    in.note = &note;
    if (auto e = runtime::exportGeometry(path, in)) return e;
    if (!note.empty()) std::fprintf(stderr, "lcjit: warning: %s\n", note.c_str());
  }
  if (times) times->renderMs = support::msSince(t0);
  return llvm::Error::success();
}

void NamedFrames::name(const char* path) {
  if (path && std::find(paths_.begin(), paths_.end(), path) == paths_.end()) paths_.push_back(path);
}

llvm::Error NamedFrames::writeAll(FrameWriter& frames, runtime::ModelRun& engine, const runtime::DrawingFiles& drawing) {
  std::vector<std::string> paths = std::move(paths_);
  paths_.clear();
  if (engine.faulted()) return llvm::Error::success();
  llvm::Error first = llvm::Error::success();
  for (const std::string& path : paths)
    if (llvm::Error e = frames.write(path, engine, drawing)) {
      if (first) llvm::consumeError(std::move(e));
      else first = std::move(e);
    }
  return first;
}

}  // namespace lcjit::app
