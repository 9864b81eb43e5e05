// Reports of a profile (ProfileReport.h).
#include "app/common/ProfileReport.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "runtime/include/lcjit/abi.h"

namespace lcjit::app {
double profileMs(uint64_t ns) { return std::round(double(ns) / 1000.0) / 1000.0; }

std::string profileWhere(const std::string& path, int line) {
  std::string file = path;
  if (size_t slash = file.rfind('/'); slash != std::string::npos) file = file.substr(slash + 1);
  return file + ":" + std::to_string(line);
}

namespace {

double ms(uint64_t ns) { return profileMs(ns); }
std::string where(const runtime::RuleSource& s) { return profileWhere(s.file, s.line); }

}  // namespace

std::vector<ProfileRow> profileRows(const runtime::Profile& profile, const std::vector<runtime::RuleSource>& src) {
  std::map<uint32_t, runtime::RuleCounts> last;
  if (!profile.steps().empty())
    for (const auto& [i, c] : profile.steps().back().rules) last[i] = c;
  std::vector<ProfileRow> rows;
  for (size_t i : runtime::hottestRules(profile.total())) {
    if (i >= src.size()) continue;
    const runtime::RuleCounts& c = profile.total()[i];
    ProfileRow r;
    r.kind = src[i].word;
    r.rule = src[i].predecessor;
    r.where = where(src[i]);
    r.applied = c.produced;
    r.ran = c.ran;
    r.ms = ms(c.ns);
    if (auto l = last.find(uint32_t(i)); l != last.end()) {
      r.appliedLastStep = l->second.produced;
      r.msLastStep = ms(l->second.ns);
    }
    rows.push_back(std::move(r));
  }
  return rows;
}

std::string profileJson(const runtime::Profile& profile, const __lc_Model& model, const std::vector<runtime::RuleSource>& src,
                        int stepsDone, double deriveMs) {
  std::vector<size_t> hot = runtime::hottestRules(profile.total());
  std::map<size_t, size_t> position;  // rule index → place in "rules"
  nlohmann::ordered_json rules = nlohmann::ordered_json::array();
  for (size_t i : hot) {
    if (i >= src.size()) continue;
    const runtime::RuleCounts& c = profile.total()[i];
    position[i] = rules.size();
    rules.push_back({{"kind", src[i].kind},
                     {"rule", src[i].predecessor},
                     {"file", src[i].file},
                     {"line", src[i].line},
                     {"applied", c.produced},
                     {"ran", c.ran},
                     {"ms", ms(c.ns)}});
  }
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const runtime::Profile::Step& s : profile.steps()) {
    nlohmann::ordered_json each = nlohmann::ordered_json::array();
    for (const auto& [i, c] : s.rules)
      if (auto p = position.find(i); p != position.end())
        each.push_back({{"rule", p->second}, {"applied", c.produced}, {"ran", c.ran}, {"ms", ms(c.ns)}});
    steps.push_back({{"step", s.step}, {"rules", std::move(each)}});
  }
  nlohmann::ordered_json out = {{"model", model.sourceFile ? model.sourceFile : ""},
                                {"steps", stepsDone},
                                {"derive_ms", std::round(deriveMs * 1000) / 1000},
                                {"rules", std::move(rules)},
                                {"per_step", std::move(steps)}};
  return out.dump(1) + "\n";
}

std::string profileTable(const std::vector<ProfileRow>& rows, size_t limit) {
  if (rows.empty()) return "(no rule has run)\n";
  size_t ruleWidth = 4, whereWidth = 5;
  for (size_t k = 0; k < rows.size() && k < limit; ++k) {
    ruleWidth = std::max(ruleWidth, rows[k].kind.size() + 1 + rows[k].rule.size());
    whereWidth = std::max(whereWidth, rows[k].where.size());
  }
  ruleWidth = std::min<size_t>(ruleWidth, 48);
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-*s  %-*s  %12s  %12s  %10s\n", int(ruleWidth), "rule", int(whereWidth), "where",
                "applied", "ran", "ms");
  out += line;
  for (size_t k = 0; k < rows.size() && k < limit; ++k) {
    const ProfileRow& r = rows[k];
    std::string name = r.kind + " " + r.rule;
    if (name.size() > ruleWidth) name = name.substr(0, ruleWidth - 3) + "...";
    std::snprintf(line, sizeof line, "%-*s  %-*s  %12llu  %12llu  %10.3f\n", int(ruleWidth), name.c_str(),
                  int(whereWidth), r.where.c_str(), (unsigned long long)r.applied, (unsigned long long)r.ran, r.ms);
    out += line;
  }
  if (rows.size() > limit) out += "(" + std::to_string(rows.size() - limit) + " more)\n";
  return out;
}

}  // namespace lcjit::app
