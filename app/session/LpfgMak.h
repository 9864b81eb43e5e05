// A model folder's own lpfg.mak: lpfg builds such a model with it (its cmpl.sh runs
// `make -f lpfg.mak` instead of the standard makefile), and research models use it for C++
// helper units, include folders and a newer C++. lcjit does not build with make: it asks make
// which commands the makefile would run (make -n, in a scratch folder of links, so nothing is
// written beside the model) and takes from the compile commands their extra sources, -I and -D
// flags and -std.
#pragma once

#include <llvm/Support/Error.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::app {

struct LpfgMakBuild {
  std::vector<std::string> sources;      // absolute paths, in the makefile's order
  std::vector<std::string> includeDirs;  // absolute
  std::vector<std::pair<std::string, std::string>> defines;  // -DNAME[=VALUE]
  std::string languageStandard;          // -std=VALUE if newer than C++14 (e.g. "c++17"), else empty
};

// nullopt when `modelDir` has no lpfg.mak; an error when make is missing or fails on it.
llvm::Expected<std::optional<LpfgMakBuild>> readLpfgMak(const std::string& modelDir);

// A C++ source file by its name: .cpp .cc .cxx .C .c++ (what lpfg.mak and the command line give).
bool isCppSource(const std::string& path);

}  // namespace lcjit::app
