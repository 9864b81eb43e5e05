// The interactive window (Window.h): GLFW + the Renderer + Dear ImGui (1.86, Debian's libimgui
// with its GLFW and OpenGL 3 backends) for the main menu.
//
// Input: GLFW's callbacks only call Window::inject*; the window keeps its own mouse state and
// hands it to ImGui each frame (ImGui's GLFW backend would poll the real pointer, which a test
// driving the window cannot move). Mouse drags follow lpfg's tasks (viewtask.cpp): the task is
// chosen when the button goes down, from the button and the modifiers, and each cursor motion
// applies its delta at once, so a drag gives the same view whatever the frame rate.
//
// Where each part lives (each section begins with a `// ----` rule); Window::Impl, the state
// they share, is declared in WindowImpl.h:
//   This file: GLFW set-up and the preview's decimation · Drawing the scene and the panes ·
//     Window::create (GLFW window, GL context, ImGui, callbacks) · The scene (setScene,
//     setViews, resetView, the messages' texts) · The frame (frame(): the menus, the panels, the
//     messages, the picture, then the choices) · Pictures and the window's state (grabImage,
//     saveImage, sizes, camera).
//   WindowInput.cpp: The camera · lpfg's view tasks (rotate, roll, zoom, frustum, pan) · Mouse
//     and keys (inject*, the queue that feeds ImGui) · The pointer (takePointer).
//   WindowMenus.cpp: Menu items and Save · The layout file · The menus and the Save as dialog ·
//     The messages · Menu introspection.
//   WindowPanels.cpp: Curves · Colours · A panel · Panels by title.
#include "viewer/Window.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "viewer/WindowImpl.h"

