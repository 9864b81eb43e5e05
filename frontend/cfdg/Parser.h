// Parses a Context Free design (CFDG 3) into Ast.h's tree. Errors name file:line:col in Context
// Free's terms.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

#include "frontend/cfdg/Ast.h"

namespace lcjit::frontend::cfdg {

// `defines`: NAME=VALUE definitions given on the command line (-D), read before the design as
// CFDG 3 definitions (a design is then read as CFDG 3, as Context Free does); the design's own
// definition of such a NAME is dropped.
llvm::Expected<Design> parseDesign(std::string_view source, const std::string& file,
                                   const std::vector<std::string>& defines = {});

// The adjustment words (x, size, hue, …) in their canonical spelling; "" for other names.
std::string adjustmentWord(std::string_view word);

}  // namespace lcjit::frontend::cfdg
