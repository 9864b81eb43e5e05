// The interactive window (Window.h): GLFW + the Renderer + Dear ImGui (1.86, Debian's libimgui
// with its GLFW and OpenGL 3 backends) for the main menu.
//
// Input: GLFW's callbacks only call Window::inject*; the window keeps its own mouse state and
// hands it to ImGui each frame (ImGui's GLFW backend would poll the real pointer, which a test
// driving the window cannot move). Mouse drags follow lpfg's tasks (viewtask.cpp): the task is
// chosen when the button goes down, from the button and the modifiers, and each cursor motion
// applies its delta at once, so a drag gives the same view whatever the frame rate.
//
// Sections, in order: GLFW set-up and the preview's decimation · Window::Impl (state, panes and
// their cameras; `--- lpfg's view tasks`: rotate, roll, zoom, frustum, pan; mouse input; drawing
// the scene and the panes; Save As) · Window::create (GLFW window, GL context, ImGui, callbacks) ·
// setScene / setViews · frame(): one frame with the main menu, the user menu and the dialogs ·
// grabImage / saveImage · inject* (input from GLFW or a test) · depth picking (takePointer).
#include "viewer/Window.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <set>

#include <epoxy/gl.h>
// GLFW after epoxy: no GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/gtc/matrix_transform.hpp>

#include <imgui.h>
#include <imgui_internal.h>  // a panel's content size, to tell when its layout has settled
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "runtime/files/ReplacingFile.h"

namespace lcjit::viewer {
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


const char* kMenuId = "lcjit main menu";
const char* kUserMenuId = "lcjit user menu";
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

const char* kSaveId = "Save as";

}  // namespace

enum class Task { Idle, Rotate, Pan, Zoom, Frustum, Roll };

struct Window::Impl {
  GLFWwindow* window = nullptr;
  std::string message;  // setMessage()
  std::optional<std::array<float, 4>> messageRect;  // where the last frame drew it
  std::string status;  // setStatus()
  ImGuiContext* imgui = nullptr;
  std::unique_ptr<Renderer> renderer;
  // While the mouse drags the view of a very large model, a decimated copy is drawn so that
  // rotating stays fluid on software rendering; the full picture returns on release.
  std::unique_ptr<Renderer> preview;
  // Multi-view (manual §7.3): one pane per active view, each its own renderer and framing; the
  // mouse adjustment applies to all. Empty: the single scene of `renderer`.
  struct Pane {
    std::unique_ptr<Renderer> renderer;
    runtime::Bounds bounds;
    std::optional<runtime::CameraPose> pose;
    ViewPane::Rect rect;
    int viewId = 0;
  };
  std::vector<Pane> panes;
  // Multi-view: the mouse manipulates the pane it presses in (lpfg); `adjust` is that pane's,
  // the others keep theirs here.
  std::vector<runtime::ViewAdjustment> paneAdjust;
  size_t activePane = 0;
  void selectPaneAt(double x, double y) {
    if (panes.empty()) return;
    int ww = 0, wh = 0;
    glfwGetWindowSize(window, &ww, &wh);
    auto [fw, fh] = fbSize();
    // The pane whose rectangle (framebuffer pixels, as drawn) holds the pointer.
    const double fx = ww > 0 ? x * fw / ww : 0, fy = wh > 0 ? y * fh / wh : 0;
    const auto rects = layoutPanes();
    for (size_t i = 0; i < panes.size(); ++i) {
      const auto& r = rects[i];
      if (fx >= r[0] && fx < r[0] + r[2] && fy >= r[1] && fy < r[1] + r[3] && i != activePane) {
        paneAdjust[activePane] = adjust;
        adjust = paneAdjust[i];
        activePane = i;
        break;
      }
    }
  }

  // The scene.
  bool hasScene = false;
  runtime::ViewSettings view;
  runtime::Bounds bounds;
  std::optional<runtime::CameraPose> pose;

  // The user's adjustment of lpfg's framing.
  runtime::ViewAdjustment adjust;
  float frustum = 1;  // multiplies the near clipping distance (lpfg FrustumBy)
  runtime::CameraMatrices camera;

  // Input.
  double cursorX = 0, cursorY = 0;
  bool down[3] = {false, false, false};
  bool digitHeld[3] = {false, false, false};  // the 1/2/3 keys: lpfg's mouse-insertion keys

  // Dear ImGui 1.86 (Debian 12's) reads keys and buttons as states when a frame starts: a key
  // pressed and released between two frames (a quick tap while a frame is slow: a loaded
  // machine, xdotool) was never seen, so Enter or Ctrl+A in a text field could be lost, and Ctrl
  // released in the same frame made Ctrl+A a plain A. The events wait here in order, and each
  // frame takes one key change, or one button change, or a run of text (what ImGui 1.87 calls
  // trickling, a little stricter): every tap lasts a frame, and modifiers, text and clicks stay in
  // the order they came. waitEvents does not sleep while some wait.
  struct UiEvent {
    enum Kind { Key, Char, Button } kind;
    int code, action, mods;
    double x, y;  // the pointer, for a button
    bool* opens = nullptr;  // the menu a right button press opens
  };
  std::deque<UiEvent> uiEvents;
  bool uiDown[3] = {false, false, false};
  void feedImGui() {
    ImGuiIO& io = ImGui::GetIO();
    bool key = false, text = false, button = false;
    ImVec2 pointer{float(cursorX), float(cursorY)};
    for (; !uiEvents.empty(); uiEvents.pop_front()) {
      const UiEvent& e = uiEvents.front();
      if (e.kind == UiEvent::Key) {
        if (key || text || button) break;
        ImGui_ImplGlfw_KeyCallback(window, e.code, 0, e.action, e.mods);
        key = true;
      } else if (e.kind == UiEvent::Char) {
        if (key || button) break;
        ImGui_ImplGlfw_CharCallback(window, unsigned(e.code));
        text = true;
      } else {
        if (button || text || key) break;
        uiDown[e.code] = e.action == GLFW_PRESS;
        pointer = ImVec2(float(e.x), float(e.y));
        if (e.opens) *e.opens = true;
        button = true;
      }
    }
    // A click still waiting is made where it was made, not where the pointer has gone since.
    if (!button && !uiEvents.empty() && uiEvents.front().kind == UiEvent::Button)
      pointer = ImVec2(float(uiEvents.front().x), float(uiEvents.front().y));
    io.MousePos = pointer;
    for (int i = 0; i < 3; ++i) io.MouseDown[i] = uiDown[i];
  }
  bool comboDown = false, comboPushed = false, comboReleased = false;
  bool clickArmed = false, clicked = false;
  double clickX = 0, clickY = 0;
  int insert = 0;  // the module the last combination push asks for (Pointer::insert)
  Task task = Task::Idle;
  double lastX = 0, lastY = 0;
  int pressMods = 0;  // the modifiers of the last button press (a curve's Ctrl+click adds a point)