namespace lcjit::viewer {

// ---------------------------------------------------------------------------------------------
// GLFW set-up and the preview's decimation

namespace {

std::string& glfwLastError() {
  static std::string e;
  return e;
}

void onGlfwError(int code, const char* text) {
  glfwLastError() = "GLFW error " + std::to_string(code) + ": " + (text ? text : "");
}

bool initGlfw() {
  static bool ok = [] {
    glfwSetErrorCallback(onGlfwError);
    return glfwInit() == GLFW_TRUE;
  }();
  return ok;
}

// Above this many segments + triangles, dragging draws the decimated preview.
constexpr size_t kPreviewLimit = 60000;

// Every k-th segment and triangle of a large geometry (k chosen to keep about `limit` of them),
// everything else as it is: the interaction preview.
runtime::Geometry decimated(const runtime::Geometry& g, size_t limit) {
  size_t total = g.segments.size() + g.triangleCount();
  size_t k = (total + limit - 1) / limit;
  runtime::Geometry d;
  d.vertices = g.vertices;
  d.discs = g.discs;
  d.labels = g.labels;
  d.camera = g.camera;
  d.extent = g.extent;
  d.oneSidedLighting = g.oneSidedLighting;
  for (size_t i = 0; i < g.segments.size(); i += k) d.addSegment(g.segments[i]);
  for (const runtime::TriangleRun& run : g.runs) {
    d.useTexture(run.texture, run.fill);
    for (uint32_t t = run.firstIndex; t + 2 < run.firstIndex + run.indexCount; t += uint32_t(3 * k))
      d.addTriangle(g.indices[t], g.indices[t + 1], g.indices[t + 2]);
  }
  return d;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Drawing the scene and the panes

Window::Impl::~Impl() {
  if (!window) return;
  glfwMakeContextCurrent(window);
  if (fbo) glDeleteFramebuffers(1, &fbo);
  if (colorRb) glDeleteRenderbuffers(1, &colorRb);
  if (depthRb) glDeleteRenderbuffers(1, &depthRb);
  renderer.reset();
  if (imgui) {
    ImGui::SetCurrentContext(imgui);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(imgui);
  }
  glfwDestroyWindow(window);
}

// Draws the scene into the bound framebuffer at the current camera.
void Window::Impl::drawScene() {
  if (!panes.empty()) return drawPanes();
  if (hasScene) {
    (preview && task != Task::Idle ? preview : renderer)->draw(view, camera, {});
  } else {
    auto [w, h] = fbSize();
    glViewport(0, 0, w, h);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
}

// The panes' rectangles in framebuffer pixels (x0, top y0, width, height), as lpfg lays them out.
std::vector<std::array<int, 4>> Window::Impl::layoutPanes() const {
  auto [w, h] = fbSize();
  std::vector<ViewPane::Rect> rects;
  for (const auto& p : panes) rects.push_back(p.rect);
  return viewer::paneRects(rects, w, h, view.windowBorderSize);
}

runtime::CameraMatrices Window::Impl::paneCamera(size_t i, const runtime::ViewAdjustment& a,
                                                 const std::array<int, 4>& r) const {
  return runtime::frameView(view, panes[i].bounds, panes[i].pose, r[2], r[3], panes[i].viewId, a);
}

// Each pane in its rectangle; the border colour shows between them.
void Window::Impl::drawPanes() {
  auto [w, h] = fbSize();
  glViewport(0, 0, w, h);
  glClearColor(view.windowBorderColor.r, view.windowBorderColor.g, view.windowBorderColor.b, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const auto rects = layoutPanes();
  for (size_t i = 0; i < panes.size(); ++i) {
    const auto& r = rects[i];
    RenderOptions o;
    o.viewportX = r[0];
    o.viewportY = h - r[1] - r[3];  // GL counts from the bottom
    panes[i].renderer->draw(view, paneCamera(i, i == activePane ? adjust : paneAdjust[i], r), o);
  }
}

// ---------------------------------------------------------------------------------------------
// Window::create (GLFW window, GL context, ImGui, callbacks)

Window::Window(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Window::~Window() = default;

llvm::Expected<std::unique_ptr<Window>> Window::create(const WindowOptions& o) {
  if (!initGlfw())
    return llvm::createStringError("cannot open a window: " + (glfwLastError().empty() ? std::string("glfwInit failed") : glfwLastError()) +
                 " (is DISPLAY set?)");
  int width = o.width, height = o.height;
  int x = -1, y = -1;
  if (o.position) std::tie(x, y) = *o.position;
  if (GLFWmonitor* m = glfwGetPrimaryMonitor()) {
    if (const GLFWvidmode* mode = glfwGetVideoMode(m)) {
      if (o.relW > 0) width = int(std::lround(o.relW * mode->width));
      if (o.relH > 0) height = int(std::lround(o.relH * mode->height));
      if (o.relX >= 0) x = int(std::lround(o.relX * mode->width));
      if (o.relY >= 0) y = int(std::lround(o.relY * mode->height));
    }
  }
  width = std::max(width, 1);
  height = std::max(height, 1);

  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
#ifdef __APPLE__
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#endif
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_DECORATED, o.borderless ? GLFW_FALSE : GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, o.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwLastError().clear();
  GLFWwindow* win = glfwCreateWindow(width, height, o.title.c_str(), nullptr, nullptr);
  if (!win) {
    // Some servers give no core profile: any context ≥ 3.3 will do.
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_ANY_PROFILE);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 1);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
    win = glfwCreateWindow(width, height, o.title.c_str(), nullptr, nullptr);
  }
  if (!win) return llvm::createStringError("cannot open a window: " + glfwLastError());
  auto impl = std::make_unique<Impl>();
  impl->window = win;
  impl->flat = o.flat;
  glfwMakeContextCurrent(win);
  if (epoxy_gl_version() < 33) {
    std::string v = std::to_string(epoxy_gl_version() / 10) + "." + std::to_string(epoxy_gl_version() % 10);
    return llvm::createStringError("the window's OpenGL context is " + v + ", 3.3 is needed");
  }
  if (x >= 0 && y >= 0) glfwSetWindowPos(win, x, y);
  glfwSwapInterval(o.vsync ? 1 : 0);

  impl->imgui = ImGui::CreateContext();
  ImGui::SetCurrentContext(impl->imgui);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  ImGui::StyleColorsLight();
  ImGui_ImplGlfw_InitForOpenGL(win, false);  // our callbacks forward to ImGui
  ImGui_ImplOpenGL3_Init("#version 330");
  impl->renderer = std::make_unique<Renderer>();

  std::unique_ptr<Window> w(new Window(std::move(impl)));
  glfwSetWindowUserPointer(win, w.get());
  glfwSetCursorPosCallback(win, [](GLFWwindow* gw, double px, double py) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->injectCursor(px, py);
  });
  glfwSetMouseButtonCallback(win, [](GLFWwindow* gw, int b, int a, int m) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->injectMouseButton(b, a, m);
  });
  glfwSetScrollCallback(win, [](GLFWwindow* gw, double dx, double dy) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->injectScroll(dx, dy);
  });
  glfwSetKeyCallback(win, [](GLFWwindow* gw, int k, int, int a, int m) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->injectKey(k, a, m);
  });
  glfwSetCharCallback(win, [](GLFWwindow* gw, unsigned c) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->injectChar(c);
  });
  glfwSetWindowFocusCallback(win, [](GLFWwindow* gw, int f) {
    Window* self = static_cast<Window*>(glfwGetWindowUserPointer(gw));
    ImGui::SetCurrentContext(self->impl_->imgui);
    ImGui_ImplGlfw_WindowFocusCallback(gw, f);
  });
  w->impl_->updateCamera();
  return std::move(w);
}

