// Clang as a library: each opt level's compiler invocation (LevelSetup) and one front-end run from
// C++ text to an LLVM module (Frontend), which a quick tier may begin before the text exists.
#pragma once

#include "frontend/ClangDiagnostics.h"

#include <clang/CodeGen/CodeGenAction.h>
#include <clang/Frontend/CompilerInstance.h>
#include <clang/Frontend/CompilerInvocation.h>
#include <clang/Frontend/FrontendAction.h>
#include <llvm/ADT/StringRef.h>
#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/MemoryBuffer.h>

#include <cstddef>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lcjit::jit {

// Runs `action` on `inv` to the end, its diagnostics into `dc`; true when there was no error.
bool executeClang(std::shared_ptr<clang::CompilerInvocation> inv, clang::FrontendAction& action,
                  frontend::DiagCollector& dc);

// One clang front end run, in two halves. begin() does all that does not need the unit's text:
// the CompilerInstance, the target, the PCH loaded and validated, the builtins registered
// (~3-4 ms of a ~10 ms quick compile). finish() puts the text into the buffer the main file
// already points at (padded with spaces to the capacity it was begun with) and parses and
// generates IR. So a quick tier can begin the next compile's front end ahead, while the
// modeller is still typing.
class Frontend {
public:
  struct Result {
    std::unique_ptr<llvm::LLVMContext> ctx;
    std::unique_ptr<llvm::Module> module;
    std::shared_ptr<std::string> backendErrors;  // what the LLVM back end reports later
    std::string diagnostics;
    bool pchProblem = false;
    // Where each global variable the module defines is declared (CachedObject::declaredAt).
    std::map<std::string, std::string> declaredAt;
  };

  Frontend(std::shared_ptr<clang::CompilerInvocation> base, std::string pchPath, bool pchFallback,
           const std::string& runtimeHeader, std::string bufferName, size_t capacity);
  Frontend(const Frontend&) = delete;
  Frontend& operator=(const Frontend&) = delete;
  ~Frontend();

  bool begin();
  Result finish(llvm::StringRef source);

  const std::string pchPath;
  const bool pchFallback;
  const std::string bufferName;
  const size_t capacity;
  // CompileOptions::lineTables, CompilerConfig::debugger (full debug information); set before
  // begin().
  bool lineTables = true;
  bool fullDebugInfo = false;

private:
  std::shared_ptr<clang::CompilerInvocation> base;
  std::string runtimeHeader;
  std::unique_ptr<char[]> text;
  std::unique_ptr<llvm::MemoryBuffer> remapped;
  std::unique_ptr<llvm::LLVMContext> ctx;
  std::shared_ptr<std::string> backendErrors;
  frontend::DiagCollector dc;
  std::unique_ptr<clang::CompilerInstance> ci;
  std::unique_ptr<clang::EmitLLVMOnlyAction> action;
  bool begun = false;
};

// Per opt level: the driver-derived invocation (built once) and the PCH state.
struct LevelSetup {
  std::mutex mutex;
  std::shared_ptr<clang::CompilerInvocation> base;
  std::vector<std::string> cc1Args;
  std::string pchPath;
  bool pchReady = false;    // pchPath holds a PCH this process built or already used successfully
  bool pchFallback = false; // PCH unusable (unwritable cache...): include the header as text
  // The quick tiers' next front end, begun on another thread after each compile (Frontend).
  std::future<std::unique_ptr<Frontend>> ahead;
};

}  // namespace lcjit::jit