  // Menu.
  bool openMenu = false, menuIsOpen = false;
  bool openUserMenu = false, userMenuIsOpen = false;
  int shortcut = 0;  // a Ctrl/Cmd+key pressed since the last frame (GLFW key code)
  bool escape = false;  // Esc pressed since the last frame
  bool openSave = false, saveIsOpen = false, focusSaveField = false;
  bool wantMouse = false;  // ImGui wanted the mouse at the end of the last frame
  std::array<char, 1024> saveName{};
  std::map<std::string, std::array<float, 4>> itemRects;
  std::set<std::string> greyedItems;  // menu items drawn greyed out (no action now)
  std::string saveError;
  // Panels: which are open (by title), and where the last frame drew their items ("title\nlabel").
  std::set<std::string> openPanels;
  std::map<std::string, std::array<float, 4>> panelRects;
  // A Curve being dragged ("title\nlabel"): the point, and the box shown when the drag began, kept
  // so that the view does not slide under the pointer as the curve's extent changes.
  struct CurveDrag {
    int point = -1;
    std::array<float, 4> box{};
    std::array<float, 2> from{};  // the point when pressed: it moves by the pointer's motion, so a
                                  // straight up drag keeps x exactly
  };
  std::map<std::string, CurveDrag> curveDrags;

  // Offscreen target of grabImage().
  GLuint fbo = 0, colorRb = 0, depthRb = 0;
  int fboW = 0, fboH = 0;

  ~Impl() {
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

  void makeCurrent() {
    if (glfwGetCurrentContext() != window) glfwMakeContextCurrent(window);
    ImGui::SetCurrentContext(imgui);
  }

  std::pair<int, int> fbSize() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    return {std::max(w, 1), std::max(h, 1)};
  }
  // Framebuffer pixels per window coordinate (HiDPI).
  float pixelRatio() const {
    int ww = 0, wh = 0;
    glfwGetWindowSize(window, &ww, &wh);
    return ww > 0 ? float(fbSize().first) / float(ww) : 1.0f;
  }

  runtime::CameraMatrices frame(const runtime::ViewAdjustment& a, float frustumFactor) const {
    auto [w, h] = fbSize();
    runtime::CameraMatrices cam = runtime::frameView(view, bounds, pose, w, h, 0, a);
    if (cam.perspective && frustumFactor != 1.0f) {
      // lpfg Projection::FrustumBy: the near clipping distance scales, the eye follows, the
      // field of view stays.
      const float onc = cam.zShift - cam.halfDepth;
      const float nc = std::max(onc * frustumFactor, 0.001f);
      const float zShift = nc + cam.halfDepth;
      const float tanHalf = 1.0f / cam.projection[1][1];
      const float fovy = 2.0f * std::atan(tanHalf);
      cam.zShift = zShift;
      cam.eye = cam.lookAt - zShift * cam.viewDirection;
      cam.view = glm::lookAt(cam.eye, cam.lookAt, cam.up);
      cam.projection = glm::perspective(fovy, float(w) / float(h), std::max(zShift - cam.halfDepth, 0.001f),
                                        zShift + cam.halfDepth);
      cam.unitsPerPixel = 2.0f * zShift * tanHalf / h;
    }
    return cam;
  }
  void updateCamera() { camera = frame(adjust, frustum); }

  // --- lpfg's view tasks (projection.cpp), deltas in lpfg's signs --------------------------
  // RotateBy(0.1·dx, −0.1·dy) on half angles, applied as q⁻¹·v·q: the view turns by −0.2·dx°
  // about the initial up axis and by +0.2·dy° about the current left (= screen right) axis.
  void rotateBy(double dx, double dy) {
    const runtime::CameraMatrices base = frame({}, 1);
    const glm::vec3 upAxis = base.up;
    const glm::vec3 left = glm::normalize(glm::cross(camera.viewDirection, camera.up));
    glm::mat4 step = glm::rotate(glm::mat4(1), glm::radians(float(-0.2 * dx)), upAxis) *
                     glm::rotate(glm::mat4(1), glm::radians(float(0.2 * dy)), left);
    adjust.rotation = step * adjust.rotation;
    updateCamera();
  }
  // RollBy(0.5·(lastX − x)): −(lastX − x)° about the view direction.
  void rollBy(double dxLpfg) {
    adjust.rotation = glm::rotate(glm::mat4(1), glm::radians(float(-dxLpfg)), camera.viewDirection) * adjust.rotation;
    updateCamera();
  }
  // ZoomBy(dy), dy = y − lastY: lpfg's scale ×1.01^dy, clamped to [min zoom, max zoom].
  void zoomBy(double dy) {
    const float base = runtime::projectionScale(view, 0);  // the zoom limits apply to it
    const float lo = std::min(view.minZoom, view.maxZoom), hi = std::max(view.minZoom, view.maxZoom);
    float scale = base / adjust.zoom * std::pow(1.01f, float(dy));
    scale = std::clamp(scale, lo, hi);
    adjust.zoom = base / scale;
    updateCamera();
  }
  // FrustumBy(dy): the near distance ×1.01^dy (perspective only).
  void frustumBy(double dy) {
    if (!camera.perspective) return;
    const float onc = camera.zShift - camera.halfDepth;  // with the current factor
    float f = frustum * std::pow(1.01f, float(dy));
    const float baseOnc = onc / frustum;
    if (baseOnc > 0 && baseOnc * f < 0.001f) f = 0.001f / baseOnc;
    frustum = f;
    updateCamera();
  }
  // PanBy(dx, dy), dy upwards: the look-at point moves against the mouse by a pixel's worth of
  // model units per pixel, so the model follows the pointer.
  void panBy(double dx, double dy) {
    // In a multi-view window the pan follows the pointer in the pane being dragged.
    const runtime::CameraMatrices cam = panes.empty() ? camera : paneCamera(activePane, adjust, layoutPanes()[activePane]);
    const glm::vec3 left = glm::normalize(glm::cross(cam.viewDirection, cam.up));
    const float upp = cam.unitsPerPixel * pixelRatio();
    adjust.pan -= upp * (float(dy) * cam.up + float(dx) * left);
    updateCamera();
  }

  bool uiHasMouse() const { return menuIsOpen || userMenuIsOpen || saveIsOpen || wantMouse; }