// ---------------------------------------------------------------------------------------------
// The scene (setScene, setViews, resetView, the messages' texts)

void Window::setScene(const runtime::Geometry& geometry, const runtime::ViewSettings& view, const RenderPalette& palette,
                      const std::vector<runtime::Image>& textures, Framing framing) {
  Impl& m = *impl_;
  m.makeCurrent();
  m.view = view;
  runtime::Bounds fresh = geometry.framingBounds();
  if (framing == Framing::Refit || !m.hasScene || m.bounds.empty() || fresh.empty()) {
    m.bounds = fresh;
  } else if (framing == Framing::HCenter) {
    float shift = fresh.center().x - m.bounds.center().x;
    m.bounds.min.x += shift;
    m.bounds.max.x += shift;
  }
  m.pose = geometry.camera;
  m.renderer->setPalette(palette);
  m.renderer->setTextures(textures);
  m.renderer->setGeometry(geometry);
  m.preview.reset();
  if (geometry.segments.size() + geometry.triangleCount() > kPreviewLimit) {
    m.preview = std::make_unique<Renderer>();
    m.preview->setPalette(palette);
    m.preview->setTextures(textures);
    m.preview->setGeometry(decimated(geometry, kPreviewLimit));
  }
  m.panes.clear();
  m.hasScene = true;
  // A view file with other zoom limits: keep the zoom within them.
  m.zoomBy(0);
}

void Window::setViews(const std::vector<ViewPane>& panes, const runtime::ViewSettings& view,
                      const RenderPalette& palette, const std::vector<runtime::Image>& textures) {
  Impl& m = *impl_;
  m.makeCurrent();
  m.view = view;
  if (m.panes.size() != panes.size()) {
    // A new layout: every pane starts from its view file framing.
    m.paneAdjust.assign(panes.size(), runtime::ViewAdjustment());
    m.activePane = 0;
    m.adjust = {};
  }
  m.panes.resize(panes.size());
  runtime::Bounds all;
  for (size_t i = 0; i < panes.size(); ++i) {
    Impl::Pane& p = m.panes[i];
    if (!p.renderer) p.renderer = std::make_unique<Renderer>();
    p.renderer->setPalette(palette);
    p.renderer->setTextures(textures);
    p.renderer->setGeometry(panes[i].geometry);
    p.bounds = panes[i].geometry.framingBounds();
    p.pose = panes[i].geometry.camera;
    p.rect = panes[i].rect;
    p.viewId = panes[i].viewId;
    all.add(p.bounds);
  }
  // Rotation and zoom work on the whole picture's framing.
  m.bounds = all;
  m.pose.reset();
  m.hasScene = true;
  m.zoomBy(0);
}

