// The host functions compiled models may call (the lcjit_* entries of lcjit/abi.h), as a table
// of (name, address) pairs the JIT defines explicitly for model code.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace lcjit::runtime {

std::vector<std::pair<std::string, void*>> hostFunctions();

// What C++ evaluated at the REPL printed (lcjit_repl_output) since the last call.
std::string takeReplOutput();

}  // namespace lcjit::runtime
