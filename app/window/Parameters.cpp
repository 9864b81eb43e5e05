// The Parameters panel (Parameters.h).
#include "app/window/Parameters.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/session/Session.h"
#include "runtime/Functions.h"
#include "support/ReplacingFile.h"
#include "runtime/files/TextLines.h"
#include "runtime/WindowInput.h"

namespace lcjit::app {
namespace {

llvm::Expected<std::string> readAll(const std::string& path) {
  auto buf = runtime::textfile::readFile(path);
  if (!buf) return buf.takeError();
  return (*buf)->getBuffer().str();
}

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

}  // namespace

void ParameterPanel::load(const ModelFiles& files, const runtime::FunctionStore& functions) {
  controls_.clear();
  status_.clear();
  vsetPath_ = files.parameters;
  std::map<std::string, size_t> byParameter;
  for (int id = 1; id <= functions.size(); ++id) {
    if (!functions.isParameter(id)) continue;
    Control c;
    c.parameter = std::string(functions.nameOf(id));
    c.shown.label = c.parameter;
    c.shown.value = functions.val(id);
    if (auto kept = unsaved_.find(c.parameter); kept != unsaved_.end())
      c.shown.value = pendingParameters_[c.parameter] = kept->second;  // the reload read the file's
    c.shown.tooltip = "#define " + c.parameter + " in " + files.parameters;
    byParameter[c.parameter] = controls_.size();
    controls_.push_back(std::move(c));
  }
  tsetPath_ = files.timeline;
  for (const runtime::FunctionStore::TimelineRange& t : functions.timelines()) {
    std::pair<float, float> range{t.start, t.end};
    if (auto kept = unsavedTimelines_.find(t.name); kept != unsavedTimelines_.end())
      range = pendingTimelines_[t.name] = kept->second;
    for (bool end : {false, true}) {
      Control c;
      c.timeline = t.name;
      c.end = end;
      c.shown.label = t.name + (end ? " end" : " start");
      c.shown.value = end ? range.second : range.first;
      c.shown.tooltip = "the timeline " + t.name + " in " + files.timeline + " (tfunc maps its range onto 0..1)";
      controls_.push_back(std::move(c));
    }
  }
  std::string dir = std::filesystem::path(files.lsystem).parent_path().string();
  int groupBase = 0;
  for (const runtime::PanelAndTarget& found : runtime::findPanels(dir)) {
    auto text = readAll(found.panel);
    llvm::Expected<runtime::PanelFile> panel =
        text ? runtime::parsePanel(*text, found.panel) : llvm::Expected<runtime::PanelFile>(text.takeError());
    if (!panel) {
      status_ += llvm::toString(panel.takeError()) + "\n";
      continue;
    }
    auto target = readAll(found.target);
    std::string targetText = target ? *target : (llvm::consumeError(target.takeError()), std::string());
    const bool targetIsVset = !vsetPath_.empty() && samePath(found.target, vsetPath_);
    int groups = 0;
    for (const runtime::PanelItem& item : panel->items) {
      using Kind = runtime::PanelItem::Kind;
      if (item.kind == Kind::Menu || item.kind == Kind::Page) continue;
      Control c;
      c.target = found.target;
      c.message = item.message;
      c.shown.label = item.name;
      c.shown.tooltip = item.message.empty() ? "" : "'" + item.message + "' to " + found.target;
      std::optional<runtime::AwkpedEdit> asDefine = runtime::awkpedEdit(item.message, 1);
      const bool define = asDefine && asDefine->kind == runtime::AwkpedEdit::Kind::Define;
      if (item.kind == Kind::Label) {
        c.shown.kind = viewer::PanelControl::Kind::Text;
      } else if (item.kind == Kind::Button) {
        c.shown.kind = viewer::PanelControl::Kind::Toggle;
        if (item.group >= 0) c.shown.group = groupBase + item.group, groups = std::max(groups, item.group + 1);
        // On when the file holds the value the button writes (vlab starts from the panel's own).
        std::optional<double> now = define ? runtime::definedValue(targetText, asDefine->name) : std::nullopt;
        c.shown.value = now ? float(*now == asDefine->value) : float(item.value == 1);
      } else {
        // A slider writes %d/SCALE: shown in the file's units, moving in steps of 1/SCALE.
        if (define && asDefine->value != 0) c.scale = float(1.0 / asDefine->value);
        c.shown.min = item.min / c.scale;
        c.shown.max = item.max / c.scale;
        c.shown.step = 1 / c.scale;
        std::optional<double> now = define ? runtime::definedValue(targetText, asDefine->name) : std::nullopt;
        c.shown.value = now ? float(*now) : item.value / c.scale;
        // A .vset value a panel drives is one control: the panel gives it its range.
        if (targetIsVset && define) {
          if (auto p = byParameter.find(asDefine->name); p != byParameter.end()) {
            Control& v = controls_[p->second];
            v.shown.min = c.shown.min, v.shown.max = c.shown.max, v.shown.step = c.shown.step;
            v.shown.label = item.name == v.parameter ? item.name : item.name + " (" + v.parameter + ")";
            continue;
          }
        }
      }
      controls_.push_back(std::move(c));
    }
    groupBase += groups;
  }
  // Labels must be unique within the panel: a repeated one gets an invisible suffix (ImGui's ##).
  std::map<std::string, int> seen;
  for (Control& c : controls_)
    if (int n = seen[c.shown.label]++; n > 0) c.shown.label += "##" + std::to_string(n);
}

bool ParameterPanel::empty() const { return controls_.empty() && tunables_.entries().empty(); }

viewer::Panel ParameterPanel::panel() {
  viewer::Panel p;
  p.title = kTitle;
  for (const Control& c : controls_) p.controls.push_back(c.shown);
  // The model's tunable values, as its last run met them.
  tunablesShown_.clear();
  for (const runtime::Tunables::Entry& t : tunables_.entries()) {
    viewer::PanelControl c;
    c.label = t.name + "##tunable";
    c.value = t.moved ? t.movedTo : std::clamp(t.value, t.min, t.max);
    if (auto pending = pendingTunables_.find(t.name); pending != pendingTunables_.end()) c.value = pending->second;
    c.min = t.min, c.max = t.max;
    c.tooltip = "tunable(\"" + t.name + "\", ...) in the model: " + (t.moved ? "moved here" : "the code's value");
    p.controls.push_back(c);
    tunablesShown_.push_back(t.name);
  }
  if (!vsetPath_.empty() || !tsetPath_.empty()) p.buttons = {"Save values"};
  p.status = status_;
  p.changed = [this](size_t i, float v) { changed(i, v); };
  p.pressed = [this](size_t) {
    if (auto e = saveParameters()) status_ = llvm::toString(std::move(e));
  };
  return p;
}

void ParameterPanel::changed(size_t index, float value) {
  if (index >= controls_.size()) {
    if (index - controls_.size() < tunablesShown_.size()) pendingTunables_[tunablesShown_[index - controls_.size()]] = value;
    return;
  }
  Control& c = controls_[index];
  if (!c.parameter.empty()) {
    c.shown.value = value;
    pendingParameters_[c.parameter] = unsaved_[c.parameter] = value;
    return;
  }
  if (!c.timeline.empty()) {
    c.shown.value = value;
    std::pair<float, float> range;
    for (const Control& o : controls_)
      if (o.timeline == c.timeline) (o.end ? range.second : range.first) = o.shown.value;
    pendingTimelines_[c.timeline] = unsavedTimelines_[c.timeline] = range;
    return;
  }
  if (c.shown.kind == viewer::PanelControl::Kind::Toggle) {
    // A group's button turns the others off; each writes its own message with %d = 1 when on.
    if (c.shown.group >= 0)
      for (Control& other : controls_)
        if (other.shown.group == c.shown.group) other.shown.value = 0;
    c.shown.value = value;
    edit(c, int(value));
    return;
  }
  c.shown.value = value;
  edit(c, int(std::lround(value * c.scale)));
}

void ParameterPanel::edit(const Control& c, int shown) {
  std::optional<runtime::AwkpedEdit> e = runtime::awkpedEdit(c.message, shown);
  if (!e) {
    status_ = "'" + c.message + "' is not a message lcjit can apply (awkped's d or n)";
    return;
  }
  auto text = readAll(c.target);
  if (!text) {
    status_ = llvm::toString(text.takeError());
    return;
  }
  auto edited = runtime::applyAwkped(*text, *e, c.target);
  if (!edited) {
    status_ = llvm::toString(edited.takeError());
    return;
  }
  if (*edited == *text) return;
  if (auto err = support::writeWholeFile(c.target, *edited)) {
    status_ = llvm::toString(std::move(err));
    return;
  }
  status_.clear();
  if (std::find(changedFiles_.begin(), changedFiles_.end(), c.target) == changedFiles_.end())
    changedFiles_.push_back(c.target);
}

std::map<std::string, float> ParameterPanel::takeParameters() { return std::exchange(pendingParameters_, {}); }
std::vector<std::string> ParameterPanel::takeChangedFiles() { return std::exchange(changedFiles_, {}); }
std::map<std::string, float> ParameterPanel::takeTunables() { return std::exchange(pendingTunables_, {}); }
std::map<std::string, std::pair<float, float>> ParameterPanel::takeTimelines() {
  return std::exchange(pendingTimelines_, {});
}

llvm::Error ParameterPanel::saveParameters() {
  if (vsetPath_.empty() && tsetPath_.empty()) return llvm::createStringError("the model has no .vset or .tset file");
  int saved = 0;
  std::vector<std::string> written;
  // One file: its text with every value of its kind set, written if anything changed.
  auto save = [&](const std::string& path, auto setAll) -> llvm::Error {
    if (path.empty()) return llvm::Error::success();
    auto text = readAll(path);
    if (!text) return text.takeError();
    std::string out = *text;
    if (auto e = setAll(out)) return e;
    if (out != *text)
      if (auto e = support::writeWholeFile(path, out)) return e;
    written.push_back(path);
    return llvm::Error::success();
  };
  if (auto e = save(vsetPath_, [&](std::string& out) -> llvm::Error {
        for (const Control& c : controls_) {
          if (c.parameter.empty()) continue;
          runtime::AwkpedEdit edit;
          edit.name = c.parameter;
          edit.value = c.shown.value;
          auto edited = runtime::applyAwkped(out, edit, vsetPath_);
          if (!edited) return edited.takeError();
          out = std::move(*edited);
          ++saved;
        }
        return llvm::Error::success();
      }))
    return e;
  if (auto e = save(tsetPath_, [&](std::string& out) -> llvm::Error {
        for (const Control& c : controls_) {
          if (c.timeline.empty() || c.end) continue;
          float end = c.shown.value;
          for (const Control& o : controls_)
            if (o.timeline == c.timeline && o.end) end = o.shown.value;
          auto edited = runtime::timelineText(out, c.timeline, c.shown.value, end, tsetPath_);
          if (!edited) return edited.takeError();
          out = std::move(*edited);
          saved += 2;
        }
        return llvm::Error::success();
      }))
    return e;
  unsaved_.clear();
  unsavedTimelines_.clear();
  status_ = "saved " + std::to_string(saved) + " value" + (saved == 1 ? "" : "s") + " to ";
  for (size_t i = 0; i < written.size(); ++i) status_ += (i ? " and " : "") + written[i];
  return llvm::Error::success();
}

}  // namespace lcjit::app