  void onCursor(double x, double y) {
    const double dx = x - lastX, dyUp = lastY - y, dyDown = y - lastY;
    cursorX = x;
    cursorY = y;
    if (task == Task::Idle || (dx == 0 && dyUp == 0)) return;
    switch (task) {
      case Task::Rotate: rotateBy(dx, dyUp); break;
      case Task::Pan: panBy(dx, dyUp); break;
      case Task::Zoom: zoomBy(dyDown); break;
      case Task::Frustum: frustumBy(dyDown); break;
      case Task::Roll: rollBy(-dx); break;
      case Task::Idle: break;
    }
    lastX = x;
    lastY = y;
  }

  void onButton(int button, int action, int mods) {
    if (button < 0 || button > 2) return;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
      const bool shift = mods & GLFW_MOD_SHIFT, alt = mods & GLFW_MOD_ALT;
      const bool ctrl = mods & (GLFW_MOD_CONTROL | GLFW_MOD_SUPER);
      const bool combo = (shift && ctrl) || (alt && ctrl) || (shift && alt) || digitHeld[0] || digitHeld[1] || digitHeld[2];
      // In a panel, the combinations are its own (a curve's Shift+Ctrl+click), not the model's.
      if (action == GLFW_PRESS && combo && !uiHasMouse()) {
        comboDown = comboPushed = true;
        insert = (shift && ctrl) || digitHeld[0] ? 1 : (alt && ctrl) || digitHeld[1] ? 2 : 0;
      }
      if (action == GLFW_RELEASE && comboDown) comboDown = false, comboReleased = true;
      // A plain click: pressed with no key on the picture, released where it was pressed.
      if (action == GLFW_PRESS) {
        clickArmed = !mods && !uiHasMouse() && !combo;
        clickX = cursorX, clickY = cursorY;
      } else if (action == GLFW_RELEASE && clickArmed) {
        clickArmed = false;
        if (std::abs(cursorX - clickX) <= 3 && std::abs(cursorY - clickY) <= 3) clicked = true;
      }
    }
    if (action == GLFW_PRESS || action == GLFW_RELEASE)
      uiEvents.push_back({UiEvent::Button, button, action, mods, cursorX, cursorY});
    if (action == GLFW_PRESS) {
      down[button] = true;
      pressMods = mods;
    } else if (action == GLFW_RELEASE) {
      down[button] = false;
    }
    if (action == GLFW_RELEASE) {
      task = Task::Idle;
      return;
    }
    if (action != GLFW_PRESS) return;
    const bool shift = mods & GLFW_MOD_SHIFT;
    const bool ctrl = mods & (GLFW_MOD_CONTROL | GLFW_MOD_SUPER);
    const bool alt = mods & GLFW_MOD_ALT;
    if (button == GLFW_MOUSE_BUTTON_RIGHT) {
      // lpfg: two of Cmd (Ctrl), Shift and Alt with the right button open the user menu.
      // Opened in the frame where ImGui takes this press (a press it sees after the menu is open
      // would close the menu again).
      if (!saveIsOpen) uiEvents.back().opens = int(shift) + int(ctrl) + int(alt) >= 2 ? &openUserMenu : &openMenu;
      task = Task::Idle;
      return;
    }
    if (uiHasMouse()) return;  // the menu or the dialog takes the click
    selectPaneAt(cursorX, cursorY);
    lastX = cursorX;
    lastY = cursorY;
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
      // lpfg GLWidget::LBDown; Ctrl+Shift, Shift+Alt and Ctrl+Alt are lpfg's mouse insertion
      // and mouse status (model interaction), not view manipulation.
      if ((ctrl && shift) || (shift && alt) || (ctrl && alt)) task = Task::Idle;
      else if (shift) task = Task::Pan;
      else if (ctrl || alt) task = Task::Zoom;
      else task = Task::Rotate;
    } else {  // middle: GLWidget::MBDown
      if (ctrl) task = camera.perspective ? Task::Frustum : Task::Idle;
      else if (shift) task = Task::Roll;
      else task = Task::Zoom;
    }
  }

  void onScroll(double, double dy) {
    if (uiHasMouse()) return;
    zoomBy(-10.0 * dy);  // a wheel notch up: 10 pixels of upward zoom drag
  }

  // Draws the scene into the bound framebuffer at the current camera.
  void drawScene() {
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
  std::vector<std::array<int, 4>> layoutPanes() const {
    auto [w, h] = fbSize();
    std::vector<ViewPane::Rect> rects;
    for (const auto& p : panes) rects.push_back(p.rect);
    return viewer::paneRects(rects, w, h, view.windowBorderSize);
  }
  runtime::CameraMatrices paneCamera(size_t i, const runtime::ViewAdjustment& a, const std::array<int, 4>& r) const {
    return runtime::frameView(view, panes[i].bounds, panes[i].pose, r[2], r[3], panes[i].viewId, a);
  }

  // Each pane in its rectangle; the border colour shows between them.
  void drawPanes() {
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

  void save(const std::string& path, const MenuActions& actions, Window& self) {
    saveError.clear();
    if (path.empty()) {
      saveError = "no file name";
    } else if (isImageFileName(path)) {
      if (llvm::Error e = self.saveImage(path)) saveError = llvm::toString(std::move(e));
    } else if (actions.saveAs) {
      actions.saveAs(path);
    } else {
      saveError = "cannot save " + path + ": not an image (" + std::string(kImageFileTypes) + ")";
    }
    if (!saveError.empty()) std::fprintf(stderr, "lcjit: %s\n", saveError.c_str());
  }

  void menuItem(const char* label, const std::function<void()>& action, std::function<void()>& chosen,
                const char* shortcut = nullptr) {
    if (ImGui::MenuItem(label, shortcut, false, bool(action))) chosen = action;
    noteLastItem(label);
    if (action) greyedItems.erase(label);
    else greyedItems.insert(label);
  }
  void noteLastItem(const std::string& label) {
    ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    itemRects[label] = {a.x, a.y, b.x, b.y};
  }

  // LCJIT_WINDOW_LAYOUT=FILE: where the menu's items and the panels' controls are, one per line
  // ("LABEL<tab>x0 y0 x1 y1", a panel's as "TITLE/LABEL"; setMessage's text as "message/FIRST LINE",
  // setStatus's as "status/TEXT"; a menu item greyed out has a third field, "greyed", so that a
  // script waits for it to be usable instead of clicking it for nothing), rewritten when it changes. Scripts that
  // drive the window from outside (xdotool, tests/interactive) click what they name, not a guess.
  void writeLayout() {
    static const char* path = std::getenv("LCJIT_WINDOW_LAYOUT");
    if (!path || (layoutSettling > 0 && layoutSettling--)) return;
    std::string text;
    auto add = [&text, this](const std::string& label, const std::array<float, 4>& r) {
      char b[96];
      std::snprintf(b, sizeof b, "\t%.0f %.0f %.0f %.0f%s\n", r[0], r[1], r[2], r[3],
                    greyedItems.count(label) ? "\tgreyed" : "");
      text += label + b;
    };
    if (menuIsOpen || userMenuIsOpen || saveIsOpen)
      for (const auto& [label, r] : itemRects) add(label, r);
    if (messageRect) add("message/" + message.substr(0, message.find('\n')), *messageRect);
    for (const auto& [key, r] : panelRects) {
      std::string label = key;
      label[label.find('\n')] = '/';
      add(label, r);
    }
    if (text == layoutWritten) return;
    layoutWritten = text;
    llvm::consumeError(runtime::writeWholeFile(path, text));  // a test's aid: nothing to say if it fails
  }
  std::string layoutWritten;
  int layoutSettling = 0;  // frames before the layout is written again
  std::map<std::string, ImVec2> panelSizes;  // each panel's size in the last frame

  // ImGui::BeginMenu, noting where its label is (once open, ImGui's last item is the submenu's
  // window, so the place is taken before).
  bool beginMenu(const char* label) {
    ImVec2 at = ImGui::GetCursorScreenPos();
    float w = ImGui::GetContentRegionAvail().x, h = ImGui::GetFrameHeight();
    bool open = ImGui::BeginMenu(label);
    itemRects[label] = {at.x, at.y, at.x + w, at.y + h};
    if (open && ImGui::IsWindowAppearing()) layoutSettling = 3;  // the submenu places itself first
    return open;
  }

  void notePanelItem(const std::string& title, const std::string& label) {
    ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    panelRects[title + "\n" + label] = {a.x, a.y, b.x, b.y};
  }

  // Where a point added at `q` goes: a function's in x order, strictly between its ends; a
  // contour's into the side of its control polygon nearest the pointer (screen distance).
  template <class ToScreen>
  static std::optional<size_t> insertionPlace(const PanelControl& c, std::array<float, 2> q, const ToScreen& toScreen,
                                              ImVec2 mouse) {
    const size_t n = c.points.size();
    if (c.function) {
      if (n < 2 || !(q[0] > c.points.front()[0] && q[0] < c.points.back()[0])) return std::nullopt;
      size_t k = 1;
      while (k < n - 1 && c.points[k][0] <= q[0]) ++k;
      return k;
    }
    if (n < 2) return n;
    std::optional<size_t> place;
    float best = 0;
    const size_t sides = c.closed ? n : n - 1;
    for (size_t k = 0; k < sides; ++k) {
      const ImVec2 a = toScreen(c.points[k]), b = toScreen(c.points[(k + 1) % n]);
      const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      const float t = len2 > 0 ? std::clamp(((mouse.x - a.x) * dx + (mouse.y - a.y) * dy) / len2, 0.0f, 1.0f) : 0;
      const float ex = a.x + t * dx - mouse.x, ey = a.y + t * dy - mouse.y, d2 = ex * ex + ey * ey;
      if (!place || d2 < best) best = d2, place = k + 1;
    }
    return place;
  }

  // A curve editor: the control polygon and the curve in a box fitted around them (a contour's
  // with equal scales on both axes), the points as handles the left button drags.
  void drawCurve(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
    const PanelControl& c = p.controls[index];
    // Fixed sizes: the panel fits its contents (AlwaysAutoResize), so the contents cannot fit it.
    constexpr float w = 320, h = 240;
    const ImVec2 at = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton(c.label.c_str(), ImVec2(w, h));
    const std::string key = p.title + "\n" + c.label;
    const bool active = ImGui::IsItemActive();
    std::array<float, 4> box = {0, 0, 1, 1};  // x0, y0, x1, y1
    auto drag = curveDrags.find(key);
    if (active && drag != curveDrags.end()) {
      box = drag->second.box;
    } else {
      float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
      for (const auto* list : {&c.points, &c.curve})
        for (const auto& q : *list) {
          x0 = std::min(x0, q[0]), x1 = std::max(x1, q[0]);
          y0 = std::min(y0, q[1]), y1 = std::max(y1, q[1]);
        }
      if (c.function) x0 = std::min(x0, 0.0f), x1 = std::max(x1, 1.0f), y0 = std::min(y0, 0.0f), y1 = std::max(y1, 1.0f);
      if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
      float mx = std::max(x1 - x0, 1e-6f) * 0.08f, my = std::max(y1 - y0, 1e-6f) * 0.08f;
      x0 -= mx, x1 += mx, y0 -= my, y1 += my;
      if (!c.function) {  // a contour keeps its shape: one scale for both axes
        const float scale = std::max((x1 - x0) / w, (y1 - y0) / h);
        const float cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
        x0 = cx - scale * w / 2, x1 = cx + scale * w / 2, y0 = cy - scale * h / 2, y1 = cy + scale * h / 2;
      }
      box = {x0, y0, x1, y1};
    }
    auto toScreen = [&](const std::array<float, 2>& q) {
      return ImVec2(at.x + (q[0] - box[0]) / (box[2] - box[0]) * w, at.y + h - (q[1] - box[1]) / (box[3] - box[1]) * h);
    };
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(at, ImVec2(at.x + w, at.y + h), IM_COL32(255, 255, 255, 255));
    dl->AddRect(at, ImVec2(at.x + w, at.y + h), IM_COL32(160, 160, 160, 255));
    // The axes through the origin (a function's x = 0..1, y = 0 and 1 lines: funcedit's limits).
    const ImU32 axis = IM_COL32(200, 200, 220, 255);
    dl->AddLine(toScreen({box[0], 0}), toScreen({box[2], 0}), axis);
    dl->AddLine(toScreen({0, box[1]}), toScreen({0, box[3]}), axis);
    if (c.function) {
      dl->AddLine(toScreen({box[0], 1}), toScreen({box[2], 1}), axis);
      dl->AddLine(toScreen({1, box[1]}), toScreen({1, box[3]}), axis);
    }
    const size_t n = c.points.size();
    for (size_t k = 0; k + 1 < n + (c.closed && n > 2 ? 1 : 0); ++k)
      dl->AddLine(toScreen(c.points[k]), toScreen(c.points[(k + 1) % n]), IM_COL32(150, 150, 150, 255));
    for (size_t k = 0; k + 1 < c.curve.size(); ++k)
      dl->AddLine(toScreen(c.curve[k]), toScreen(c.curve[k + 1]), IM_COL32(20, 60, 200, 255), 2.0f);
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    if (ImGui::IsItemActivated()) {
      // The handle nearest the press, if within reach.
      CurveDrag d;
      d.box = box;
      float best = 10.0f * 10.0f;
      for (size_t k = 0; k < n; ++k) {
        const ImVec2 q = toScreen(c.points[k]);
        const float d2 = (q.x - mouse.x) * (q.x - mouse.x) + (q.y - mouse.y) * (q.y - mouse.y);
        if (d2 <= best) best = d2, d.point = int(k);
      }
      const bool ctrl = pressMods & (GLFW_MOD_CONTROL | GLFW_MOD_SUPER), shift = pressMods & GLFW_MOD_SHIFT;
      if (ctrl && shift) {  // funcedit's Delete; a function keeps its ends
        const bool end = c.function && (d.point == 0 || d.point == int(n) - 1);
        if (d.point >= 0 && !end && p.removed) chosen.push_back([f = p.removed, index, k = size_t(d.point)] { f(index, k); });
        d.point = -1;
      } else if (ctrl) {  // funcedit's Add, away from the points
        if (d.point < 0 && p.added) {
          const std::array<float, 2> q = {box[0] + (mouse.x - at.x) / w * (box[2] - box[0]),
                                          box[1] + (at.y + h - mouse.y) / h * (box[3] - box[1])};
          if (std::optional<size_t> before = insertionPlace(c, q, toScreen, mouse))
            chosen.push_back([f = p.added, index, k = *before, q] { f(index, k, q); });
        }
        d.point = -1;
      }
      if (d.point >= 0) d.from = c.points[d.point];
      curveDrags[key] = d;
    } else if (!active) {
      curveDrags.erase(key);
    }
    drag = curveDrags.find(key);
    const int dragged = active && drag != curveDrags.end() ? drag->second.point : -1;
    for (size_t k = 0; k < n; ++k) {
      const ImVec2 q = toScreen(c.points[k]);
      const ImU32 col = int(k) == dragged ? IM_COL32(230, 40, 40, 255) : IM_COL32(30, 30, 30, 255);
      dl->AddRectFilled(ImVec2(q.x - 4, q.y - 4), ImVec2(q.x + 4, q.y + 4), col);
      panelRects[key + "#" + std::to_string(k)] = {q.x - 4, q.y - 4, q.x + 4, q.y + 4};
    }
    // A press without a move is no edit (a point's screen place does not map back to its exact value).
    const ImVec2 pressed = ImGui::GetIO().MouseClickedPos[ImGuiMouseButton_Left];
    if (dragged < 0 || (mouse.x == pressed.x && mouse.y == pressed.y)) return;
    const std::array<float, 2> from = drag->second.from;
    float x = mouse.x == pressed.x ? from[0] : from[0] + (mouse.x - pressed.x) / w * (box[2] - box[0]);
    const float y = mouse.y == pressed.y ? from[1] : from[1] - (mouse.y - pressed.y) / h * (box[3] - box[1]);
    if (c.function) {
      if (dragged == 0) x = 0;
      else if (size_t(dragged) == n - 1) x = 1;
      else x = std::clamp(x, c.points[dragged - 1][0], c.points[dragged + 1][0]);
    }
    const auto& old = c.points[dragged];
    if ((x != old[0] || y != old[1]) && p.edited)
      chosen.push_back([f = p.edited, index, k = size_t(dragged), x, y] { f(index, k, {x, y, 0, 0}); });
  }

  // A grid of colours, 16 to a row; the selected one framed.
  void drawSwatches(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
    const PanelControl& c = p.controls[index];
    constexpr float side = 18;
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(2, 2));
    for (size_t k = 0; k < c.colors.size(); ++k) {
      if (k % 16) ImGui::SameLine();
      const auto& q = c.colors[k];
      ImGui::PushID(int(k));
      const bool selected = int(k) == int(c.value);
      if (selected) ImGui::PushStyleColor(ImGuiCol_Border, ImVec4(1, 0.1f, 0.1f, 1));
      if (selected) ImGui::PushStyleVar(ImGuiStyleVar_FrameBorderSize, 2.0f);
      const bool clicked = ImGui::ColorButton("##c", ImVec4(q[0], q[1], q[2], 1),
                                              ImGuiColorEditFlags_NoAlpha | ImGuiColorEditFlags_NoTooltip, ImVec2(side, side));
      if (selected) ImGui::PopStyleVar(), ImGui::PopStyleColor();
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%zu: %d %d %d", k, int(std::lround(q[0] * 255)), int(std::lround(q[1] * 255)),
                                                    int(std::lround(q[2] * 255)));
      notePanelItem(p.title, c.label + "#" + std::to_string(k));
      if (clicked && p.changed) chosen.push_back([f = p.changed, index, k] { f(index, float(k)); });
      ImGui::PopID();
    }
    ImGui::PopStyleVar();
  }

  // One colour on one line: a swatch, its label, and a slider for each of its bytes (a material's
  // four colours fit the panel one under the other).
  void drawColor(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
    const PanelControl& c = p.controls[index];
    std::array<float, 4> q = c.colors.empty() ? std::array<float, 4>{0, 0, 0, 1} : c.colors[0];
    const float height = ImGui::GetFrameHeight();
    ImGui::ColorButton("##swatch", ImVec4(q[0], q[1], q[2], 1), ImGuiColorEditFlags_NoAlpha, ImVec2(height, height));
    ImGui::SameLine();
    const float labelAt = ImGui::GetCursorPosX();
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted(c.label.c_str());
    if (!c.tooltip.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", c.tooltip.c_str());
    static const char* names[3] = {"R", "G", "B"};
    static const char* formats[3] = {"R %d", "G %d", "B %d"};
    constexpr float kSliderWidth = 64;
    bool edited = false;
    for (int k = 0; k < 3; ++k) {
      ImGui::SameLine(k == 0 ? labelAt + 84 : 0);
      int byte = int(std::lround(q[k] * 255));
      ImGui::SetNextItemWidth(kSliderWidth);
      ImGui::PushID(k);
      if (ImGui::SliderInt("##byte", &byte, 0, 255, formats[k])) {
        q[k] = float(byte) / 255.0f;
        edited = true;
      }
      ImGui::PopID();
      notePanelItem(p.title, c.label + " " + names[k]);
    }
    if (edited && !c.colors.empty() && q != c.colors[0] && p.edited)
      chosen.push_back([f = p.edited, index, q] { f(index, 0, q); });
  }

  // One open panel, stacked down the right side at first (the user may move it); its edits become
  // `chosen` actions, run after the frame as menu choices are.
  // `top`: where the panel starts; set to where the next one may start.
  void drawPanel(const Panel& p, float& top, std::vector<std::function<void()>>& chosen) {
    ImGuiIO& io = ImGui::GetIO();
    constexpr float kWidth = 340;
    // A column down the right edge: each panel hangs from it (growing leftwards to fit its
    // longest label or row), below the one before; at most 60 % of the width, scrolled beyond.
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 8, top), ImGuiCond_Always, ImVec2(1, 0));
    ImGui::SetNextWindowSizeConstraints(ImVec2(kWidth, 0),
                                        ImVec2(std::max(kWidth, io.DisplaySize.x * 0.6f), io.DisplaySize.y - top - 8));
    ImGui::SetNextWindowBgAlpha(0.88f);
    bool open = true;
    constexpr ImGuiWindowFlags kFlags = ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize |
                                        ImGuiWindowFlags_HorizontalScrollbar | ImGuiWindowFlags_NoMove;
    if (ImGui::Begin(p.title.c_str(), &open, kFlags)) {
      // A panel sizes itself over its first frames, and moves with its size (it hangs from the
      // right edge): its layout is not told until that is over.
      if (ImGui::IsWindowAppearing()) layoutSettling = 3;
      for (size_t i = 0; i < p.controls.size(); ++i) {
        const PanelControl& c = p.controls[i];
        ImGui::PushID(int(i));
        float v = c.value;
        bool edited = false;
        switch (c.kind) {
          case PanelControl::Kind::Text:
            if (c.sameLine) ImGui::SameLine();
            ImGui::TextUnformatted(c.label.c_str());
            break;
          case PanelControl::Kind::Button:
            if (c.sameLine) ImGui::SameLine();
            edited = ImGui::Button(c.label.c_str());
            v = c.value + 1;  // any change: the press
            break;
          case PanelControl::Kind::Choice: {
            int chosen = int(c.value);
            ImGui::SetNextItemWidth(kWidth * 0.55f);
            const char* preview = chosen >= 0 && chosen < int(c.options.size()) ? c.options[size_t(chosen)].c_str() : "";
            if (ImGui::BeginCombo(c.label.c_str(), preview)) {
              if (ImGui::IsWindowAppearing()) layoutSettling = 3;  // the list places itself first
              for (int k = 0; k < int(c.options.size()); ++k) {
                if (ImGui::Selectable(c.options[size_t(k)].c_str(), k == chosen)) v = float(k), edited = true;
                notePanelItem(p.title, c.options[size_t(k)]);
              }
              ImGui::EndCombo();
            }
            break;
          }
          case PanelControl::Kind::Toggle: {
            bool on = c.value != 0;
            if (c.group >= 0 ? ImGui::RadioButton(c.label.c_str(), on) : ImGui::Checkbox(c.label.c_str(), &on)) {
              v = c.group >= 0 ? 1.0f : (on ? 1.0f : 0.0f);
              edited = true;
            }
            break;
          }
          case PanelControl::Kind::Slider:
            ImGui::SetNextItemWidth(kWidth * 0.55f);
            if (c.min < c.max) {
              edited = ImGui::SliderFloat(c.label.c_str(), &v, c.min, c.max, "%.6g");
              if (edited && c.step > 0) v = std::round(v / c.step) * c.step;
            } else {
              edited = ImGui::DragFloat(c.label.c_str(), &v, std::max(std::fabs(c.value) / 100.0f, 0.001f), 0, 0, "%.6g");
            }
            break;
          case PanelControl::Kind::Curve:
            drawCurve(p, i, chosen);
            break;
          case PanelControl::Kind::Swatches:
            drawSwatches(p, i, chosen);
            break;
          case PanelControl::Kind::Color:
            drawColor(p, i, chosen);
            break;
        }
        if (c.kind != PanelControl::Kind::Swatches && c.kind != PanelControl::Kind::Color) notePanelItem(p.title, c.label);
        if (c.kind == PanelControl::Kind::Slider) {  // the slider's frame, without its label
          std::array<float, 4>& r = panelRects[p.title + "\n" + c.label];
          r[2] = r[0] + kWidth * 0.55f;
        }
        if (!c.tooltip.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", c.tooltip.c_str());
        if (edited && v != c.value && p.changed) chosen.push_back([f = p.changed, i, v] { f(i, v); });
        ImGui::PopID();
      }
      if (!p.columns.empty() &&
          ImGui::BeginTable("##table", int(p.columns.size()),
                            ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
        for (const std::string& c : p.columns) ImGui::TableSetupColumn(c.c_str());
        ImGui::TableHeadersRow();
        for (const auto& row : p.rows) {
          ImGui::TableNextRow();
          for (size_t k = 0; k < row.size() && k < p.columns.size(); ++k) {
            ImGui::TableSetColumnIndex(int(k));
            ImGui::TextUnformatted(row[k].c_str());
          }
        }
        ImGui::EndTable();
      }
      for (size_t b = 0; b < p.buttons.size(); ++b) {
        if (b) ImGui::SameLine();
        bool pressed = ImGui::Button(p.buttons[b].c_str());
        notePanelItem(p.title, p.buttons[b]);
        if (pressed && p.pressed) chosen.push_back([f = p.pressed, b] { f(b); });
      }
      if (!p.status.empty()) ImGui::TextWrapped("%s", p.status.c_str());
    }
    top = ImGui::GetWindowPos().y + ImGui::GetWindowSize().y + 8;
    // A panel whose contents grew or shrank resizes (and, hanging from the right edge, moves) over
    // the next frames: its layout is not told until it has stopped.
    // ImGui sizes a window from its previous frame's contents (ImGuiWindow::ContentSizeIdeal, as
    // ImGui computes it): contents that differ now move it in the next frame.
    const ImGuiWindow* w = ImGui::GetCurrentWindow();
    const ImVec2 ideal(std::floor(std::max(w->DC.CursorMaxPos.x, w->DC.IdealMaxPos.x) - w->DC.CursorStartPos.x),
                       std::floor(std::max(w->DC.CursorMaxPos.y, w->DC.IdealMaxPos.y) - w->DC.CursorStartPos.y));
    if (ideal.x != w->ContentSizeIdeal.x || ideal.y != w->ContentSizeIdeal.y) layoutSettling = std::max(layoutSettling, 2);
    ImVec2 size = ImGui::GetWindowSize();
    auto [last, added] = panelSizes.try_emplace(p.title, size);
    if (!added && (last->second.x != size.x || last->second.y != size.y)) layoutSettling = std::max(layoutSettling, 2);
    last->second = size;
    ImGui::End();
    if (!open) openPanels.erase(p.title);
  }
};

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

