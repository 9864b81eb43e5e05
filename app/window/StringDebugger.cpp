// The string debugger (StringDebugger.h).
#include "app/window/StringDebugger.h"

#include "app/common/ModuleReport.h"

#include <algorithm>
#include <climits>
#include <filesystem>

#include "runtime/Engine.h"
#include "runtime/Profile.h"

namespace lcjit::app {
namespace {

using Kind = viewer::PanelControl::Kind;

viewer::PanelControl text(std::string line) {
  viewer::PanelControl c;
  c.kind = Kind::Text;
  c.label = std::move(line);
  return c;
}
viewer::PanelControl button(std::string label, bool sameLine) {
  viewer::PanelControl c;
  c.kind = Kind::Button;
  c.label = std::move(label);
  c.sameLine = sameLine;
  return c;
}


}  // namespace

void StringDebugger::select(const runtime::Engine& e, size_t offset) {
  size_t index = 0;
  for (size_t p = 0; p < offset && p < e.string().size(); p = e.modules().next(e.string().data(), p)) ++index;
  selected_ = index;
}

viewer::Panel StringDebugger::panel(runtime::Engine& e, bool busy, const Requests& requests) {
  if (busy) {
    last_.status = "deriving...";
    return last_;
  }
  e.setProvenance(true);
  viewer::Panel p;
  p.title = kTitle;
  const int step = e.stepNo(), length = e.derivationLength();
  const size_t count = e.moduleCount();
  if (selected_ && *selected_ >= count) selected_.reset();  // the string got shorter (Step back)
  p.controls.push_back(text("step " + std::to_string(step) + " of " + std::to_string(length) + ": " +
                            std::to_string(count) + " module" + (count == 1 ? "" : "s")));
  p.controls.push_back(button("Step back", false));
  p.controls.push_back(button("Step", true));
  p.controls.push_back(button("Run", true));
  // Stop when: the productions, as written.
  viewer::PanelControl stopWhen;
  stopWhen.kind = Kind::Choice;
  stopWhen.label = "stop when";
  stopWhen.options = {"(no production applies)"};
  std::vector<int> ruleOfOption = {-1};
  std::vector<runtime::RuleSource> rules = e.ruleSources();
  for (size_t i = 0; i < rules.size(); ++i) {
    if (rules[i].kind != "production") continue;
    stopWhen.options.push_back(rules[i].predecessor + " applies (" + ruleWhere(rules[i]) + ")");
    ruleOfOption.push_back(int(i));
    if (int(i) == e.breakRule()) stopWhen.value = float(stopWhen.options.size() - 1);
  }
  p.controls.push_back(stopWhen);
  viewer::PanelControl which;
  which.label = "module";
  which.value = selected_ ? float(*selected_) : 0;
  which.min = 0;
  which.max = float(count ? count - 1 : 0);
  which.step = 1;
  p.controls.push_back(which);
  if (selected_)
    for (std::string& line : describeModule(e, *selected_)) p.controls.push_back(text(std::move(line)));
  else
    p.controls.push_back(text("click a module's drawing to see it, its origin and its context"));
  p.changed = [this, &e, requests, step, ruleOfOption](size_t i, float v) {
    switch (i) {
      case 1: return requests.deriveTo(std::max(0, step - 1));
      case 2: return requests.deriveTo(step + 1);
      case 3: return requests.deriveTo(INT_MAX);
      case 4:
        if (size_t(v) < ruleOfOption.size()) e.breakOn(ruleOfOption[size_t(v)]);
        return;
      case 5: selected_ = size_t(std::max(0.0f, v)); return;
      default: return;
    }
  };
  last_ = p;
  last_.changed = nullptr;  // while deriving, nothing can be asked
  return p;
}

}  // namespace lcjit::app
