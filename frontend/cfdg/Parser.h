// Parses a Context Free design (CFDG 3) into Ast.h's tree. Errors name file:line:col in Context
// Free's terms.
#pragma once
#include <string>
#include <string_view>

#include <llvm/Support/Error.h>

#include "frontend/cfdg/Ast.h"

namespace lcjit::frontend::cfdg {

llvm::Expected<Design> parseDesign(std::string_view source, const std::string& file);

// The adjustment words (x, size, hue, …) in their canonical spelling; "" for other names.
std::string adjustmentWord(std::string_view word);

}  // namespace lcjit::frontend::cfdg
