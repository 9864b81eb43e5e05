// The interactive window: a GLFW window with an OpenGL 3.3 core context, the same Renderer as
// headless rendering (one renderer, two surfaces), lpfg's view manipulation (manual §1.2.1) and
// lpfg's main menu (§1.2.2) as a Dear ImGui popup on the right button.
//
// Like Dear ImGui's backends, the window consumes data: it knows nothing of the engine or the
// model session. The caller owns the model, calls setScene() when the picture changes, frame()
// in its loop, and gets the menu's choices back through MenuActions.
//
// View manipulation restates lpfg (vlab lpfg/viewtask.cpp, glwidget.cpp, projection.cpp):
//   left drag               rotate: 0.2°/pixel about the initial up axis (horizontal motion)
//                           and the current left axis (vertical motion)
//   Shift + left drag       pan: the model follows the mouse
//   Ctrl/Alt + left drag,   zoom: moving up zooms in, ×1.01 per pixel; the scale stays within
//   middle drag, wheel      the view file's `min zoom:`/`max zoom:` (lpfg's zoom is 1/scale)
//   Shift + middle drag     roll about the view direction, 1°/pixel
//   Ctrl + middle drag      frustum (perspective only): moving up brings the eye closer
//   right button            the main menu
// Command (macOS) is GLFW's Super key; it counts as Ctrl.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Geometry.h"
#include "viewer/Headless.h"  // writeImage
#include "viewer/Renderer.h"
#include "runtime/files/ViewFile.h"

