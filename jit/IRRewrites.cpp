// The IR rewrites of IRRewrites.h: a version's state exported or another's used, and its
// constructors gathered into one init function.
#include "jit/IRRewrites.h"
#include "jit/ModelMemory.h"

#include <llvm/IR/Constants.h>
#include <llvm/IR/DIBuilder.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Module.h>

#include <algorithm>
#include <cstdint>
#include <utility>

namespace lcjit::jit {

namespace {

// Whether `fn` (an initializer clang emitted) touches one of `globals`.
bool touches(const llvm::Function& fn, const std::set<const llvm::GlobalVariable*>& globals) {
  std::vector<const llvm::Value*> work;
  std::set<const llvm::Value*> seen;
  for (const llvm::BasicBlock& bb : fn)
    for (const llvm::Instruction& inst : bb)
      for (const llvm::Value* op : inst.operands())
        work.push_back(op);
  while (!work.empty()) {
    const llvm::Value* v = work.back();
    work.pop_back();
    if (!seen.insert(v).second)
      continue;
    if (auto* gv = llvm::dyn_cast<llvm::GlobalVariable>(v); gv && globals.count(gv))
      return true;
    if (auto* ce = llvm::dyn_cast<llvm::ConstantExpr>(v))
      for (const llvm::Value* op : ce->operands())
        work.push_back(op);
  }
  return false;
}

}  // namespace

std::vector<std::string> exportState(llvm::Module& m) {
  std::vector<std::string> state;
  for (llvm::GlobalVariable& gv : m.globals()) {
    // thread_local ones stay each version's own: ORC reaches them through emulated TLS.
    if (gv.isDeclaration() || gv.isConstant() || gv.isThreadLocal() || !gv.hasName() ||
        gv.getName().starts_with("llvm."))
      continue;
    if (gv.hasLocalLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv.setVisibility(llvm::GlobalValue::DefaultVisibility);
    } else if (gv.hasLinkOnceODRLinkage()) {
      gv.setLinkage(llvm::GlobalValue::WeakODRLinkage);
    } else if (gv.hasLinkOnceLinkage()) {
      gv.setLinkage(llvm::GlobalValue::WeakAnyLinkage);
    }
    if (gv.hasInitializer() && gv.getInitializer()->isNullValue() &&
        m.getDataLayout().getTypeAllocSize(gv.getValueType()) >= detail::kFarData)
      gv.setDSOLocal(false);
    state.push_back(gv.getName().str());
  }
  // The productions' functions too (static in the generated C++): an incremental recompile
  // declares the unchanged ones and links against these.
  for (llvm::Function& f : m.functions())
    if (!f.isDeclaration() && f.hasLocalLinkage() && f.getName().contains("__lc_rule_")) {
      f.setLinkage(llvm::GlobalValue::ExternalLinkage);
      f.setVisibility(llvm::GlobalValue::DefaultVisibility);
    }
  return state;
}

void useSharedState(llvm::Module& m, const std::set<std::string>& shared) {
  std::set<const llvm::GlobalVariable*> declared;
  for (const std::string& name : shared)
    if (llvm::GlobalVariable* gv = m.getGlobalVariable(name, /*AllowInternal=*/true); gv && !gv->isDeclaration()) {
      gv->setInitializer(nullptr);
      gv->setComdat(nullptr);
      gv->setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv->setVisibility(llvm::GlobalValue::DefaultVisibility);
      declared.insert(gv);
    }
  llvm::GlobalVariable* ctors = m.getNamedGlobal("llvm.global_ctors");
  auto* array = ctors && ctors->hasInitializer() ? llvm::dyn_cast<llvm::ConstantArray>(ctors->getInitializer()) : nullptr;
  if (!array)
    return;
  for (const llvm::Use& u : array->operands()) {
    auto* entry = llvm::dyn_cast<llvm::ConstantStruct>(u.get());
    auto* ctor = entry ? llvm::dyn_cast<llvm::Function>(entry->getOperand(1)->stripPointerCasts()) : nullptr;
    if (!ctor || ctor->isDeclaration())
      continue;
    std::vector<llvm::CallInst*> drop;
    for (llvm::BasicBlock& bb : *ctor)
      for (llvm::Instruction& inst : bb)
        if (auto* call = llvm::dyn_cast<llvm::CallInst>(&inst))
          if (llvm::Function* f = call->getCalledFunction(); f && !f->isDeclaration() && touches(*f, declared))
            drop.push_back(call);
    for (llvm::CallInst* call : drop)
      call->eraseFromParent();
  }
}

void gatherInitializers(llvm::Module& m) {
  auto entries = [&](const char* list) {
    std::vector<std::pair<uint64_t, llvm::Function*>> fns;
    llvm::GlobalVariable* gv = m.getNamedGlobal(list);
    if (!gv)
      return fns;
    if (auto* array = llvm::dyn_cast_or_null<llvm::ConstantArray>(gv->hasInitializer() ? gv->getInitializer() : nullptr))
      for (const llvm::Use& u : array->operands()) {
        auto* entry = llvm::dyn_cast<llvm::ConstantStruct>(u.get());
        if (!entry || entry->getNumOperands() < 2)
          continue;
        auto* prio = llvm::dyn_cast<llvm::ConstantInt>(entry->getOperand(0));
        auto* fn = llvm::dyn_cast<llvm::Function>(entry->getOperand(1)->stripPointerCasts());
        if (prio && fn)
          fns.emplace_back(prio->getZExtValue(), fn);
      }
    gv->eraseFromParent();
    std::stable_sort(fns.begin(), fns.end(), [](auto& a, auto& b) { return a.first < b.first; });
    return fns;
  };
  auto ctors = entries("llvm.global_ctors");
  auto dtors = entries("llvm.global_dtors");
  if (ctors.empty() && dtors.empty())
    return;
  llvm::LLVMContext& ctx = m.getContext();
  auto* voidFn = llvm::FunctionType::get(llvm::Type::getVoidTy(ctx), false);
  auto* init = llvm::Function::Create(voidFn, llvm::GlobalValue::ExternalLinkage, "__orc_init_func.lcjit", m);
  llvm::IRBuilder<> b(llvm::BasicBlock::Create(ctx, "entry", init));
  // With line tables, a function of its own in them: the constructors inlined into it keep
  // their lines (a function without one gets no line table, whatever is inlined into it).
  if (m.debug_compile_units_begin() != m.debug_compile_units_end()) {
    llvm::DICompileUnit* unit = *m.debug_compile_units_begin();
    llvm::DIBuilder di(m, /*AllowUnresolved=*/false, unit);
    llvm::DISubprogram* sp = di.createFunction(
        unit->getFile(), init->getName(), init->getName(), unit->getFile(), 0,
        di.createSubroutineType(di.getOrCreateTypeArray({})), 0, llvm::DINode::FlagArtificial,
        llvm::DISubprogram::SPFlagDefinition);
    init->setSubprogram(sp);
    b.SetCurrentDebugLocation(llvm::DILocation::get(ctx, 0, 0, sp));
    di.finalize();
  }
  for (auto& [prio, fn] : ctors)
    b.CreateCall(fn->getFunctionType(), fn);
  if (!dtors.empty()) {
    llvm::FunctionCallee atexit = m.getOrInsertFunction(
        "atexit", llvm::FunctionType::get(b.getInt32Ty(), {llvm::PointerType::getUnqual(ctx)}, false));
    for (auto it = dtors.rbegin(); it != dtors.rend(); ++it)
      b.CreateCall(atexit, {it->second});
  }
  b.CreateRetVoid();
}

}  // namespace lcjit::jit
