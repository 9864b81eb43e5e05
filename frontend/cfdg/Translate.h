// A parsed Context Free design → the C++ the JIT compiles (lcjit/cfdg.h's contract): one function
// per rule, the start function, and the design's table. Each replacement's constant random seed
// is computed here from the design's text as Context Free computes it (Entropy.h), so that the
// same variation gives the same picture.
#pragma once
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "frontend/cfdg/Ast.h"

namespace lcjit::frontend::cfdg {

struct Settings {
  double minimumSize = 0;  // CF::MinimumSize (0: not set)
  double maxShapes = 0;    // CF::MaxShapes
  double borderFixed = __builtin_nan(""), borderDynamic = __builtin_nan("");  // CF::Border… (NaN: not set)
  double border = -100;    // not a CF setting: kept for -b
};

struct Translation {
  std::string cpp;
  std::vector<std::string> shapes;  // by id: CIRCLE, SQUARE, TRIANGLE, FILL, then the design's
  int randStaticCount = 0;
  Settings settings;
};

llvm::Expected<Translation> translateDesign(const Design& design);

}  // namespace lcjit::frontend::cfdg
