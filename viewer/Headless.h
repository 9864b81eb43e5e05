// Headless rendering: an EGL context with no window system (Mesa's surfaceless platform, else the
// default display with a 1×1 pbuffer), an offscreen framebuffer of W×H with depth, the Renderer,
// glReadPixels; the pictures go to files through ImageFiles.h. Works with no X display and no GPU
// (llvmpipe).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "viewer/ImageFiles.h"
#include "viewer/Renderer.h"

namespace lcjit::viewer {

struct HeadlessOptions {
  int width = 800, height = 800;
  int viewId = 0;                    // view:/box: entries used
  runtime::ViewAdjustment adjust;    // identity for batch output
  RenderOptions render;
};

class HeadlessRenderer {
 public:
  static llvm::Expected<std::unique_ptr<HeadlessRenderer>> create();
  ~HeadlessRenderer();
  HeadlessRenderer(const HeadlessRenderer&) = delete;
  HeadlessRenderer& operator=(const HeadlessRenderer&) = delete;

  // Frames the geometry with lpfg's rule (runtime::frameView), uploads everything and renders.
  llvm::Expected<runtime::Image> render(const runtime::Geometry& geometry, const runtime::ViewSettings& view,
                                        const RenderPalette& palette, const std::vector<runtime::Image>& textures,
                                        const HeadlessOptions& options = {});
  // Several views in one picture (a multi-view model, §7.3): each view framed in its rectangle
  // (paneRects), the view file's window border colour between them. options.width/height are
  // the whole picture's.
  llvm::Expected<runtime::Image> renderPanes(const std::vector<ViewPane>& panes, const runtime::ViewSettings& view,
                                             const RenderPalette& palette, const std::vector<runtime::Image>& textures,
                                             const HeadlessOptions& options = {});
  // Renders what was uploaded through renderer() with a given camera (animations, tests).
  llvm::Expected<runtime::Image> renderFrame(const runtime::ViewSettings& view, const runtime::CameraMatrices& camera,
                                             const RenderOptions& options = {});

  // Makes the context current and gives the renderer (for uploads between frames).
  Renderer& renderer();
  std::string glRenderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

  struct Impl;

 private:
  explicit HeadlessRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The current context's framebuffer `fbo` (colour attachment 0), w×h, read into an Image with
// its rows turned top first (GL's go bottom to top). Leaves the default framebuffer bound.
llvm::Expected<runtime::Image> readFramebuffer(unsigned fbo, int w, int h);

// One picture to a file: create a context, render, write.
llvm::Error renderToFile(const runtime::Geometry& geometry, const runtime::ViewSettings& view,
                         const RenderPalette& palette, const std::vector<runtime::Image>& textures,
                         const std::string& path, const HeadlessOptions& options = {});

}  // namespace lcjit::viewer
