// The level-0 PCH's support code (-fpch-codegen): compiled once from the PCH, cut into parts that
// ORC links on first use, cached beside the PCH, and loaded into one JITDylib per PCH.
#include "support/CacheFiles.h"
#include "jit/CompilerImpl.h"
#include "jit/IRRewrites.h"

#include <llvm/Demangle/Demangle.h>
#include <llvm/ExecutionEngine/Orc/ObjectFileInterface.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Transforms/Utils/Cloning.h>

#include <algorithm>
#include <map>
#include <optional>
#include <utility>

namespace lcjit::jit {

namespace {

// Splits the support module into parts of `perPart` definitions, in order of their demangled
// names so that related functions (all of __lc_emit_*, one class's members) share a part. Each
// part is one object file and ORC links an object only when a symbol of it is first looked up,
// so a model pays for the parts it uses; the whole (~2,000 functions, mostly libstdc++ templates
// the header instantiated) took ~15 ms to link. Locals become hidden globals so that parts can
// reach each other's, and COMDATs go: each definition exists once.
std::vector<std::unique_ptr<llvm::Module>> splitIntoParts(llvm::Module& m, size_t perPart) {
  for (llvm::GlobalValue& gv : m.global_values()) {
    if (gv.getName().starts_with("llvm."))
      continue;
    if (auto* go = llvm::dyn_cast<llvm::GlobalObject>(&gv))
      go->setComdat(nullptr);
    if (!gv.hasName())
      gv.setName("lcjit.support.unnamed");
    if (gv.hasLocalLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
      gv.setVisibility(llvm::GlobalValue::HiddenVisibility);
    } else if (gv.hasWeakLinkage() || gv.hasLinkOnceLinkage()) {
      gv.setLinkage(llvm::GlobalValue::ExternalLinkage);
    }
  }
  m.getComdatSymbolTable().clear();
  std::vector<std::pair<std::string, const llvm::GlobalObject*>> defs;
  for (const llvm::GlobalObject& go : m.global_objects())
    if (!go.isDeclaration() && !go.getName().starts_with("llvm."))
      defs.emplace_back(llvm::demangle(go.getName().str()), &go);
  std::sort(defs.begin(), defs.end());
  std::map<const llvm::GlobalValue*, size_t> partOf;
  for (size_t i = 0; i < defs.size(); ++i)
    partOf[defs[i].second] = i / perPart;
  for (const llvm::GlobalAlias& a : m.aliases())
    if (const llvm::GlobalObject* target = a.getAliaseeObject(); target && partOf.count(target))
      partOf[&a] = partOf[target];
  std::vector<std::unique_ptr<llvm::Module>> parts;
  for (size_t p = 0; p * perPart < defs.size(); ++p) {
    llvm::ValueToValueMapTy map;
    parts.push_back(llvm::CloneModule(m, map, [&](const llvm::GlobalValue* gv) {
      auto it = partOf.find(gv);
      return it != partOf.end() && it->second == p;
    }));
  }
  return parts;
}

// The support objects' cache file: "lcjit-support 1\n", then per object "SIZE\n" and its bytes.
std::string serializeParts(const std::vector<std::string>& parts) {
  std::string out = "lcjit-support 1\n";
  for (const std::string& part : parts)
    out += std::to_string(part.size()) + "\n" + part;
  return out;
}

std::optional<std::vector<std::string>> deserializeParts(llvm::StringRef in) {
  if (!in.consume_front("lcjit-support 1\n"))
    return std::nullopt;
  std::vector<std::string> parts;
  while (!in.empty()) {
    auto [size, rest] = in.split('\n');
    size_t n = 0;
    if (size.getAsInteger(10, n) || rest.size() < n)
      return std::nullopt;
    parts.push_back(rest.take_front(n).str());
    in = rest.drop_front(n);
  }
  return parts;
}

}  // namespace

std::shared_ptr<Compiler::Impl::Support> Compiler::Impl::startSupport(const LevelSetup& L, const std::string& pchPath) {
  std::lock_guard<std::mutex> lock(supportMutex);
  auto& support = supports[pchPath];
  if (!support) {
    support = std::make_shared<Support>();
    support->ready = std::async(std::launch::async, [this, s = support.get(), base = L.base, pchPath,
                                                     number = supportsStarted++] {
                       auto jd = loadSupport(base, pchPath, number, s->note);
                       if (jd)
                         s->jd = *jd;
                       else
                         s->error = llvm::toString(jd.takeError());
                     }).share();
  }
  return support;
}

llvm::Expected<orc::JITDylib*> Compiler::Impl::supportDylib(const LevelSetup& L, const std::string& pchPath,
                                                            std::vector<std::string>* notes) {
  std::shared_ptr<Support> support = startSupport(L, pchPath);
  support->ready.wait();
  if (notes) {
    std::lock_guard<std::mutex> lock(supportMutex);
    if (!support->note.empty())
      notes->push_back(std::move(support->note));
    support->note.clear();
  }
  if (!support->jd)
    return llvm::createStringError(support->error);
  return support->jd;
}

llvm::Expected<orc::JITDylib*> Compiler::Impl::loadSupport(std::shared_ptr<clang::CompilerInvocation> base,
                                                           const std::string& pchPath, unsigned number,
                                                           std::string& note) {
  std::string cachePath = pchPath + ".o";
  std::optional<std::vector<std::string>> parts;
  support::CheckedRead file = support::readCheckedCacheFile(cachePath);
  if (!file.problem.empty())
    note = cacheNote(cachePath, file.problem);
  if (file.bytes)
    parts = deserializeParts(*file.bytes);
  bool fresh = !parts;
  if (fresh) {
    // The PCH as the input: clang emits what it marked for codegen (as `clang -c x.pch`).
    auto inv = std::make_shared<clang::CompilerInvocation>(*base);
    auto& fo = inv->getFrontendOpts();
    fo.Inputs.clear();
    fo.Inputs.emplace_back(pchPath, clang::InputKind(clang::Language::CXX, clang::InputKind::Precompiled));
    fo.OutputFile.clear();
    fo.DisableFree = false;
    inv->getCodeGenOpts().MainFileName = pchPath;
    frontend::DiagCollector dc;
    llvm::LLVMContext ctx;
    clang::EmitLLVMOnlyAction action(&ctx);
    std::unique_ptr<llvm::Module> module;
    if (executeClang(inv, action, dc))
      module = action.takeModule();
    if (!module)
      return llvm::createStringError("lcjit: cannot compile the runtime header's support code from " + pchPath + ":\n" +
                       trimTrailingNewlines(dc.text));
    gatherInitializers(*module);
    // always_inline callees (libstdc++'s allocators) go
    if (auto err = state->codegen[0].optimize(*module, 0, jtmb, llvm::CodeGenOptLevel::None))
      return std::move(err);
    parts.emplace();
    for (auto& part : splitIntoParts(*module, kSupportPartSize)) {
      auto object = emitObject(*part, 0);
      if (!object)
        return object.takeError();
      parts->push_back(std::move(*object));
    }
    support::writeCheckedCacheFile(cachePath, serializeParts(*parts));  // failing only costs a later build
  }

  auto& J = *state->jit;
  std::unique_lock<std::mutex> jitLock(state->mutex);
  auto jd = J.createJITDylib("lcjit.support." + std::to_string(number));
  if (!jd)
    return jd.takeError();
  orc::JITDylibSearchOrder order;
  state->appendRuntime(order);
  jd->setLinkOrder(std::move(order), /*LinkAgainstThisJITDylibFirst=*/true);
  orc::SymbolLookupSet oneOfEach;
  for (size_t i = 0; i < parts->size(); ++i) {
    auto buffer = llvm::MemoryBuffer::getMemBufferCopy((*parts)[i], cachePath + "#" + std::to_string(i));
    if (fresh) {
      auto symbols = orc::getObjectFileInterface(J.getExecutionSession(), buffer->getMemBufferRef());
      if (!symbols)
        return symbols.takeError();
      if (!symbols->SymbolFlags.empty())
        oneOfEach.add(symbols->SymbolFlags.begin()->first);
    }
    if (auto err = J.addObjectFile(*jd, std::move(buffer))) {
      if (fresh)
        return std::move(err);
      // A cached part that will not load: build the support code afresh, once.
      std::string why = llvm::toString(std::move(err));
      if (auto e = J.getExecutionSession().removeJITDylib(*jd))
        llvm::consumeError(std::move(e));
      jitLock.unlock();
      llvm::sys::fs::remove(cachePath);
      note = cacheNote(cachePath, "it would not load (" + why + ")");
      return loadSupport(std::move(base), pchPath, number, note);
    }
  }
  // A freshly built support links every part once, so that a problem shows here rather than as
  // a bad call from the first model that uses the part.
  state->takeSessionErrors();
  if (fresh) {
    if (auto linked = J.getExecutionSession().lookup(
            orc::makeJITDylibSearchOrder(&*jd, orc::JITDylibLookupFlags::MatchAllSymbols), std::move(oneOfEach));
        !linked) {
      std::string cause = trimTrailingNewlines(state->takeSessionErrors());
      llvm::consumeError(linked.takeError());
      llvm::sys::fs::remove(cachePath);
      return llvm::createStringError("lcjit: cannot link the runtime header's support code: " + cause);
    }
  }
  if (auto err = J.initialize(*jd))
    return std::move(err);
  return &*jd;
}

}  // namespace lcjit::jit
