// The window's menus and the texts over the picture (WindowImpl.h): lpfg's main menu (§1.2.2,
// with the animate menu of §1.2.3) and the user menu (§6.8) as Dear ImGui popups, the animate
// shortcuts and Esc, the Save as dialog and Save itself, setMessage()'s and setStatus()'s texts,
// and the layout file that tells scripts where each item is drawn.
//
// Sections, in order (each begins with a `// ----` rule): Menu items and Save · The layout file ·
// The menus and the Save as dialog (drawMenus) · The messages (drawMessages) · Menu introspection.
#include <cstdio>
#include <cstdlib>

#include "support/ReplacingFile.h"
#include "viewer/WindowImpl.h"

namespace lcjit::viewer {
namespace {

const char* kMenuId = "lcjit main menu";
const char* kUserMenuId = "lcjit user menu";
const char* kSaveId = "Save as";

}  // namespace

// ---------------------------------------------------------------------------------------------
// Menu items and Save

void Window::Impl::save(const std::string& path, const MenuActions& actions, Window& self) {
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

void Window::Impl::menuItem(const char* label, const std::function<void()>& action,
                            std::function<void()>& chosen, const char* shortcut) {
  if (ImGui::MenuItem(label, shortcut, false, bool(action))) chosen = action;
  noteLastItem(label);
  if (action) greyedItems.erase(label);
  else greyedItems.insert(label);
}

void Window::Impl::noteLastItem(const std::string& label) {
  ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  itemRects[label] = {a.x, a.y, b.x, b.y};
}

// ImGui::BeginMenu, noting where its label is (once open, ImGui's last item is the submenu's
// window, so the place is taken before).
bool Window::Impl::beginMenu(const char* label) {
  ImVec2 at = ImGui::GetCursorScreenPos();
  float w = ImGui::GetContentRegionAvail().x, h = ImGui::GetFrameHeight();
  bool open = ImGui::BeginMenu(label);
  itemRects[label] = {at.x, at.y, at.x + w, at.y + h};
  if (open && ImGui::IsWindowAppearing()) layoutSettling = 3;  // the submenu places itself first
  return open;
}

// ---------------------------------------------------------------------------------------------
// The layout file

// LCJIT_WINDOW_LAYOUT=FILE: where the menu's items and the panels' controls are, one per line
// ("LABEL<tab>x0 y0 x1 y1", a panel's as "TITLE/LABEL", a row of its table as "TITLE/CELL | CELL …"
// and its status line as "TITLE/TEXT"; setMessage's text as "message/FIRST LINE",
// setStatus's as "status/TEXT"; a menu item greyed out has a third field, "greyed", so that a
// script waits for it to be usable instead of clicking it for nothing), rewritten when it changes. Scripts that
// drive the window from outside (xdotool, tests/interactive) click what they name, not a guess.
void Window::Impl::writeLayout() {
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
  llvm::consumeError(support::writeWholeFile(path, text));  // a test's aid: nothing to say if it fails
}

// ---------------------------------------------------------------------------------------------
// The menus and the Save as dialog

void drawMenus(Window::Impl& m, const MenuActions& actions, Window& self, MenuChoice& choice) {
  ImGuiIO& io = ImGui::GetIO();
  std::function<void()>& chosen = choice.chosen;
  bool& exitChosen = choice.exitChosen;
  std::string& saveTo = choice.saveTo;
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
    if (actions.nextVariation) m.menuItem("Next variation", actions.nextVariation, chosen, "Ctrl+N");
    ImGui::Separator();
    std::function<void()> save, saveAs, exit;
    const std::string saveName = actions.saveName;
    if (!saveName.empty() && (isImageFileName(saveName) || actions.saveAs))
      save = [&m, &actions, saveName, &self] { m.save(saveName, actions, self); };
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
    if (!actions.namedGroups.empty() && m.beginMenu("Rules")) {
      for (const auto& [name, group] : actions.namedGroups) {
        std::function<void()> apply;
        if (actions.applyGroup) apply = [&actions, group = group] { actions.applyGroup(group); };
        m.menuItem(name.c_str(), apply, chosen);
      }
      ImGui::EndMenu();
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
  if (m.shortcut == GLFW_KEY_N && actions.nextVariation && !m.saveIsOpen) chosen = actions.nextVariation;
  m.shortcut = 0;
  if (m.escape && !m.saveIsOpen && !chosen && actions.interrupt) chosen = actions.interrupt;
  m.escape = false;

  if (m.openSave) {
    ImGui::OpenPopup(kSaveId);
    m.openSave = false;
    m.focusSaveField = true;
  }
  m.saveIsOpen = false;
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
}

// ---------------------------------------------------------------------------------------------
// The messages

void drawMessages(Window::Impl& m) {
  ImGuiIO& io = ImGui::GetIO();
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
}

// ---------------------------------------------------------------------------------------------
// Menu introspection

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
