// The window's input and camera (WindowImpl.h): lpfg's framing with the user's adjustment, the
// view tasks a drag applies (viewtask.cpp, projection.cpp), the mouse and keys as GLFW or a test
// reports them (Window::inject*), the queue that hands them to Dear ImGui one change a frame, and
// the pointer as model code reads it (takePointer).
//
// Sections, in order (each begins with a `// ----` rule): The camera · lpfg's view tasks ·
// Mouse and keys (onCursor, onButton, onScroll, feedImGui, inject*, waitEvents) · The pointer
// (takePointer: the cursor ray, mouse insertion).
#include <algorithm>
#include <cmath>

#include <backends/imgui_impl_glfw.h>
#include <glm/gtc/matrix_transform.hpp>

#include "viewer/WindowImpl.h"

namespace lcjit::viewer {

// ---------------------------------------------------------------------------------------------
// The camera

runtime::CameraMatrices Window::Impl::frame(const runtime::ViewAdjustment& a, float frustumFactor) const {
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

void Window::Impl::selectPaneAt(double x, double y) {
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

// ---------------------------------------------------------------------------------------------
// lpfg's view tasks (projection.cpp), deltas in lpfg's signs

// RotateBy(0.1·dx, −0.1·dy) on half angles, applied as q⁻¹·v·q: the view turns by −0.2·dx°
// about the initial up axis and by +0.2·dy° about the current left (= screen right) axis.
void Window::Impl::rotateBy(double dx, double dy) {
  const runtime::CameraMatrices base = frame({}, 1);
  const glm::vec3 upAxis = base.up;
  const glm::vec3 left = glm::normalize(glm::cross(camera.viewDirection, camera.up));
  glm::mat4 step = glm::rotate(glm::mat4(1), glm::radians(float(-0.2 * dx)), upAxis) *
                   glm::rotate(glm::mat4(1), glm::radians(float(0.2 * dy)), left);
  adjust.rotation = step * adjust.rotation;
  updateCamera();
}

// RollBy(0.5·(lastX − x)): −(lastX − x)° about the view direction.
void Window::Impl::rollBy(double dxLpfg) {
  adjust.rotation = glm::rotate(glm::mat4(1), glm::radians(float(-dxLpfg)), camera.viewDirection) * adjust.rotation;
  updateCamera();
}

// ZoomBy(dy), dy = y − lastY: lpfg's scale ×1.01^dy, clamped to [min zoom, max zoom].
void Window::Impl::zoomBy(double dy) {
  const float base = runtime::projectionScale(view, 0);  // the zoom limits apply to it
  const float lo = std::min(view.minZoom, view.maxZoom), hi = std::max(view.minZoom, view.maxZoom);
  float scale = base / adjust.zoom * std::pow(1.01f, float(dy));
  scale = std::clamp(scale, lo, hi);
  adjust.zoom = base / scale;
  updateCamera();
}

// FrustumBy(dy): the near distance ×1.01^dy (perspective only).
void Window::Impl::frustumBy(double dy) {
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
void Window::Impl::panBy(double dx, double dy) {
  // In a multi-view window the pan follows the pointer in the pane being dragged.
  const runtime::CameraMatrices cam = panes.empty() ? camera : paneCamera(activePane, adjust, layoutPanes()[activePane]);
  const glm::vec3 left = glm::normalize(glm::cross(cam.viewDirection, cam.up));
  const float upp = cam.unitsPerPixel * pixelRatio();
  adjust.pan -= upp * (float(dy) * cam.up + float(dx) * left);
  updateCamera();
}

// ---------------------------------------------------------------------------------------------
// Mouse and keys

void Window::Impl::onCursor(double x, double y) {
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

void Window::Impl::onButton(int button, int action, int mods) {
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
    else if (shift || flat) task = Task::Pan;
    else if (ctrl || alt) task = Task::Zoom;
    else task = Task::Rotate;
  } else {  // middle: GLWidget::MBDown
    if (ctrl) task = camera.perspective ? Task::Frustum : Task::Idle;
    else if (shift) task = Task::Roll;
    else task = Task::Zoom;
  }
}

void Window::Impl::onScroll(double, double dy) {
  if (uiHasMouse()) return;
  zoomBy(-10.0 * dy);  // a wheel notch up: 10 pixels of upward zoom drag
}

void Window::Impl::feedImGui() {
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

// ---------------------------------------------------------------------------------------------
// The pointer

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

}  // namespace lcjit::viewer
