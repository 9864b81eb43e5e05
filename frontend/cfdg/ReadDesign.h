// Context Free's front end as the languages' table names it (app/session/Languages.h): a design's
// text → the C++ unit the shape-expansion engine runs (Translate.h), with the files it imported.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

#include "frontend/cfdg/Translate.h"

namespace lcjit::frontend::cfdg {

// A global number a design defines as a plain constant (`turn = 10`, `n = -2.5`): what a -D
// NAME=VALUE replaces, and what the window's Parameters panel offers to change.
struct DesignVariable {
  std::string name;
  double value = 0;
  int line = 0;  // of its definition in the design (or 0: given with -D)
};

struct DesignUnit {
  Translation translation;
  std::vector<std::string> imports;  // the files imported or included, as read
  std::vector<DesignVariable> variables;  // in the order the design defines them
};

// Parses (with the -D NAME=VALUE `defines`, Parser.h) and translates; errors at file:line:col.
llvm::Expected<DesignUnit> readDesign(std::string_view text, const std::string& file,
                                      const std::vector<std::string>& defines);

}  // namespace lcjit::frontend::cfdg
