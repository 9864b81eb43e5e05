// The user menu (see UserMenu.h).
#include "UserMenu.h"

namespace lcjit::runtime {

UserMenu& UserMenu::instance() {
  static UserMenu menu;
  return menu;
}

void UserMenu::add(const std::string& label, int code) {
  std::lock_guard<std::mutex> lock(mutex_);
  items_.emplace_back(label, code);
}

void UserMenu::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  items_.clear();
}

std::vector<std::pair<std::string, int>> UserMenu::items() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_;
}

void UserMenu::choose(int code) {
  std::lock_guard<std::mutex> lock(mutex_);
  choice_ = code;
}

int UserMenu::choice() {
  std::lock_guard<std::mutex> lock(mutex_);
  int c = choice_;
  choice_ = -1;
  return c;
}

}  // namespace lcjit::runtime