void Window::resetView() {
  impl_->adjust = {};
  for (auto& a : impl_->paneAdjust) a = {};
  impl_->frustum = 1;
  impl_->updateCamera();
}

void Window::setMessage(std::string text) { impl_->message = std::move(text); }
void Window::setStatus(std::string text) { impl_->status = std::move(text); }
const std::string& Window::message() const { return impl_->message; }
std::optional<std::array<float, 4>> Window::messageRect() const { return impl_->messageRect; }

// ---------------------------------------------------------------------------------------------
// The frame

bool Window::frame(const MenuActions& actions) {
  Impl& m = *impl_;
  glfwPollEvents();
  if (glfwWindowShouldClose(m.window)) return false;
  m.makeCurrent();
  m.updateCamera();  // the framebuffer may have been resized

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGuiIO& io = ImGui::GetIO();
  m.feedImGui();
  ImGui::NewFrame();

  MenuChoice choice;
  drawMenus(m, actions, *this, choice);
  m.panelRects.clear();
  std::vector<std::function<void()>> edits;
  float panelTop = 8;
  for (const Panel& p : actions.panels)
    if (m.openPanels.count(p.title)) m.drawPanel(p, panelTop, edits);
  drawMessages(m);
  ImGui::Render();
  m.wantMouse = io.WantCaptureMouse;
  m.writeLayout();

  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m.drawScene();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glfwSwapBuffers(m.window);

  // Actions run after the frame: they may replace the scene (setScene) or reset the view.
  if (choice.chosen) choice.chosen();
  for (const auto& edit : edits) edit();
  if (!choice.saveTo.empty()) m.save(choice.saveTo, actions, *this);
  return !choice.exitChosen && !glfwWindowShouldClose(m.window);
}

// ---------------------------------------------------------------------------------------------
// Pictures and the window's state

llvm::Expected<runtime::Image> Window::grabImage() {
  Impl& m = *impl_;
  m.makeCurrent();
  m.updateCamera();
  auto [w, h] = m.fbSize();
  if (!m.fbo || m.fboW != w || m.fboH != h) {
    if (!m.fbo) {
      glGenFramebuffers(1, &m.fbo);
      glGenRenderbuffers(1, &m.colorRb);
      glGenRenderbuffers(1, &m.depthRb);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, m.colorRb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, m.depthRb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m.colorRb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, m.depthRb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      return llvm::createStringError("cannot create the offscreen framebuffer for the picture");
    }
    m.fboW = w;
    m.fboH = h;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo);
  m.drawScene();
  if (m.hasScene && !m.renderer->lastError().empty()) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return llvm::createStringError("rendering: " + m.renderer->lastError());
  }
  return readFramebuffer(m.fbo, w, h);
}

llvm::Error Window::saveImage(const std::string& path) {
  if (!isImageFileName(path)) return llvm::createStringError("cannot save the picture as " + path + ": use " + kImageFileTypes);
  llvm::Expected<runtime::Image> img = grabImage();
  if (!img) return img.takeError();
  return writeImage(*img, path);
}

std::pair<int, int> Window::framebufferSize() const { return impl_->fbSize(); }
std::pair<int, int> Window::windowSize() const {
  int w = 0, h = 0;
  glfwGetWindowSize(impl_->window, &w, &h);
  return {w, h};
}
const runtime::CameraMatrices& Window::camera() const { return impl_->camera; }
const runtime::ViewAdjustment& Window::adjustment() const { return impl_->adjust; }
float Window::frustumFactor() const { return impl_->frustum; }
const Renderer& Window::renderer() const { return *impl_->renderer; }
std::string Window::glRenderer() const {
  impl_->makeCurrent();
  const char* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

}  // namespace lcjit::viewer
