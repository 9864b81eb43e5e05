// Headless rendering (see Headless.h): EGL without a window system, an offscreen framebuffer,
// the Renderer, and the framebuffer read back as an Image.
#include "viewer/Headless.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <mutex>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace lcjit::viewer {

namespace {

std::string eglErrorText(const char* what) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s (EGL error 0x%x)", what, (unsigned)eglGetError());
  return buf;
}

// One EGL display per process, never terminated (contexts of several renderers share it).
struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  bool surfaceless = false;  // EGL_MESA_platform_surfaceless
  std::string problem;
};

const Display& display() {
  static Display d;
  static std::once_flag once;
  std::call_once(once, [] {
    if (!epoxy_has_egl()) {
      d.problem = "no EGL library (libEGL) available";
      return;
    }
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless") &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")) {
      EGLDisplay dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, nullptr, nullptr)) {
        d.display = dpy;
        d.surfaceless = true;
        return;
      }
    }
    EGLDisplay dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, nullptr, nullptr)) {
      d.display = dpy;
      return;
    }
    d.problem = eglErrorText("cannot initialise an EGL display");
  });
  return d;
}

}  // namespace

llvm::Expected<runtime::Image> readFramebuffer(unsigned fbo, int w, int h) {
  runtime::Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(size_t(w) * h * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const size_t row = size_t(w) * 4;
  std::vector<uint8_t> tmp(row);
  for (int y = 0; y < h / 2; ++y) {
    uint8_t* a = &img.rgba[row * y];
    uint8_t* b = &img.rgba[row * (h - 1 - y)];
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
  if (GLenum e = glGetError(); e != GL_NO_ERROR) return llvm::createStringError("OpenGL error " + std::to_string(e) + " reading the picture");
  return img;
}

struct HeadlessRenderer::Impl {
  EGLDisplay dpy = EGL_NO_DISPLAY;
  EGLContext ctx = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;
  GLuint fbo = 0, color = 0, depth = 0;
  int width = 0, height = 0;
  std::unique_ptr<Renderer> renderer;

  bool makeCurrent() { return eglMakeCurrent(dpy, surface, surface, ctx); }

  llvm::Expected<runtime::Image> readImage(int w, int h) { return readFramebuffer(fbo, w, h); }

  llvm::Error ensureFramebuffer(int w, int h) {
    if (fbo && w == width && h == height) {
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      return llvm::Error::success();
    }
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (w <= 0 || h <= 0 || w > maxSize || h > maxSize)
      return llvm::createStringError("image size " + std::to_string(w) + "x" + std::to_string(h) + " not supported (at most " +
                   std::to_string(maxSize) + ")");
    if (!fbo) {
      glGenFramebuffers(1, &fbo);
      glGenRenderbuffers(1, &color);
      glGenRenderbuffers(1, &depth);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return llvm::createStringError("offscreen framebuffer incomplete");
    width = w;
    height = h;
    return llvm::Error::success();
  }

  ~Impl() {
    if (ctx != EGL_NO_CONTEXT && makeCurrent()) {
      renderer.reset();
      if (fbo) {
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &color);
        glDeleteRenderbuffers(1, &depth);
      }
    }
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface != EGL_NO_SURFACE) eglDestroySurface(dpy, surface);
    if (ctx != EGL_NO_CONTEXT) eglDestroyContext(dpy, ctx);
  }
};

HeadlessRenderer::HeadlessRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
HeadlessRenderer::~HeadlessRenderer() = default;

llvm::Expected<std::unique_ptr<HeadlessRenderer>> HeadlessRenderer::create() {
  const Display& d = display();
  if (d.display == EGL_NO_DISPLAY) return llvm::createStringError("headless rendering: " + d.problem);
  auto impl = std::make_unique<Impl>();
  impl->dpy = d.display;
  if (!eglBindAPI(EGL_OPENGL_API)) return llvm::createStringError(eglErrorText("headless rendering: no desktop OpenGL through EGL"));

  const bool surfacelessContext = epoxy_has_egl_extension(d.display, "EGL_KHR_surfaceless_context");
  const bool noConfig = epoxy_has_egl_extension(d.display, "EGL_KHR_no_config_context");
  EGLConfig config = nullptr;
  {
    const EGLint attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                            EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(d.display, attrs, &config, 1, &n) || n < 1) config = nullptr;
  }
  if (!config && !(noConfig && surfacelessContext)) return llvm::createStringError("headless rendering: no suitable EGL config");
  EGLConfig ctxConfig = config ? config : EGL_NO_CONFIG_KHR;
  const EGLint core33[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                           EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint compat33[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                             EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT, EGL_NONE};
  for (const EGLint* attrs : {core33, compat33}) {
    impl->ctx = eglCreateContext(d.display, ctxConfig, EGL_NO_CONTEXT, attrs);
    if (impl->ctx != EGL_NO_CONTEXT) break;
  }
  if (impl->ctx == EGL_NO_CONTEXT) return llvm::createStringError(eglErrorText("headless rendering: cannot create an OpenGL 3.3 context"));
  if (!surfacelessContext) {
    const EGLint pb[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    impl->surface = eglCreatePbufferSurface(d.display, config, pb);
    if (impl->surface == EGL_NO_SURFACE) return llvm::createStringError(eglErrorText("headless rendering: cannot create a pbuffer"));
  }
  if (!impl->makeCurrent()) return llvm::createStringError(eglErrorText("headless rendering: cannot make the context current"));
  if (epoxy_gl_version() < 33) return llvm::createStringError("headless rendering: OpenGL 3.3 needed, the context has " +
                                            std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10));
  impl->renderer = std::make_unique<Renderer>();
  return std::unique_ptr<HeadlessRenderer>(new HeadlessRenderer(std::move(impl)));
}

Renderer& HeadlessRenderer::renderer() {
  impl_->makeCurrent();
  return *impl_->renderer;
}

std::string HeadlessRenderer::glRenderer() const {
  impl_->makeCurrent();
  const char* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

llvm::Expected<runtime::Image> HeadlessRenderer::renderFrame(const runtime::ViewSettings& view,
                                                            const runtime::CameraMatrices& camera, const RenderOptions& options) {
  if (!impl_->makeCurrent()) return llvm::createStringError(eglErrorText("headless rendering: cannot make the context current"));
  if (llvm::Error e = impl_->ensureFramebuffer(camera.width, camera.height)) return e;
  Renderer& r = *impl_->renderer;
  r.draw(view, camera, options);
  if (!r.lastError().empty()) return llvm::createStringError("rendering: " + r.lastError());
  return impl_->readImage(camera.width, camera.height);
}

llvm::Expected<runtime::Image> HeadlessRenderer::renderPanes(const std::vector<ViewPane>& panes, const runtime::ViewSettings& view,
                                                            const RenderPalette& palette,
                                                            const std::vector<runtime::Image>& textures,
                                                            const HeadlessOptions& options) {
  if (!impl_->makeCurrent()) return llvm::createStringError(eglErrorText("headless rendering: cannot make the context current"));
  if (llvm::Error e = impl_->ensureFramebuffer(options.width, options.height)) return e;
  glViewport(0, 0, options.width, options.height);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(view.windowBorderColor.r, view.windowBorderColor.g, view.windowBorderColor.b, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  Renderer& r = *impl_->renderer;
  r.setPalette(palette);
  r.setTextures(textures);
  std::vector<ViewPane::Rect> placed;
  for (const ViewPane& pane : panes) placed.push_back(pane.rect);
  const std::vector<std::array<int, 4>> rects = paneRects(placed, options.width, options.height, view.windowBorderSize);
  for (size_t i = 0; i < panes.size(); ++i) {
    const ViewPane& pane = panes[i];
    const std::array<int, 4>& rect = rects[i];
    r.setGeometry(pane.geometry);
    runtime::CameraMatrices cam = runtime::paneCamera(view, pane, rect, options.adjust);
    RenderOptions o = options.render;
    o.viewportX = rect[0];
    o.viewportY = options.height - rect[1] - rect[3];  // GL counts from the bottom
    r.draw(view, cam, o);
    if (!r.lastError().empty()) return llvm::createStringError("rendering: " + r.lastError());
  }
  return impl_->readImage(options.width, options.height);
}

llvm::Expected<runtime::Image> HeadlessRenderer::render(const runtime::Geometry& geometry, const runtime::ViewSettings& view,
                                                       const RenderPalette& palette, const std::vector<runtime::Image>& textures,
                                                       const HeadlessOptions& options) {
  if (!impl_->makeCurrent()) return llvm::createStringError(eglErrorText("headless rendering: cannot make the context current"));
  Renderer& r = *impl_->renderer;
  r.setPalette(palette);
  r.setTextures(textures);
  r.setGeometry(geometry);
  runtime::CameraMatrices cam = runtime::frameView(view, geometry.framingBounds(), geometry.camera, options.width,
                                                   options.height, options.viewId, options.adjust);
  return renderFrame(view, cam, options.render);
}

llvm::Error renderToFile(const runtime::Geometry& geometry, const runtime::ViewSettings& view,
                         const RenderPalette& palette, const std::vector<runtime::Image>& textures,
                         const std::string& path, const HeadlessOptions& options) {
  auto r = HeadlessRenderer::create();
  if (!r) return r.takeError();
  auto img = (*r)->render(geometry, view, palette, textures, options);
  if (!img) return img.takeError();
  return writeImage(*img, path, options.render.backgroundAlpha < 1);
}

}  // namespace lcjit::viewer
