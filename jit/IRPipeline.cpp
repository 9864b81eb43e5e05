// The per-level IR pipelines of IRPipeline.h: -O0's, a light one of lcjit's own at -O1, the
// standard -O2.
#include "jit/IRPipeline.h"

#include <llvm/Analysis/InlineCost.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/IntrinsicInst.h>
#include <llvm/IR/Module.h>
#include <llvm/Passes/OptimizationLevel.h>
#include <llvm/Passes/PassBuilder.h>
#include <llvm/Target/TargetMachine.h>
#include <llvm/Transforms/Coroutines/CoroCleanup.h>
#include <llvm/Transforms/Coroutines/CoroConditionalWrapper.h>
#include <llvm/Transforms/Coroutines/CoroEarly.h>
#include <llvm/Transforms/Coroutines/CoroSplit.h>
#include <llvm/Transforms/IPO/ElimAvailExtern.h>
#include <llvm/Transforms/IPO/GlobalDCE.h>
#include <llvm/Transforms/IPO/Inliner.h>
#include <llvm/Transforms/InstCombine/InstCombine.h>
#include <llvm/Transforms/Scalar/EarlyCSE.h>
#include <llvm/Transforms/Scalar/SROA.h>
#include <llvm/Transforms/Scalar/SimplifyCFG.h>

#include <utility>
#include <vector>

namespace lcjit::jit {

namespace {

// Model code is compiled with -ffp-contract=off (lpfg's x86-64 baseline has no fused multiply-add),
// so llvm.fmuladd comes only from a model's own `#pragma STDC FP_CONTRACT ON`. It becomes a
// multiply and an add, as on lpfg's target, at every tier: FastISel (the quick tiers' instruction
// selector) has no rule for it and would hand its whole block to the far slower SelectionDAG.
void lowerFMulAdd(llvm::Module& m) {
  std::vector<llvm::CallInst*> calls;
  for (llvm::Function& f : m)
    if (f.getIntrinsicID() == llvm::Intrinsic::fmuladd)
      for (llvm::User* u : f.users())
        if (auto* call = llvm::dyn_cast<llvm::CallInst>(u))
          calls.push_back(call);
  for (llvm::CallInst* call : calls) {
    llvm::IRBuilder<> b(call);
    b.setFastMathFlags(call->getFastMathFlags());
    llvm::Value* r = b.CreateFAdd(b.CreateFMul(call->getArgOperand(0), call->getArgOperand(1)), call->getArgOperand(2));
    call->replaceAllUsesWith(r);
    call->eraseFromParent();
  }
}

}  // namespace

void runIRPipeline(llvm::Module& m, int level, llvm::TargetMachine* tm) {
  // Declared in this order so they are destroyed in the right order (they reference each other).
  llvm::LoopAnalysisManager lam;
  llvm::FunctionAnalysisManager fam;
  llvm::CGSCCAnalysisManager cgam;
  llvm::ModuleAnalysisManager mam;

  llvm::PipelineTuningOptions pto;
  if (level >= 2) {
    // What clang's driver turns on at -O2.
    pto.LoopUnrolling = true;
    pto.LoopInterleaving = true;
    pto.LoopVectorization = true;
    pto.SLPVectorization = true;
  }
  llvm::PassBuilder pb(tm, pto);
  pb.registerModuleAnalyses(mam);
  pb.registerCGSCCAnalyses(cgam);
  pb.registerFunctionAnalyses(fam);
  pb.registerLoopAnalyses(lam);
  pb.crossRegisterProxies(lam, fam, cgam, mam);

  llvm::ModulePassManager mpm;
  if (level <= 0) {
    mpm = pb.buildO0DefaultPipeline(llvm::OptimizationLevel::O0);
  } else if (level >= 2) {
    mpm = pb.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O2);
  } else {
    // Light pipeline: enough to remove the abstraction overhead of small helper calls and
    // allocas (most of the -O2 speed-up on model code) while keeping IR small for fast isel.
    {
      llvm::ModulePassManager coro;
      coro.addPass(llvm::CoroEarlyPass());
      mpm.addPass(llvm::CoroConditionalWrapper(std::move(coro)));
    }
    llvm::FunctionPassManager early;
    early.addPass(llvm::SROAPass(llvm::SROAOptions::ModifyCFG));
    early.addPass(llvm::EarlyCSEPass());
    early.addPass(llvm::SimplifyCFGPass());
    mpm.addPass(llvm::createModuleToFunctionPassAdaptor(std::move(early)));

    llvm::ModuleInlinerWrapperPass inliner(llvm::getInlineParams(1, 0));
    llvm::FunctionPassManager post;
    post.addPass(llvm::SROAPass(llvm::SROAOptions::ModifyCFG));
    post.addPass(llvm::EarlyCSEPass());
    post.addPass(llvm::InstCombinePass());
    post.addPass(llvm::SimplifyCFGPass());
    inliner.getPM().addPass(llvm::createCGSCCToFunctionPassAdaptor(std::move(post)));
    // Required for correctness whenever the model contains C++20 coroutines.
    inliner.getPM().addPass(llvm::CoroSplitPass(false));
    mpm.addPass(std::move(inliner));
    {
      llvm::ModulePassManager coro;
      coro.addPass(llvm::CoroCleanupPass());
      mpm.addPass(llvm::CoroConditionalWrapper(std::move(coro)));
    }
    // Bodies kept only for inlining (extern templates: libstdc++'s std::string in C++14) become
    // declarations again, as in the standard pipelines: left available_externally, their
    // references did not resolve in the JIT link.
    mpm.addPass(llvm::EliminateAvailableExternallyPass());
    // Inlined linkonce_odr helpers (most of the runtime header) would otherwise be codegen'd.
    mpm.addPass(llvm::GlobalDCEPass());
  }
  mpm.run(m, mam);
  lowerFMulAdd(m);
}

}  // namespace lcjit::jit
