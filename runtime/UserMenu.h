// The user menu of manual §6.8: items model code adds (UserMenuItem), the window shows (two of
// Ctrl/Shift/Alt + right click) and the choice model code reads back (UserMenuChoice). Model code
// runs on the derivation thread and the window on the main thread, hence the lock.
#pragma once
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::runtime {

class UserMenu {
 public:
  static UserMenu& instance();

  void add(const std::string& label, int code);
  void clear();
  std::vector<std::pair<std::string, int>> items() const;
  // The window records a selection; choice() returns the last one since the previous call, or
  // -1 if there was none.
  void choose(int code);
  int choice();

 private:
  mutable std::mutex mutex_;
  std::vector<std::pair<std::string, int>> items_;
  int choice_ = -1;
};

}  // namespace lcjit::runtime
