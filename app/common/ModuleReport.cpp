// One module told in words (ModuleReport.h).
#include "app/common/ModuleReport.h"

#include <filesystem>
#include <optional>

#include "runtime/Engine.h"

namespace lcjit::app {
namespace {

std::string moduleText(const runtime::Engine& e, size_t offset) {
  std::string t;
  e.modules().format(e.string().data() + offset, t);
  return t;
}

// The byte offset of module `index`, or nothing past the end.
std::optional<size_t> offsetOf(const runtime::Engine& e, size_t index) {
  const runtime::ModuleBuffer& s = e.string();
  size_t p = 0;
  for (size_t i = 0; i < index && p < s.size(); ++i) p = e.modules().next(s.data(), p);
  if (p >= s.size()) return std::nullopt;
  return p;
}

}  // namespace

std::string ruleWhere(const runtime::RuleSource& r) {
  return std::filesystem::path(r.file).filename().string() + ":" + std::to_string(r.line);
}

std::string originText(const runtime::Engine& e, size_t index) {
  runtime::Engine::Origin o = e.originOf(index);
  if (o.rule == runtime::Engine::Origin::kAxiom) return "the axiom";
  if (o.rule >= 0 && uint32_t(o.rule) < e.model().nRules) {
    runtime::RuleSource r = e.ruleSources()[size_t(o.rule)];
    return r.word + " " + r.predecessor + " (" + ruleWhere(r) + ") in step " + std::to_string(o.step);
  }
  return e.provenance() ? "not known (a change outside the derivation, or a Gillespie step)"
                        : "not tracked in this run (origins are kept from the run after they are asked for)";
}

std::vector<std::string> describeModule(const runtime::Engine& e, size_t index) {
  std::vector<std::string> lines;
  std::optional<size_t> at = offsetOf(e, index);
  if (!at) return {"module " + std::to_string(index) + ": past the string's end"};
  lines.push_back("module " + std::to_string(index) + ": " + moduleText(e, *at));
  lines.push_back("made by: " + originText(e, index));
  // Three neighbours each side, the module in brackets.
  const runtime::ModuleBuffer& s = e.string();
  std::string context;
  size_t left = *at;
  int before = 0;
  while (left > 0 && before < 3) left = e.modules().prev(s.data(), left), ++before;
  if (left > 0) context += "... ";
  for (size_t p = left, k = 0; p < s.size() && k < size_t(before) + 4; p = e.modules().next(s.data(), p), ++k) {
    std::string m = moduleText(e, p);
    context += p == *at ? "[" + m + "] " : m + " ";
  }
  lines.push_back("context: " + context);
  const char* rec = s.data() + *at;
  const __lc_ModuleInfo& info = e.modules().info(runtime::ModuleTable::idAt(rec));
  for (uint32_t k = 0; k < info.nFields; ++k) {
    std::string v;
    runtime::ModuleTable::formatField(info.fields[k], rec, v);
    lines.push_back("  p" + std::to_string(k) + ": " + info.fields[k].typeName + " = " + v);
  }
  return lines;
}

}  // namespace lcjit::app
