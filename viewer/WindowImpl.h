// The window's state (Window::Impl), shared by the files that make the window: Window.cpp (GLFW
// set-up, the scene, the frame loop, pictures), WindowInput.cpp (the camera, lpfg's view tasks,
// mouse and keys), WindowMenus.cpp (the main menu, the user menu, the Save as dialog, the
// messages over the picture, the layout file) and WindowPanels.cpp (the panels). Internal to the
// window, as imgui_internal.h is to Dear ImGui.
#pragma once
#include <algorithm>
#include <array>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <epoxy/gl.h>
// GLFW after epoxy: no GL header of its own.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "viewer/Window.h"

namespace lcjit::viewer {

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
  bool comboDown = false, comboPushed = false, comboReleased = false;
  bool clickArmed = false, clicked = false;
  double clickX = 0, clickY = 0;
  int insert = 0;  // the module the last combination push asks for (Pointer::insert)
  Task task = Task::Idle;
  bool flat = false;  // WindowOptions::flat
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
  // LCJIT_WINDOW_LAYOUT (writeLayout): what was written last, and how long to wait before writing.
  std::string layoutWritten;
  int layoutSettling = 0;  // frames before the layout is written again
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
  std::map<std::string, ImVec2> panelSizes;  // each panel's size in the last frame

  // Offscreen target of grabImage().
  GLuint fbo = 0, colorRb = 0, depthRb = 0;
  int fboW = 0, fboH = 0;

  ~Impl();

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
  void updateCamera() { camera = frame(adjust, frustum); }
  bool uiHasMouse() const { return menuIsOpen || userMenuIsOpen || saveIsOpen || wantMouse; }

  // Window.cpp: the scene and the panes.
  void drawScene();
  std::vector<std::array<int, 4>> layoutPanes() const;
  runtime::CameraMatrices paneCamera(size_t i, const runtime::ViewAdjustment& a, const std::array<int, 4>& r) const;
  void drawPanes();

  // WindowInput.cpp: the camera, lpfg's view tasks, mouse and keys.
  runtime::CameraMatrices frame(const runtime::ViewAdjustment& a, float frustumFactor) const;
  void rotateBy(double dx, double dy);
  void rollBy(double dxLpfg);
  void zoomBy(double dy);
  void frustumBy(double dy);
  void panBy(double dx, double dy);
  void selectPaneAt(double x, double y);
  void onCursor(double x, double y);
  void onButton(int button, int action, int mods);
  void onScroll(double, double dy);
  void feedImGui();

  // WindowMenus.cpp: menu items, Save, the layout file.
  void save(const std::string& path, const MenuActions& actions, Window& self);
  void menuItem(const char* label, const std::function<void()>& action, std::function<void()>& chosen,
                const char* shortcut = nullptr);
  void noteLastItem(const std::string& label);
  bool beginMenu(const char* label);
  void writeLayout();

  // WindowPanels.cpp: the panels and their controls.
  void notePanelItem(const std::string& title, const std::string& label);
  void drawCurve(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen);
  void drawSwatches(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen);
  void drawColor(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen);
  void drawPanel(const Panel& p, float& top, std::vector<std::function<void()>>& chosen);
};

// What one frame's menus and Save as dialog chose; run after the frame is drawn (WindowMenus.cpp).
struct MenuChoice {
  std::function<void()> chosen;
  bool exitChosen = false;
  std::string saveTo;  // the Save as dialog's file name, when it was confirmed
};
// The main menu, the user menu, the animate shortcuts, Esc and the Save as dialog.
void drawMenus(Window::Impl& m, const MenuActions& actions, Window& self, MenuChoice& choice);
// setMessage()'s text over the picture's top left corner, setStatus()'s at its bottom left.
void drawMessages(Window::Impl& m);

}  // namespace lcjit::viewer
