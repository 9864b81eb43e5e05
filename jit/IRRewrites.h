// What lcjit changes in a model's IR between the front end and the IR passes, so that versions can
// share state and an object file can carry its own constructors. How it fits: docs/jit.md.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace llvm {
class Module;
}

namespace lcjit::jit {

// Gives the module's mutable globals names another compile of the same source can refer to:
// internal ones become external under the same (deterministic) name, discardable ones stay.
// Returns the names: the model's state, which a better-optimised tier shares (CompileOptions::
// shareStateWith). A zero-filled one of detail::kFarData bytes or more is reached through the GOT
// (not dso_local), here and wherever it is shared: the linker may place it far from all code
// (ModelMemory.h).
std::vector<std::string> exportState(llvm::Module& m);

// The globals other loaded code owns become declarations here (resolved against that code's
// JITDylib), and their dynamic initializers are not run again: clang calls one function per
// initialized global from the TU's constructor; the calls for shared globals are dropped.
void useSharedState(llvm::Module& m, const std::set<std::string>& shared);

// Object files reach ORC without its IR-level constructor scraping, so do it here: one function
// under the generic IR platform's init prefix (it runs those on JITDylib initialize) calls the
// constructors in priority order and registers the destructors with the JITDylib's own atexit
// (run on deinitialize).
void gatherInitializers(llvm::Module& m);

}  // namespace lcjit::jit