void Window::setScene(const runtime::Geometry& geometry, const runtime::ViewSettings& view, const RenderPalette& palette,
                      const std::vector<TextureImage>& textures, Framing framing) {
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
                      const RenderPalette& palette, const std::vector<TextureImage>& textures) {
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

  std::function<void()> chosen;
  bool exitChosen = false;
  if (m.openMenu) {
    ImGui::OpenPopup(kMenuId);
    m.openMenu = false;
  }
  m.menuIsOpen = false;
  if (ImGui::BeginPopup(kMenuId)) {
    m.menuIsOpen = true;
    if (ImGui::IsWindowAppearing()) m.layoutSettling = 3;
    m.itemRects.clear();
    // lpfg §1.2.2, with the animate menu of §1.2.3 in place of "Animate" while animating.
    m.menuItem("New model", actions.newModel, chosen);
    m.menuItem("New L-system", actions.newLsystem, chosen);
    m.menuItem("New run", actions.newRun, chosen);
    m.menuItem("New view", actions.newView, chosen);
    m.menuItem("New rendering", actions.newRendering, chosen);
    ImGui::Separator();
    std::function<void()> save, saveAs, exit;
    const std::string saveName = actions.saveName;
    if (!saveName.empty() && (isImageFileName(saveName) || actions.saveAs))
      save = [&m, &actions, saveName, this] { m.save(saveName, actions, *this); };
    saveAs = [&m, saveName] {
      std::snprintf(m.saveName.data(), m.saveName.size(), "%s", saveName.c_str());
      m.openSave = true;
    };
    m.menuItem("Save", save, chosen);
    m.menuItem("Save as...", saveAs, chosen);
    if (m.beginMenu("String")) {
      m.menuItem("Input", actions.stringInput, chosen);
      m.menuItem("Output", actions.stringOutput, chosen);
      ImGui::EndMenu();
    }
    ImGui::Separator();
    if (actions.animating) {
      m.menuItem("Step", actions.step, chosen, "Ctrl+F");
      m.menuItem("Run", actions.run, chosen, "Ctrl+R");
      m.menuItem("Forever", actions.forever, chosen, "Ctrl+V");
      m.menuItem("Stop", actions.stop, chosen, "Ctrl+S");
      m.menuItem("Rewind", actions.rewind, chosen, "Ctrl+W");
      m.menuItem("Clear", actions.clear, chosen);
      m.menuItem("New animate", actions.newAnimate, chosen);
      m.menuItem("Start recording", actions.startRecording, chosen);
      m.menuItem("Don't animate", actions.dontAnimate, chosen);
    } else {
      m.menuItem("Animate", actions.animate, chosen);
    }
    if (!actions.panels.empty() && m.beginMenu("Panels")) {
      for (const Panel& p : actions.panels) {
        bool open = m.openPanels.count(p.title) != 0;
        if (ImGui::MenuItem(p.title.c_str(), nullptr, open))
          chosen = [&m, title = p.title, open] {
            if (open) m.openPanels.erase(title);
            else m.openPanels.insert(title);
          };
        m.noteLastItem(p.title);
      }
      ImGui::EndMenu();
    }
    if (actions.setRefreshMode && m.beginMenu("Refresh mode")) {
      std::function<void()> explicitMode = [&actions] { actions.setRefreshMode(false); };
      std::function<void()> monitorMode = [&actions] { actions.setRefreshMode(true); };
      if (ImGui::MenuItem("Explicit", nullptr, !actions.monitoring)) chosen = explicitMode;
      m.noteLastItem("Explicit");
      if (ImGui::MenuItem("Triggered/Continuous", nullptr, actions.monitoring)) chosen = monitorMode;
      m.noteLastItem("Triggered/Continuous");
      ImGui::EndMenu();
    }
    ImGui::Separator();
    if (actions.exit) exit = [&exitChosen, &actions] { exitChosen = true; actions.exit(); };
    m.menuItem("Exit", exit, chosen);
    ImGui::EndPopup();
  }
  m.menuIsOpen = ImGui::IsPopupOpen(kMenuId);
  if (m.openUserMenu) {
    ImGui::OpenPopup(kUserMenuId);
    m.openUserMenu = false;
  }
  if (ImGui::BeginPopup(kUserMenuId)) {
    m.itemRects.clear();
    if (ImGui::IsWindowAppearing()) m.layoutSettling = 3;
    if (actions.userMenu.empty()) ImGui::TextDisabled("(no user menu items)");
    for (const auto& [label, code] : actions.userMenu) {
      std::function<void()> pick;
      if (actions.userChoice) pick = [&actions, code = code] { actions.userChoice(code); };
      m.menuItem(label.c_str(), pick, chosen);
    }
    ImGui::EndPopup();
  }
  m.userMenuIsOpen = ImGui::IsPopupOpen(kUserMenuId);
  if (m.shortcut && actions.animating && !m.saveIsOpen) {
    const std::function<void()>* byKey = m.shortcut == GLFW_KEY_F   ? &actions.step
                                         : m.shortcut == GLFW_KEY_R ? &actions.run
                                         : m.shortcut == GLFW_KEY_V ? &actions.forever
                                         : m.shortcut == GLFW_KEY_S ? &actions.stop
                                         : m.shortcut == GLFW_KEY_W ? &actions.rewind
                                                                    : nullptr;
    if (byKey && *byKey) chosen = *byKey;
  }
  m.shortcut = 0;
  if (m.escape && !m.saveIsOpen && !chosen && actions.interrupt) chosen = actions.interrupt;
  m.escape = false;

  if (m.openSave) {
    ImGui::OpenPopup(kSaveId);
    m.openSave = false;
    m.focusSaveField = true;
  }
  m.saveIsOpen = false;
  std::string saveTo;
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Appearing,
                          ImVec2(0.5f, 0.5f));
  if (ImGui::BeginPopupModal(kSaveId, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    m.saveIsOpen = true;
    if (ImGui::IsWindowAppearing()) m.layoutSettling = 3;  // sized and centred in its first frames
    ImGui::TextUnformatted("File name (the extension chooses the format):");
    ImGui::TextDisabled(".png .jpg .bmp: the picture; .obj .ply .stl .gltf .glb .svg .ps .eps .pov .strb: %s",
                        actions.saveAs ? "the model" : "not available");
    if (m.focusSaveField) {
      ImGui::SetKeyboardFocusHere();
      m.focusSaveField = false;
    }
    ImGui::SetNextItemWidth(420);
    bool enter = ImGui::InputText("##file", m.saveName.data(), m.saveName.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    m.itemRects["##file"] = {a.x, a.y, b.x, b.y};
    bool ok = ImGui::Button("Save");
    a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    m.itemRects["Save##dialog"] = {a.x, a.y, b.x, b.y};
    ImGui::SameLine();
    bool cancel = ImGui::Button("Cancel") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape));
    a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    m.itemRects["Cancel##dialog"] = {a.x, a.y, b.x, b.y};
    if (enter || ok) saveTo = m.saveName.data();
    if (enter || ok || cancel) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  m.saveIsOpen = ImGui::IsPopupOpen(kSaveId);
  m.panelRects.clear();
  std::vector<std::function<void()>> edits;
  float panelTop = 8;
  for (const Panel& p : actions.panels)
    if (m.openPanels.count(p.title)) m.drawPanel(p, panelTop, edits);
  if (!m.message.empty()) {
    // Over the picture's top left corner, which stays the last good model's: the problem with
    // the edit (compile diagnostics with their source lines, a fault in model code).
    ImGui::SetNextWindowPos(ImVec2(8, 8));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(io.DisplaySize.x - 16, io.DisplaySize.y - 16));
    constexpr ImGuiWindowFlags kFlags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                        ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                        ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;
    if (ImGui::Begin("##lcjit-message", nullptr, kFlags)) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.55f, 0.45f, 1.0f));
      ImGui::PushTextWrapPos(io.DisplaySize.x - 32);  // a long diagnostic wraps inside the window
      ImGui::TextUnformatted(m.message.c_str());
      ImGui::PopTextWrapPos();
      ImGui::PopStyleColor();
      ImVec2 a = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
      m.messageRect = {a.x, a.y, a.x + size.x, a.y + size.y};
    }
    ImGui::End();
  } else {
    m.messageRect.reset();
  }
  if (!m.status.empty()) {
    ImGui::SetNextWindowPos(ImVec2(8, io.DisplaySize.y - 8), ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.6f);
    constexpr ImGuiWindowFlags kFlags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                        ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                        ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs;
    if (ImGui::Begin("##lcjit-status", nullptr, kFlags)) {
      ImGui::TextUnformatted(m.status.c_str());
      ImVec2 a = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
      m.panelRects["status\n" + m.status] = {a.x, a.y, a.x + size.x, a.y + size.y};
    }
    ImGui::End();
  }
  ImGui::Render();
  m.wantMouse = io.WantCaptureMouse;
  m.writeLayout();

  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m.drawScene();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glfwSwapBuffers(m.window);

  // Actions run after the frame: they may replace the scene (setScene) or reset the view.
  if (chosen) chosen();
  for (const auto& edit : edits) edit();
  if (!saveTo.empty()) m.save(saveTo, actions, *this);
  return !exitChosen && !glfwWindowShouldClose(m.window);
}

