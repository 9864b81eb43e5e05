// vlab's panel files and awkped's edits (PanelFile.h).
#include "runtime/files/PanelFile.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "runtime/files/TextLines.h"

namespace lcjit::runtime {
namespace {

using textfile::splitLines;
using textfile::trim;
using textfile::words;

std::optional<double> number(std::string_view w) {
  std::string s(w);
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

// Where word `index` (0-based) of `line` starts and ends, as awk splits it (blanks and tabs).
std::optional<std::pair<size_t, size_t>> wordSpan(std::string_view line, size_t index) {
  size_t i = 0, k = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i == line.size()) break;
    size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (k++ == index) return std::make_pair(b, i);
  }
  return std::nullopt;
}

std::string readText(const std::filesystem::path& p) {
  auto buffer = support::readInputFile(p.string());
  return buffer ? (*buffer)->getBuffer().str() : std::string();
}

}  // namespace

std::string awkNumber(double v) {
  if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 1e15) {
    char b[32];
    std::snprintf(b, sizeof b, "%.0f", v);
    return std::string(b) == "-0" ? "0" : b;
  }
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::optional<AwkpedEdit> awkpedEdit(std::string_view message, int shown) {
  std::string text(message);
  for (size_t at; (at = text.find("%d")) != std::string::npos;) text.replace(at, 2, std::to_string(shown));
  std::vector<std::string_view> w = words(text);
  AwkpedEdit e;
  if (w.size() >= 3 && w[0] == "d") {
    auto value = number(w[2]);
    auto scale = w.size() >= 4 ? number(w[3]) : std::optional<double>(1.0);
    if (!value || !scale || *scale == 0) return std::nullopt;
    e.kind = AwkpedEdit::Kind::Define;
    e.name = std::string(w[1]);
    e.value = *value / *scale;
    return e;
  }
  if (w.size() >= 5 && w[0] == "n") {
    auto line = number(w[1]), word = number(w[2]), exp = number(w[3]), value = number(w[4]);
    if (!line || !word || !exp || !value || *line < 1 || *word < 1) return std::nullopt;
    e.kind = AwkpedEdit::Kind::LineWord;
    e.line = int(*line);
    e.word = int(*word);
    e.value = *value * std::pow(10.0, *exp);
    return e;
  }
  return std::nullopt;
}

