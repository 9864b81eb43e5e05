// The window's panels (WindowImpl.h, Window.h's Panel): each open panel a Dear ImGui window down
// the right edge, its controls (sliders, toggles, choices, buttons, a table) and the editors
// drawn by hand: a curve's control points (vlab's funcedit), a grid of colours, one colour's bytes.
// Edits come back as actions run after the frame.
//
// Sections, in order (each begins with a `// ----` rule): Curves (insertion, the editor) ·
// Colours (swatches, one colour) · A panel · Panels by title.
#include <algorithm>
#include <cmath>

#include <imgui_internal.h>  // a panel's content size, to tell when its layout has settled

#include "viewer/WindowImpl.h"

namespace lcjit::viewer {
namespace {

// Where a point added at `q` goes: a function's in x order, strictly between its ends; a
// contour's into the side of its control polygon nearest the pointer (screen distance).
template <class ToScreen>
std::optional<size_t> insertionPlace(const PanelControl& c, std::array<float, 2> q, const ToScreen& toScreen,
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

}  // namespace

void Window::Impl::notePanelItem(const std::string& title, const std::string& label) {
  ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  panelRects[title + "\n" + label] = {a.x, a.y, b.x, b.y};
}

// ---------------------------------------------------------------------------------------------
// Curves

// A curve editor: the control polygon and the curve in a box fitted around them (a contour's
// with equal scales on both axes), the points as handles the left button drags.
void Window::Impl::drawCurve(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
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

// ---------------------------------------------------------------------------------------------
// Colours

// A grid of colours, 16 to a row; the selected one framed.
void Window::Impl::drawSwatches(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
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
void Window::Impl::drawColor(const Panel& p, size_t index, std::vector<std::function<void()>>& chosen) {
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

// ---------------------------------------------------------------------------------------------
// A panel

// One open panel, stacked down the right side at first (the user may move it); its edits become
// `chosen` actions, run after the frame as menu choices are.
// `top`: where the panel starts; set to where the next one may start.
void Window::Impl::drawPanel(const Panel& p, float& top, std::vector<std::function<void()>>& chosen) {
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
        std::string cells;  // the row in the layout file: its cells joined by " | "
        for (size_t k = 0; k < row.size() && k < p.columns.size(); ++k) {
          ImGui::TableSetColumnIndex(int(k));
          ImGui::TextUnformatted(row[k].c_str());
          cells += (k ? " | " : "") + row[k];
        }
        notePanelItem(p.title, cells);
      }
      ImGui::EndTable();
    }
    for (size_t b = 0; b < p.buttons.size(); ++b) {
      if (b) ImGui::SameLine();
      bool pressed = ImGui::Button(p.buttons[b].c_str());
      notePanelItem(p.title, p.buttons[b]);
      if (pressed && p.pressed) chosen.push_back([f = p.pressed, b] { f(b); });
    }
    if (!p.status.empty()) {
      ImGui::TextWrapped("%s", p.status.c_str());
      notePanelItem(p.title, p.status);
    }
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

// ---------------------------------------------------------------------------------------------
// Panels by title

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

}  // namespace lcjit::viewer