llvm::Expected<Image> Window::grabImage() {
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
  llvm::Expected<Image> img = grabImage();
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

void Window::injectCursor(double x, double y) { impl_->onCursor(x, y); }
void Window::injectMouseButton(int button, int action, int mods) { impl_->onButton(button, action, mods); }
void Window::injectScroll(double dx, double dy) {
  ImGui::SetCurrentContext(impl_->imgui);
  ImGui_ImplGlfw_ScrollCallback(impl_->window, dx, dy);
  impl_->onScroll(dx, dy);
}
void Window::injectKey(int key, int action, int mods) {
  if (action != GLFW_REPEAT) impl_->uiEvents.push_back({Impl::UiEvent::Key, key, action, mods, 0, 0});
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_3 && action != GLFW_REPEAT)
    impl_->digitHeld[key - GLFW_KEY_1] = action == GLFW_PRESS;
  if (action == GLFW_PRESS && (mods & (GLFW_MOD_CONTROL | GLFW_MOD_SUPER))) impl_->shortcut = key;
  if (action == GLFW_PRESS && key == GLFW_KEY_ESCAPE) impl_->escape = true;
}
void Window::injectChar(unsigned codepoint) {
  impl_->uiEvents.push_back({Impl::UiEvent::Char, int(codepoint), 0, 0, 0, 0});
}

