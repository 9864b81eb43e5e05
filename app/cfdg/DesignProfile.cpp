// A Context Free design's profile, for people (DesignProfile.h).
#include "app/cfdg/DesignProfile.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include <nlohmann/json.hpp>

namespace lcjit::app {
namespace {

namespace cf = runtime::cfdg;

// A rule of the design as the profile names it.
struct RuleName {
  std::string kind, rule, file;
  int line = 0;
};

RuleName ruleName(const __cf_Design& design, int index) {
  const __cf_Rule& r = design.rules[index];
  const __cf_Shape& shape = design.shapes[r.shape];
  RuleName n;
  n.kind = shape.isPath ? "path" : "rule";
  n.rule = shape.name;
  // The weight tells a shape's rules apart: as written (a % weight as a percentage).
  int siblings = 0;
  for (int k = 0; k < design.ruleCount; ++k) siblings += design.rules[k].shape == r.shape;
  if (siblings > 1) {
    char weight[48];
    if (r.percent) std::snprintf(weight, sizeof weight, " %g%%", r.weight * 100.0);
    else std::snprintf(weight, sizeof weight, " %g", r.weight);
    n.rule += weight;
  }
  // "file:line:col": the file may hold colons, the line and column do not.
  const std::string at = r.at ? r.at : "";
  const size_t column = at.rfind(':'), line = column == std::string::npos ? column : at.rfind(':', column - 1);
  if (line != std::string::npos) {
    n.file = at.substr(0, line);
    n.line = std::atoi(at.c_str() + line + 1);
  }
  return n;
}

}  // namespace

std::vector<ProfileRow> designProfileRows(const __cf_Design& design, const cf::Expansion& e) {
  std::vector<ProfileRow> rows;
  for (size_t i : runtime::hottestRules(e.ruleRuns)) {
    if (i >= size_t(design.ruleCount)) continue;
    const RuleName n = ruleName(design, int(i));
    ProfileRow r;
    r.kind = n.kind;
    r.rule = n.rule;
    r.where = profileWhere(n.file, n.line);
    r.applied = e.ruleRuns[i].produced;
    r.ran = e.ruleRuns[i].ran;
    r.ms = profileMs(e.ruleRuns[i].ns);
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<std::pair<std::string, uint64_t>> finishedByKind(const __cf_Design& design, const cf::Expansion& e) {
  uint64_t primitives[4] = {0, 0, 0, 0};
  std::map<int, uint64_t> paths;  // by the path's shape number
  for (const cf::FinishedShape& f : e.shapes) {
    if (f.shape < 4) ++primitives[f.shape];
    else ++paths[e.paths[size_t(f.path)].shape];
  }
  std::vector<std::pair<std::string, uint64_t>> kinds;
  const char* names[4] = {"CIRCLE", "SQUARE", "TRIANGLE", "FILL"};
  for (int k = 0; k < 4; ++k)
    if (primitives[k]) kinds.emplace_back(names[k], primitives[k]);
  for (const auto& [shape, count] : paths) kinds.emplace_back(std::string("path ") + design.shapes[shape].name, count);
  return kinds;
}

std::string finishedText(const std::vector<std::pair<std::string, uint64_t>>& kinds) {
  std::string text;
  for (const auto& [kind, count] : kinds) text += (text.empty() ? "" : ", ") + std::to_string(count) + " " + kind;
  return text.empty() ? "no shapes" : text;
}

std::string designProfileTable(const __cf_Design& design, const cf::Expansion& e) {
  std::vector<ProfileRow> rows = designProfileRows(design, e);
  return profileTable(rows, rows.size()) + std::to_string(e.expanded) + " rules expanded; finished: " +
         finishedText(finishedByKind(design, e)) + "\n";
}

std::string designProfileJson(const __cf_Design& design, const cf::Expansion& e, const std::string& file,
                              uint64_t variation, double expandMs) {
  nlohmann::ordered_json rules = nlohmann::ordered_json::array();
  for (size_t i : runtime::hottestRules(e.ruleRuns)) {
    if (i >= size_t(design.ruleCount)) continue;
    const RuleName n = ruleName(design, int(i));
    const runtime::RuleCounts& c = e.ruleRuns[i];
    rules.push_back({{"kind", n.kind},
                     {"rule", n.rule},
                     {"file", n.file},
                     {"line", n.line},
                     {"applied", c.produced},
                     {"ran", c.ran},
                     {"ms", profileMs(c.ns)}});
  }
  nlohmann::ordered_json finished = nlohmann::ordered_json::object();
  for (const auto& [kind, count] : finishedByKind(design, e)) finished[kind] = count;
  nlohmann::ordered_json out = {{"design", file},
                                {"variation", cf::variationName(variation)},
                                {"expanded", e.expanded},
                                {"expand_ms", std::round(expandMs * 1000) / 1000},
                                {"rules", std::move(rules)},
                                {"finished", std::move(finished)}};
  return out.dump(1) + "\n";
}

}  // namespace lcjit::app
