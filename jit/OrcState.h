// The JIT's long-lived state: one LLJIT, the TargetMachines kept for code generation, and one
// JITDylib per loaded model version (detail::Dylib), which ModelCode holds. See docs/jit.md.
#pragma once

#include "jit/CodeMap.h"
#include "jit/Compiler.h"

#include <llvm/ExecutionEngine/Orc/Core.h>
#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/ExecutionEngine/Orc/LLJIT.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Target/TargetMachine.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::jit {

namespace orc = llvm::orc;

// Runs an ORC call that executes model code (static constructors/destructors); a C++ exception
// thrown by that code becomes an Error instead of unwinding through ORC into the caller.
template <class Fn>
llvm::Error callCatching(Fn fn, const char* who) {
  try {
    return fn();
  } catch (...) {
    return llvm::createStringError(llvm::Twine("a ") + who + " threw an exception");
  }
}

// Runs the destructors this JITDylib's own code registered (its atexit list), and only those:
// LLJIT::deinitialize would also run those of every JITDylib in its link order, which for a
// version sharing another's globals destroys them while the other still runs.
llvm::Error runOwnAtExits(orc::LLJIT& J, orc::JITDylib& JD);

namespace detail {

// Instruction selection (and the IR passes) at one level, with one TargetMachine kept for it:
// creating one and its subtarget costs ~1 ms, a tenth of a quick compile. It is not thread-safe
// (subtargets are created on demand), hence the mutex.
struct Codegen {
  std::mutex mutex;
  std::unique_ptr<llvm::TargetMachine> tm;

  llvm::Error ensure(orc::JITTargetMachineBuilder& b, llvm::CodeGenOptLevel level);
  llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> compile(llvm::Module& m, orc::JITTargetMachineBuilder b,
                                                              llvm::CodeGenOptLevel level);
  // The IR passes of `level` (runIRPipeline) with this TargetMachine.
  llvm::Error optimize(llvm::Module& m, int level, orc::JITTargetMachineBuilder b, llvm::CodeGenOptLevel cgLevel);
};

// Everything ModelCode needs after the Compiler is gone: the LLJIT is destroyed only after the
// last ModelCode released its JITDylib (the reverse order is a use-after-free).
struct JitState {
  // The LLJIT for `jtmb`'s target, with the host symbols defined in a JITDylib of their own.
  // `objectsDir`: where the object code of ORC's own support modules is kept between runs ("":
  // in memory only). `debugger`: every object linked is registered with gdb/lldb
  // (CompilerConfig::debugger).
  static llvm::Expected<std::shared_ptr<JitState>> create(const orc::JITTargetMachineBuilder& jtmb,
                                                          const std::vector<HostSymbol>& hostSymbols,
                                                          const std::string& objectsDir, bool debugger);

  std::unique_ptr<orc::LLJIT> jit;
  orc::JITDylib* hostJD = nullptr;
  // Model code's addresses back to its source (a plugin of the JIT's linker).
  std::shared_ptr<CodeMap> codeMap;

  // What every JITDylib of lcjit's links against last: host symbols before the process's, so
  // that explicit definitions win over same-named process symbols.
  void appendRuntime(orc::JITDylibSearchOrder& order) const;
  // Serializes JITDylib creation, initialization, deinitialization and removal; lookups on
  // materialized code don't take it (ORC's session is thread-safe for those).
  std::mutex mutex;
  std::atomic<uint64_t> counter{0};
  std::mutex errorMutex;
  std::string sessionErrors;
  // JITDylibs of failed compiles, kept allocated: the generic IR platform keys its init/atexit
  // tables by JITDylib address and only clears them on a full initialize/deinitialize, so a
  // reused address could inherit stale entries.
  std::vector<orc::JITDylibSP> failedDylibs;
  // [0] fast instruction selection (the quick tiers, and ORC's own small IR modules), [1] default.
  std::array<Codegen, 2> codegen;

  ~JitState();

  std::string takeSessionErrors();
};

// One loaded model version. A version sharing another's state keeps that one alive (its globals
// live there), and is destroyed first.
struct Dylib {
  std::shared_ptr<JitState> state;
  orc::JITDylib* jd = nullptr;
  std::string name;
  std::vector<std::string> stateNames;              // the mutable globals this version defines
  std::vector<std::shared_ptr<Dylib>> stateOwners;  // the versions whose globals this one uses
  std::vector<std::shared_ptr<Dylib>> linked;       // the versions whose functions it calls
  // Each owned global as loaded, before the constructors ran: where it is, its size, and its
  // bytes, unless it was zero-filled (.bss): those are not copied (a model's 1 GB array would be
  // made resident by the copy), and resetState() makes them zero again.
  struct Initial {
    char* at;
    uint64_t size;
    bool zero;
    std::string bytes;
  };
  std::vector<Initial> initialState;
  std::function<llvm::Error(const std::function<llvm::Error()>&)> runModelCode;  // CompileOptions'

  llvm::Error asModelCode(const std::function<llvm::Error()>& f) const { return runModelCode ? runModelCode(f) : f(); }

  ~Dylib();
};

}  // namespace detail

}  // namespace lcjit::jit
