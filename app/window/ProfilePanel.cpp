// The Profile panel's rows and status (ProfilePanel.h).
#include "app/window/ProfilePanel.h"

#include <cstdio>

namespace lcjit::app {

viewer::Panel profilePanel(const std::vector<ProfileRow>& rows, ProfiledRules whose, const std::string& finished,
                           std::function<void()> runAgain) {
  const bool lsystem = whose == ProfiledRules::LSystem;
  viewer::Panel p;
  p.title = kProfilePanelTitle;
  p.columns = {"rule", "where", "applied", "ms"};
  if (lsystem) p.columns.push_back("last step");
  constexpr size_t kShown = 40;
  for (size_t i = 0; i < rows.size() && i < kShown; ++i) {
    const ProfileRow& r = rows[i];
    char ms[32];
    std::snprintf(ms, sizeof ms, "%.3f", r.ms);
    // Cut short (the where column finds the rule).
    std::string rule = (lsystem ? r.kind.substr(0, 1) : r.kind) + " " + r.rule;
    if (rule.size() > 34) rule = rule.substr(0, 31) + "...";
    std::vector<std::string> row = {rule, r.where, std::to_string(r.applied), ms};
    if (lsystem) {
      char last[48];
      std::snprintf(last, sizeof last, "%llu (%.3f ms)", (unsigned long long)r.appliedLastStep, r.msLastStep);
      row.push_back(last);
    }
    p.rows.push_back(std::move(row));
  }
  p.status = rows.empty() ? "counting from the next run" : std::to_string(rows.size()) + " rules ran";
  if (!rows.empty() && !finished.empty()) p.status += "; finished: " + finished;
  if (rows.size() > kShown) p.status += " (the " + std::to_string(kShown) + " hottest shown)";
  p.buttons = {"Run again"};
  p.pressed = [runAgain = std::move(runAgain)](size_t) { runAgain(); };
  return p;
}

}  // namespace lcjit::app
