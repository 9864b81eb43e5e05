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

std::vector<RuleSource> ruleSources(const __lc_Model& model) {
  std::vector<RuleSource> out(model.nRules);
  for (uint32_t i = 0; i < model.nRules; ++i) {
    const __lc_Rule& r = model.rules[i];
    out[i].kind = r.kind == __lc_Production ? "production" : r.kind == __lc_Decomposition ? "decomposition" : "interpretation";
    out[i].predecessor = r.predecessor ? r.predecessor : "";
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
