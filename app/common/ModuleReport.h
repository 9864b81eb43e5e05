// One module of the string told in words, for the window's String panel and the REPL's :module:
// its text, the rule and step that made it (the engine's provenance), its neighbours, its
// parameters.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "runtime/Profile.h"

namespace lcjit::runtime {
class Engine;
}

namespace lcjit::app {

// "m.l:12": where a rule is written (the file's name, not its folder).
std::string ruleWhere(const runtime::RuleSource& rule);

// Where module `index` came from: "production A(n) (m.l:9) in step 2", "the axiom", or why it is
// not known.
std::string originText(const runtime::Engine& engine, size_t index);

// The lines that describe module `index` (0-based) of the engine's string.
std::vector<std::string> describeModule(const runtime::Engine& engine, size_t index);

}  // namespace lcjit::app
