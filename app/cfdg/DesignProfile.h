// What a Context Free design's counted expansion (ExpandOptions::profile) says, for people: its
// rules as the profile's rows (app/common/ProfileReport), named as the design writes them ("rule
// Tree 0.5" for one of Tree's rules, of weight 0.5; "rule Leaf", a shape's only rule; "path
// Petal"; "tree.cfdg:12"), the hottest first; the shapes the picture holds, by kind. `--profile`
// prints them as a table, `--profile FILE.json` writes them as JSON, and the window's Profile panel
// shows the rows.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "app/common/ProfileReport.h"
#include "runtime/cfdg/Expander.h"

namespace lcjit::app {

// The rules that ran, hottest first (their own time; a rule always applies, so applied == ran).
std::vector<ProfileRow> designProfileRows(const __cf_Design& design, const runtime::cfdg::Expansion& e);

// The finished shapes the picture holds (a symmetry's copies each count), by kind: CIRCLE,
// SQUARE, TRIANGLE, FILL, then each path ("path Petal"); kinds with none left out.
std::vector<std::pair<std::string, uint64_t>> finishedByKind(const __cf_Design& design, const runtime::cfdg::Expansion& e);
// The same as words: "1024 SQUARE, 3 CIRCLE" ("no shapes" for none).
std::string finishedText(const std::vector<std::pair<std::string, uint64_t>>& kinds);

// `--profile`: the rules as ProfileReport's table, then the rules expanded and the shapes
// finished by kind.
std::string designProfileTable(const __cf_Design& design, const runtime::cfdg::Expansion& e);
// `--profile FILE.json`: the design, its variation, the expansion's time, every rule that ran
// (`kind`, `rule`, `file`, `line`, `applied`, `ran`, `ms`, hottest first) and `finished`, the shapes
// by kind.
std::string designProfileJson(const __cf_Design& design, const runtime::cfdg::Expansion& e, const std::string& file,
                              uint64_t variation, double expandMs);

}  // namespace lcjit::app
