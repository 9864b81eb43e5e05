// Files in lcjit's disk caches (compiled PCHs and objects, the preprocessor's macro image):
// written whole or not at all, and keyed by what they were made from.
#pragma once

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/SHA256.h>

#include <string>

namespace lcjit::frontend {

// Writes `bytes` to a temporary file beside `path` and renames it into place, so that a reader
// never sees a partial file; false (and nothing written) on failure.
bool writeCacheFile(const std::string& path, llvm::StringRef bytes);

// Adds every regular file under `dir` (names and contents, in name order) to `h`: what a cache
// entry made from the runtime headers depends on.
void hashDirectoryTree(llvm::SHA256& h, const std::string& dir);

}  // namespace lcjit::frontend
