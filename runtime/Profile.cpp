// Per-rule counts and times (Profile.h).
#include "runtime/Profile.h"

#include <algorithm>
#include <numeric>

#include "runtime/include/lcjit/abi.h"

namespace lcjit::runtime {

void Profile::reset(size_t rules) {
  current_.assign(rules, {});
  total_.assign(rules, {});
  interpretation_.assign(rules, {});
  steps_.clear();
}

void Profile::flush(std::vector<RuleCounts>& into, Step* step) {
  for (size_t i = 0; i < current_.size(); ++i) {
    if (current_[i].empty()) continue;
    into[i].add(current_[i]);
    if (&into != &total_) total_[i].add(current_[i]);
    if (step) step->rules.emplace_back(uint32_t(i), current_[i]);
    current_[i] = {};
  }
}

void Profile::endStep(int step) {
  Step s;
  s.step = step;
  flush(total_, &s);
  if (!s.rules.empty()) steps_.push_back(std::move(s));
}

void Profile::interpreted() { flush(interpretation_, nullptr); }

std::string shownPredecessor(std::string predecessor, std::string_view (*shown)(std::string_view)) {
  if (!shown) return predecessor;
  const size_t open = std::min(predecessor.find('('), predecessor.size());
  std::string out(shown(std::string_view(predecessor).substr(0, open)));
  if (open == predecessor.size() || predecessor.back() != ')') return out + predecessor.substr(open);
  // The parameters the user named; those a translation named for itself (reserved names, `__…`:
  // XL's fields the pattern leaves unnamed) are left out.
  std::string kept;
  int depth = 0;
  size_t from = open + 1;
  for (size_t i = open + 1; i < predecessor.size(); ++i) {
    const char c = predecessor[i];
    if (c == '(') ++depth;
    if (c == ')' && depth > 0) --depth;
    else if ((c == ',' && depth == 0) || i + 1 == predecessor.size()) {
      const std::string arg = predecessor.substr(from, i - from);
      if (arg.rfind("__", 0) != 0) kept += (kept.empty() ? "" : ",") + arg;
      from = i + 1;
    }
  }
  return kept.empty() ? out : out + "(" + kept + ")";
}

std::vector<RuleSource> ruleSources(const __lc_Model& model, const LanguageWords* words,
                                    std::string_view (*shown)(std::string_view)) {
  std::vector<RuleSource> out(model.nRules);
  const LanguageWords w = words ? *words : LanguageWords{};
  for (uint32_t i = 0; i < model.nRules; ++i) {
    const __lc_Rule& r = model.rules[i];
    out[i].kind = r.kind == __lc_Production ? "production" : r.kind == __lc_Decomposition ? "decomposition" : "interpretation";
    const char* own = r.kind == __lc_Production ? w.production : r.kind == __lc_Decomposition ? w.decomposition : w.interpretation;
    out[i].word = own ? own : out[i].kind;
    out[i].predecessor = shownPredecessor(r.predecessor ? r.predecessor : "", shown);
    out[i].file = r.file && *r.file ? r.file : (model.sourceFile ? model.sourceFile : "");
    out[i].line = r.line;
  }
  return out;
}

std::vector<size_t> hottestRules(const std::vector<RuleCounts>& counts) {
  std::vector<size_t> order;
  for (size_t i = 0; i < counts.size(); ++i)
    if (!counts[i].empty()) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (counts[a].ns != counts[b].ns) return counts[a].ns > counts[b].ns;
    return counts[a].produced > counts[b].produced;
  });
  return order;
}

}  // namespace lcjit::runtime
