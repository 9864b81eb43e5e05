// The IR passes of each optimisation level (0, 1, 2): clang's own are off, so that their time is
// measured apart and level 1 can be a pipeline of lcjit's own. Why these: docs/jit.md.
#pragma once

namespace llvm {
class Module;
class TargetMachine;
}

namespace lcjit::jit {

// Runs the passes of `level` on `m` for `tm`'s target; llvm.fmuladd comes out as a multiply and an
// add at every level.
void runIRPipeline(llvm::Module& m, int level, llvm::TargetMachine* tm);

}  // namespace lcjit::jit