namespace lcjit::viewer {

// lpfg's window options: -w W H, -wr RW RH (fractions of the screen), -wp X Y, -wpr RX RY,
// -wnb (no border). Relative values win over absolute ones when set (> 0, resp. >= 0).
struct WindowOptions {
  int width = 800, height = 800;
  std::optional<std::pair<int, int>> position;
  float relW = 0, relH = 0, relX = -1, relY = -1;
  bool borderless = false;
  std::string title = "lcjit";
  bool vsync = true;    // glfwSwapInterval(1); benchmarks turn it off
  bool visible = true;  // tests may create a hidden window (it still draws)
  // A flat picture (a Context Free design): the left button pans, as a 2D view's does, and
  // nothing turns the picture out of its plane.
  bool flat = false;
};

// A panel beside the view (the Parameters panel, the profiler): data the caller owns and rebuilds
// as it likes, drawn in a side window of its own that the main menu's Panels submenu opens and
// closes. Edits come back through `changed` and `pressed`, called after the frame, like menu items.
struct PanelControl {
  enum class Kind {
    Slider,  // min < max: a slider (vlab's); min == max: a field dragged by 1/100 of its value
    Toggle,  // a check box; toggles with the same group >= 0 are exclusive (vlab's button groups)
    Text,    // a line of text (vlab's labels)
    Choice,  // one of `options`; value: the chosen one's index
    Button,  // a button on a line of its own (value: unused); pressing it reports its value
    // Control points to drag (vlab's funcedit, cuspy): `points`, the `curve` through them drawn
    // under them. A moved point comes back through Panel::edited (item: the point, value: x, y);
    // as in funcedit, Ctrl+click adds a point (Panel::added), Shift+Ctrl+click on one removes it
    // (Panel::removed).
    Curve,
    // A grid of `colors` (vlab's palette, medit); a click selects one: `changed(control, index)`.
    // `value` is the selected index.
    Swatches,
    // One colour, colors[0], with sliders for its red, green and blue bytes (0..255);
    // Panel::edited gets the new colour (item 0).
    Color,
  } kind = Kind::Slider;
  std::vector<std::string> options;
  std::string label;  // unique within its panel
  float value = 0, min = 0, max = 0;
  float step = 0;     // a slider snaps to multiples of it (vlab's whole steps over a scale); 0: none
  int group = -1;
  bool sameLine = false;  // drawn right of the control before it
  std::string tooltip;  // where the value lives (file, #define), shown on hover
  // Curve: the control points and the curve (a polyline) in the curve's own coordinates.
  std::vector<std::array<float, 2>> points, curve;
  bool closed = false;    // Curve: the control polygon closes (a closed contour)
  bool function = false;  // Curve: a function's points: the ends stay at x = 0 and x = 1, and x
                          // never decreases from one point to the next (funcedit's rules)
  std::vector<std::array<float, 4>> colors;  // Swatches, Color: RGBA in 0..1
};
struct Panel {
  std::string title;  // unique; the Panels submenu's item
  std::vector<PanelControl> controls;
  // A table under the controls (the profiler): its column titles and rows of cells.
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> buttons;  // a row of buttons at the bottom ("Save values")
  std::string status;                // a line under them (what Save did, an error)
  std::function<void(size_t control, float value)> changed;
  std::function<void(size_t button)> pressed;
  // A Curve's point moved ({x, y, 0, 0}) or a Color changed (RGBA).
  std::function<void(size_t control, size_t item, std::array<float, 4> value)> edited;
  // A Curve's point added before index `at` (a function's in x order, a contour's on the nearest
  // side of its polygon), or removed (never a function's first or last).
  std::function<void(size_t control, size_t at, std::array<float, 2> point)> added;
  std::function<void(size_t control, size_t index)> removed;
};

// The main menu's actions. An empty function greys its item out.
struct MenuActions {
  std::function<void()> newModel, newLsystem, newRun, newView, newRendering, exit;
  // Save as… with a name whose extension is not an image's (.png .jpg .jpeg .bmp): the caller
  // writes it (.obj, .ps, .strb, …). Image names are written by the window itself.
  std::function<void(const std::string& path)> saveAs;
  // "Save": this file name (lpfg: the L-system's name with .png). Empty: Save is greyed out.
  // Also the Save as… dialog's initial text.
  std::string saveName;
  // String > Input / Output: the binary string (lpfg: the L-system's name with .strb).
  std::function<void()> stringInput, stringOutput;
  // Animate (§1.2.3): `animating` shows the animate menu instead of "Animate"; its shortcuts are
  // Ctrl+F Step, Ctrl+R Run, Ctrl+V Forever, Ctrl+S Stop, Ctrl+W Rewind (lpfg's Cmd keys).
  bool animating = false;
  std::function<void()> animate, step, run, forever, stop, rewind, clear, newAnimate, startRecording, dontAnimate;
  // Refresh mode: false explicit, true triggered/continuous (lpfg offers the two). Empty
  // setRefreshMode: not offered.
  bool monitoring = false;
  std::function<void(bool)> setRefreshMode;
  // The user menu (§6.8: UserMenuItem): shown on a right click with two of Ctrl/Shift/Alt held;
  // a choice calls userChoice with the item's code.
  std::vector<std::pair<std::string, int>> userMenu;
  std::function<void(int code)> userChoice;
  // A design's next variation (Context Free's Next Variation), Ctrl+N; empty: not offered (an
  // L-system has none).
  std::function<void()> nextVariation;
  // The Rules menu: the model's production groups applied by name (XL's rule methods, as
  // GroIMP's buttons): a choice calls applyGroup with its group (empty: greyed out, the model
  // busy). No groups: no menu.
  std::vector<std::pair<std::string, int>> namedGroups;
  std::function<void(int group)> applyGroup;
  // Esc (outside the Save as… dialog): interrupt the model code running now (docs/faults.md).
  std::function<void()> interrupt;
  // The panels the Panels submenu offers (none: no submenu).
  std::vector<Panel> panels;
};

// Mouse buttons, actions and modifier bits are GLFW's (GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS,
// GLFW_MOD_SHIFT…): the inject* functions are what the GLFW callbacks call.
class Window {
 public:
  static llvm::Expected<std::unique_ptr<Window>> create(const WindowOptions& options = {});
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // How a new picture is framed: Refit frames its own bounding box (a new model, New view);
  // Keep keeps the previous framing (animation frames, lpfg's default); HCenter keeps it but
  // centres the new picture horizontally (`hcenter between frames: on`).
  enum class Framing { Refit, Keep, HCenter };
  // Uploads a new picture. The user's rotation/zoom/pan are kept unless resetView() is called.
  void setScene(const runtime::Geometry& geometry, const runtime::ViewSettings& view, const RenderPalette& palette,
                const std::vector<runtime::Image>& textures, Framing framing = Framing::Refit);
  // Several views in one window, separated by the view file's `window border:`.
  void setViews(const std::vector<ViewPane>& panes, const runtime::ViewSettings& view, const RenderPalette& palette,
                const std::vector<runtime::Image>& textures);
  // Back to the view file's framing (New model, New view).
  void resetView();
  // Text shown over the picture until replaced; "" removes it. For problems the user must see
  // while the last good model stays on screen: a broken edit's diagnostics, a fault.
  void setMessage(std::string text);
  const std::string& message() const;
  // A line at the picture's bottom left until replaced; "" removes it. For how far a long
  // derivation has come ("step 40 of 200: 1 204 311 modules"). Listed in the layout as "status".
  void setStatus(std::string text);