llvm::Expected<std::string> applyAwkped(std::string_view text, const AwkpedEdit& edit, const std::string& file) {
  std::string out(text);
  const std::string value = awkNumber(edit.value);
  // Line starts in `out`, found again after each change (a change alters the lengths).
  size_t lineNo = 0, start = 0;
  bool changed = false;
  while (start < out.size()) {
    ++lineNo;
    size_t nl = out.find('\n', start);
    size_t end = nl == std::string::npos ? out.size() : nl;
    std::string_view line(out.data() + start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (edit.kind == AwkpedEdit::Kind::Define) {
      auto w0 = wordSpan(line, 0), w1 = wordSpan(line, 1), w2 = wordSpan(line, 2);
      // awkped's test: the first word is "#define", the second the name; every such line changes.
      if (w0 && w1 && w2 && line.substr(w0->first, w0->second - w0->first) == "#define" &&
          line.substr(w1->first, w1->second - w1->first) == edit.name) {
        out.replace(start + w2->first, w2->second - w2->first, value);
        changed = true;
        end = out.find('\n', start);
        if (end == std::string::npos) end = out.size();
      }
    } else if (int(lineNo) == edit.line) {
      auto w = wordSpan(line, size_t(edit.word - 1));
      if (!w)
        return textfile::fail(file, lineNo, "a panel sets word " + std::to_string(edit.word) +
                                                " of this line, which has fewer words");
      // awkped keeps a comma that ended the word ("1.5," stays a list item).
      std::string_view old = line.substr(w->first, w->second - w->first);
      std::string put = value + (old.size() > 1 && old.back() == ',' ? "," : "");
      out.replace(start + w->first, w->second - w->first, put);
      return out;
    }
    if (end >= out.size()) break;
    start = end + 1;
  }
  if (edit.kind == AwkpedEdit::Kind::LineWord)
    return textfile::fail(file, 0, "a panel sets line " + std::to_string(edit.line) + ", past the file's end");
  if (!changed) return textfile::fail(file, 0, "a panel sets '#define " + edit.name + "', which the file does not have");
  return out;
}

std::optional<double> definedValue(std::string_view text, std::string_view name) {
  std::optional<double> found;
  for (std::string_view line : splitLines(text)) {
    std::vector<std::string_view> w = words(line);
    if (w.size() >= 3 && w[0] == "#define" && w[1] == name)
      if (auto v = number(w[2])) found = v;
  }
  return found;
}

llvm::Expected<PanelFile> parsePanel(std::string_view text, const std::string& file) {
  PanelFile panel;
  std::vector<std::string_view> lines = splitLines(text);
  PanelItem* item = nullptr;
  bool inGroup = false;
  int groups = 0;
  std::vector<std::string> groupNames;
  auto closeGroup = [&] {
    if (!inGroup) return;
    for (PanelItem& b : panel.items)
      if (b.kind == PanelItem::Kind::Button && std::find(groupNames.begin(), groupNames.end(), b.name) != groupNames.end())
        b.group = groups;
    ++groups;
    groupNames.clear();
    inGroup = false;
  };
  for (size_t n = 0; n < lines.size(); ++n) {
    std::string_view line = trim(lines[n]);
    if (line.empty()) {
      closeGroup();
      continue;
    }
    size_t colon = line.find(':');
    if (inGroup && (colon == std::string_view::npos || line == "ENDGROUP")) {
      if (line == "ENDGROUP") closeGroup();
      else groupNames.emplace_back(line);
      continue;
    }
    if (colon == std::string_view::npos) {
      if (n == 0 || line == "ENDGROUP") continue;  // L-studio's "pver 1 1" header line
      return textfile::fail(file, n + 1, "expected 'heading: value', found '" + std::string(line) + "'");
    }
    std::string key(trim(line.substr(0, colon)));
    std::string_view value = trim(line.substr(colon + 1));
    if (key == "type") {
      closeGroup();
      item = nullptr;
      if (value == "GROUP") {
        inGroup = true;
        continue;
      }
      PanelItem it;
      if (value == "SLIDER") it.kind = PanelItem::Kind::Slider;
      else if (value == "BUTTON") it.kind = PanelItem::Kind::Button;
      else if (value == "LABEL") it.kind = PanelItem::Kind::Label;
      else if (value == "MENU") it.kind = PanelItem::Kind::Menu;
      else if (value == "PAGE") it.kind = PanelItem::Kind::Page;
      else return textfile::fail(file, n + 1, "unknown panel item type '" + std::string(value) + "'");
      panel.items.push_back(it);
      item = &panel.items.back();
      continue;
    }
    if (!item) {
      if (key == "panel name" || key == "name") panel.name = std::string(value);
      else if (key == "associate") {
        std::vector<std::string_view> w = words(value);  // "File NAME"
        if (w.size() >= 2 && w[0] == "File") panel.target = std::string(value.substr(value.find(w[1])));
      } else if (key == "trigger") panel.trigger = std::string(value);
      continue;
    }
    if (key == "name") item->name = std::string(value);
    else if (key == "message") item->message = std::string(value);
    else if (key == "min/max" || key == "value") {
      std::vector<std::string_view> w = words(value);
      std::optional<double> a = w.empty() ? std::nullopt : number(w[0]);
      std::optional<double> b = w.size() >= 2 ? number(w[1]) : std::nullopt;
      if (!a || (key == "min/max" && !b))
        return textfile::fail(file, n + 1, "'" + key + ":' needs " + (key == "value" ? "a number" : "two numbers"));
      if (key == "value") item->value = int(*a);
      else item->min = int(*a), item->max = int(*b);
    }
  }
  closeGroup();
  return panel;
}

std::vector<PanelAndTarget> findPanels(const std::string& modelDir) {
  namespace fs = std::filesystem;
  std::vector<PanelAndTarget> out;
  fs::path dir = modelDir.empty() ? fs::path(".") : fs::path(modelDir);
  auto add = [&](const std::string& panel, const std::string& target) {
    PanelAndTarget p{(dir / panel).lexically_normal().string(), (dir / target).lexically_normal().string()};
    for (const PanelAndTarget& q : out)
      if (q.panel == p.panel) return;
    std::error_code ec;
    if (fs::is_regular_file(p.panel, ec)) out.push_back(p);
  };
  // vlab's object: `panel P | awkped T` (the panel may be preceded by options such as -rmode).
  std::string spec = readText(dir / "specifications");
  for (std::string_view line : splitLines(spec)) {
    std::vector<std::string_view> w = words(line);
    auto bar = std::find(w.begin(), w.end(), "|");
    // "panel", at least the panel's name, "|", "awkped", the target
    if (w.size() < 5 || w[0] != "panel" || bar == w.end() || bar - w.begin() < 2 || w.end() - bar < 3 ||
        *(bar + 1) != "awkped")
      continue;
    add(std::string(*(bar - 1)), std::string(w.back()));
  }
  std::error_code ec;
  std::vector<std::string> pnl;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".pnl") pnl.push_back(e.path().filename().string());
  std::sort(pnl.begin(), pnl.end());
  for (const std::string& name : pnl) {
    auto parsed = parsePanel(readText(dir / name), (dir / name).string());
    if (!parsed) {
      llvm::consumeError(parsed.takeError());
      continue;
    }
    if (!parsed->target.empty()) add(name, parsed->target);
  }
  std::sort(out.begin(), out.end(), [](const PanelAndTarget& a, const PanelAndTarget& b) { return a.panel < b.panel; });
  return out;
}

}  // namespace lcjit::runtime
