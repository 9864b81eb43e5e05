// L+C → C++: turns the L-system constructs of a preprocessed model (modules, axiom, productions,
// decomposition/interpretation rules, groups, control statements, produce & co.) into a C++
// translation unit against lpfgall.h that describes itself through __lc_model() (lcjit/abi.h).
// Everything else passes through; #line directives keep Clang's diagnostics on the .l file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::frontend {

struct ModuleDecl {
  std::string name;
  int id = 0;
  std::vector<std::string> paramTypes;
};

struct Rewritten {
  std::string cpp;
  std::vector<ModuleDecl> userModules;  // in declaration order, ids from 103
  int ruleCount = 0;
  // Where each rule's function (`static void __lc_rule_N(...) {...}`, N = index) is in `cpp`, as
  // [begin, end) offsets, and where the generated tables start: what an incremental recompile
  // compares and replaces.
  std::vector<std::pair<size_t, size_t>> ruleSpans;
  size_t tablesAt = 0;
  // Production groups a user applies by name, a step at a time (XL's rule methods, as GroIMP's
  // buttons apply them: the window's Rules menu): each name and its group. Empty for L+C.
  std::vector<std::pair<std::string, int>> namedGroups;
};

// `preprocessed` is preprocessor output with GNU line markers; `mainFile` is the .l path.
// Errors are `FILE:LINE:COL: error: MESSAGE`.
llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile);

// The pseudo-file the generated tables are compiled as: `<lcjit: generated model tables FILE:L:C>`,
// where FILE:L:C is the end of the model's text (ClangDiagnostics reads it).
inline constexpr const char* kTablesFile = "<lcjit: generated model tables";

// The entry point every rewritten model defines.
inline constexpr const char* kModelEntry = "__lc_model";

}  // namespace lcjit::frontend