void Window::waitEvents(double seconds) {
  if (impl_->uiEvents.empty()) glfwWaitEventsTimeout(seconds);
}

void Window::wake() { glfwPostEmptyEvent(); }

Window::Pointer Window::takePointer() {
  Impl& m = *impl_;
  Pointer p;
  p.x = (int)m.cursorX;
  p.y = (int)m.cursorY;
  // Unproject the cursor at the near plane, the far plane and halfway (window y runs down).
  const runtime::CameraMatrices& c = m.camera;
  auto [ww, wh] = windowSize();
  glm::vec4 viewport(0, 0, (float)c.width, (float)c.height);
  float sx = ww > 0 ? (float)c.width / (float)ww : 1, sy = wh > 0 ? (float)c.height / (float)wh : 1;
  p.fbX = (float)m.cursorX * sx;
  p.fbY = (float)m.cursorY * sy;
  glm::vec3 win(p.fbX, (float)c.height - p.fbY, 0);
  auto at = [&](float depth, double* out) {
    win.z = depth;
    glm::vec3 v = glm::unProject(win, c.view, c.projection, viewport);
    out[0] = v.x, out[1] = v.y, out[2] = v.z;
  };
  at(0, p.front);
  at(1, p.rear);
  at(0.5f, p.middle);
  p.down = m.comboDown;
  p.pushed = m.comboPushed;
  p.released = m.comboReleased;
  p.insert = m.comboPushed ? m.insert : 0;
  m.comboPushed = m.comboReleased = false;
  p.clicked = std::exchange(m.clicked, false);
  p.clickFbX = float(m.clickX) * sx;
  p.clickFbY = float(m.clickY) * sy;
  return p;
}

void Window::showPanel(const std::string& title, bool open) {
  if (open) impl_->openPanels.insert(title);
  else impl_->openPanels.erase(title);
}
bool Window::panelOpen(const std::string& title) const { return impl_->openPanels.count(title) != 0; }
std::optional<std::array<float, 4>> Window::panelItemRect(const std::string& title, const std::string& label) const {
  auto it = impl_->panelRects.find(title + "\n" + label);
  if (it == impl_->panelRects.end()) return std::nullopt;
  return it->second;
}

bool Window::menuOpen() const { return impl_->menuIsOpen; }
bool Window::userMenuOpen() const { return impl_->userMenuIsOpen; }
bool Window::saveDialogOpen() const { return impl_->saveIsOpen; }
std::optional<std::array<float, 4>> Window::menuItemRect(const std::string& label) const {
  auto it = impl_->itemRects.find(label);
  if (it == impl_->itemRects.end()) return std::nullopt;
  return it->second;
}
const std::string& Window::lastSaveError() const { return impl_->saveError; }

}  // namespace lcjit::viewer
