// XL (GroIMP's relational growth grammars, .rgg and .xl files) on lcjit's L-system engine: the
// model, as the C preprocessor left it, is translated into the L+C that frontend/lc's rewriter
// takes, and the rewriter makes the C++ of it. Each token of the user's text keeps its file, line
// and column in the L+C (GNU line markers, and spaces up to its column), so the rewriter's and the
// compiler's errors name the .rgg where it was written. docs/xl.md says what is translated, how
// GroIMP's turtle maps onto lcjit's, and what XL lcjit does not run yet.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <llvm/Support/Error.h>

#include "frontend/lc/Rewriter.h"

namespace lcjit::frontend::xl {

// The L+C of an XL model. Errors are `FILE:LINE:COL: error: MESSAGE`.
// `run`: the rule method a step applies (GroIMP's button; empty: the model's first). Each rule
// method is a production group of the L+C, which `ruleMethods` gets: its name and its group.
llvm::Expected<std::string> toLplusC(const std::string& preprocessed, const std::string& mainFile,
                                     const std::string& run = {},
                                     std::vector<std::pair<std::string, int>>* ruleMethods = nullptr);

// The name XL gives a module of the L+C toLplusC writes, in the string's text: `[` and `]` for
// SB and EB, `G` for a model's module XL_G (named as one of lcjit's own), `F` for F_d and F_dc
// (GroIMP's F(l, d) and F(l, d, c)), `Null` for Null_t (Null(x, y, z)); any other keeps its name.
std::string_view shownName(std::string_view lcName);

// The languages table's front end for XL (app/session/Languages.h's RewriteModel): toLplusC,
// then frontend::rewrite.
llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile, const std::string& run);

}  // namespace lcjit::frontend::xl