  // Polls events, handles the mouse and the menu, draws once and swaps. False when the window
  // should close (its close button, or Exit).
  bool frame(const MenuActions& actions);
  // Sleeps until an input event arrives or `seconds` pass: an idle window costs no CPU. Returns
  // at once while input waits for the menus (one key change per frame: a tap is never lost).
  void waitEvents(double seconds);
  // From any thread: makes a waitEvents() in progress return now (the REPL's input arrived).
  static void wake();

  // The picture the window shows (without the menu), at the framebuffer's size.
  llvm::Expected<runtime::Image> grabImage();
  // grabImage() to .png / .jpg / .jpeg / .bmp.
  llvm::Error saveImage(const std::string& path);

  std::pair<int, int> framebufferSize() const;
  std::pair<int, int> windowSize() const;
  // The camera the last frame() (or grabImage()) used.
  const runtime::CameraMatrices& camera() const;
  // The current interactive adjustment (rotation, zoom, pan; frustum factor separately).
  const runtime::ViewAdjustment& adjustment() const;
  float frustumFactor() const;
  // Renderer statistics and error of the last draw; GL_RENDERER.
  const Renderer& renderer() const;
  std::string glRenderer() const;

  // Input, in window coordinates (pixels from the top left), as GLFW reports it.
  void injectCursor(double x, double y);
  void injectMouseButton(int button, int action, int mods);
  void injectScroll(double dx, double dy);
  void injectKey(int key, int action, int mods);
  void injectChar(unsigned codepoint);

  // The pointer as lpfg's GetMouseStatus() reports it (§7.4): pixel position, the cursor ray's
  // points on the front and back clipping planes and halfway, and the left button — counted only
  // while one of the mouse-insertion key combinations is held (Shift+Ctrl, Alt+Ctrl, Shift+Alt,
  // or the 1/2/3 keys). Pushed/released latch until takePointer() returns them.
  struct Pointer {
    int x = 0, y = 0;
    float fbX = 0, fbY = 0;  // the same in framebuffer pixels (what CameraMatrices measure)
    double front[3] = {0, 0, 0}, rear[3] = {0, 0, 0}, middle[3] = {0, 0, 0};
    bool down = false, pushed = false, released = false;
    // The module a push asks to insert (§7.4's table): 1 MouseIns (Shift+Ctrl, Shift+Alt+Ctrl or
    // the 1 key), 2 MouseInsPos (Alt+Ctrl or 2), 0 none (Shift+Alt or 3).
    int insert = 0;
    // A plain left click on the picture (no key held, released within 3 px of the press; a drag
    // rotates instead), latched like pushed: where, in framebuffer pixels.
    bool clicked = false;
    float clickFbX = 0, clickFbY = 0;
  };
  Pointer takePointer();

  // Menu introspection (tests, scripting): whether the main menu / Save as dialog is open, and
  // where the last frame drew the menu item with this label (x0, y0, x1, y1 window coordinates).
  bool menuOpen() const;
  bool userMenuOpen() const;
  bool saveDialogOpen() const;
  std::optional<std::array<float, 4>> menuItemRect(const std::string& label) const;
  // Panels by title: open or close one (the Panels submenu does the same), whether it is open.
  void showPanel(const std::string& title, bool open);
  bool panelOpen(const std::string& title) const;
  // Where the last frame drew a panel's control or button (its label); nothing if not drawn. A
  // Curve's point i is "label#i", a Swatches' colour i too; a Color's sliders "label R" (G, B).
  std::optional<std::array<float, 4>> panelItemRect(const std::string& title, const std::string& label) const;
  // Where the last frame drew setMessage()'s text; nothing when there is none.
  std::optional<std::array<float, 4>> messageRect() const;
  // The last Save/Save as… error (empty if none).
  const std::string& lastSaveError() const;

  struct Impl;

 private:
  explicit Window(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace lcjit::viewer
