// The host functions compiled models may call (the lcjit_* entries of lcjit/abi.h), as a table
// of (name, address) pairs the JIT defines explicitly for model code.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace lcjit::runtime {

std::vector<std::pair<std::string, void*>> hostFunctions();

}  // namespace lcjit::runtime
