// What a derivation's profile (runtime/Profile.h) says, for people: the JSON of `--profile
// FILE.json`, the rows the window's Profile panel and the REPL's :profile show. Rules are named as
// the user wrote them (kind, predecessor, file:line), the hottest first.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "runtime/Profile.h"

namespace lcjit::app {

struct ProfileRow {
  std::string kind, rule, where;  // "production" (XL's "rule"), "A(n) < B", "m.l:12"
  uint64_t applied = 0, ran = 0;  // in total
  double ms = 0;
  uint64_t appliedLastStep = 0;   // in the last step counted
  double msLastStep = 0;
};

// A rule's place as the rows name it ("m.l:12": the file's name without its folder), and a time
// in nanoseconds as their milliseconds (to the microsecond). Context Free designs' profiles
// (app/cfdg/DesignProfile) make their rows with them.
std::string profileWhere(const std::string& file, int line);
double profileMs(uint64_t ns);

// Hottest first; rules that never ran are left out. The *LastStep columns: the last step counted.
std::vector<ProfileRow> profileRows(const runtime::Profile& profile, const std::vector<runtime::RuleSource>& rules);

// `--profile`: the model, the steps derived, every rule that ran (hottest first) and, per step,
// what each rule did in it (rules by their index in "rules").
std::string profileJson(const runtime::Profile& profile, const __lc_Model& model, const std::vector<runtime::RuleSource>& rules,
                        int stepsDone, double deriveMs);

// The rows as aligned text (the REPL's :profile, a design's --profile), at most `limit` rules.
std::string profileTable(const std::vector<ProfileRow>& rows, size_t limit);

}  // namespace lcjit::app
