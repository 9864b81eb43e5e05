// Per-rule counts and times of a derivation (the window's Profile panel, `--profile FILE.json`,
// the REPL's :profile): how often each production, decomposition and interpretation rule ran and
// produced, and the time its body took, per step and in total. Off unless asked for: the engine
// then pays one test of a null pointer per rule body it runs.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

struct __lc_Model;

namespace lcjit::runtime {

struct RuleCounts {
  uint64_t produced = 0;  // the body ran and ended in produce: the rule applied
  uint64_t ran = 0;       // the body ran (its predecessor and context matched)
  uint64_t ns = 0;        // time in the body, rules it ran inside it included (OutputFrame)
  bool empty() const { return ran == 0; }
  void add(const RuleCounts& o) {
    produced += o.produced;
    ran += o.ran;
    ns += o.ns;
  }
};

class Profile {
 public:
  using Clock = std::chrono::steady_clock;

  // Starts again for a model with `rules` rules (a begin(), a new model).
  void reset(size_t rules);
  void record(size_t rule, bool produced, Clock::duration spent) {
    RuleCounts& c = current_[rule];
    c.produced += produced;
    ++c.ran;
    c.ns += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(spent).count());
  }
  // Ends what was counted since the last call as step `step` (0: Start, the axiom and its
  // decomposition). Interpretation is counted apart (interpreted()).
  void endStep(int step);
  void interpreted();

  struct Step {
    int step = 0;
    std::vector<std::pair<uint32_t, RuleCounts>> rules;  // the rules that ran, by index
  };
  const std::vector<RuleCounts>& total() const { return total_; }       // steps and interpretation
  const std::vector<RuleCounts>& interpretation() const { return interpretation_; }
  const std::vector<Step>& steps() const { return steps_; }
  size_t rules() const { return total_.size(); }

 private:
  void flush(std::vector<RuleCounts>& into, Step* step);
  std::vector<RuleCounts> current_, total_, interpretation_;
  std::vector<Step> steps_;
};

// What a language whose front end writes L+C calls the parts of the L+C in its own terms, for
// the faults' messages and the reports: XL's rules are the L+C's productions, its blocks among the rules its
// StartEach. A null part: L+C's word.
struct LanguageWords {
  const char* production = nullptr;  // "rule"
  const char* decomposition = nullptr;
  const char* interpretation = nullptr;
  const char* start = nullptr;  // what the Start statement is, StartEach …
  const char* startEach = nullptr;
  const char* endEach = nullptr;
  const char* end = nullptr;
};

// The rules of `model` by index: kind ("production", "decomposition", "interpretation"), what
// the model's language calls it (`word`: L+C's "production", XL's "rule"), the predecessor as
// written (its module named as the language names it, `shown`), file and line. For reports.
struct RuleSource {
  std::string kind, word, predecessor, file;
  int line = 0;
};
std::vector<RuleSource> ruleSources(const __lc_Model& model, const LanguageWords* words = nullptr,
                                    std::string_view (*shown)(std::string_view) = nullptr);
// A rule's predecessor `A(x)` with its module as the language names it and only the parameters
// its user named (`shown`; null: as it is).
std::string shownPredecessor(std::string predecessor, std::string_view (*shown)(std::string_view));

// Rules by total time, hottest first (ties: more applications first, then source order); rules that
// never ran are left out.
std::vector<size_t> hottestRules(const std::vector<RuleCounts>& counts);

}  // namespace lcjit::runtime
