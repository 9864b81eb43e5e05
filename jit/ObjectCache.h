// The object cache: a compile's object code kept by a key of everything it was made from, in
// memory (the newest few) and on disk, for an identical compile to load instead. See docs/jit.md.
#pragma once

#include <llvm/ADT/StringRef.h>

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace lcjit::jit {

// What the object cache keeps of a compile: the object file and what loading it needs to know.
struct CachedObject {
  std::string object;
  std::string anchor;                   // a defined symbol: looking it up links the whole object
  std::vector<std::string> stateNames;  // see exportState
  std::vector<uint64_t> stateSizes;     // their sizes in bytes
  // Where each variable the object defines is declared, by its symbol: "FILE:LINE:COL" (for
  // errors about its static data: StaticData::declaredAt).
  std::map<std::string, std::string> declaredAt;
};

// The object cache's key: everything the object depends on. The PCH's name (`pchPath`) hashes the
// compiler, the cc1 line and the runtime header tree; quoted includes are already expanded into
// `source` by the preprocessor. `unitKind`: "pch", "text" (the header included as text) or
// "plain" (CompileOptions::plainUnit). `shared`: the globals that are declarations here.
std::string objectKey(llvm::StringRef pchPath, llvm::StringRef unitKind, llvm::StringRef bufferName,
                      llvm::StringRef source, const std::set<std::string>& shared, int level);

}  // namespace lcjit::jit
