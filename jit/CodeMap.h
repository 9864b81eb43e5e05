// Where each piece of loaded model code came from: a JIT address back to the file, line and
// column of the L+C statement it was compiled from, through the object's DWARF line tables
// (model code is compiled with -gline-tables-only under the rewriter's #line directives). A fault
// names the statement that failed with it (docs/faults.md).
//
// How: a JITLink plugin notes, for each object linked, the address range of every function it
// defines; the object's bytes are kept beside them (shared with the object cache). A lookup finds
// the function holding the address, turns it into that function's section and offset in the
// object, and asks DWARF there (parsed on the first lookup in that object, not at load: loading
// stays as fast as it was).
#pragma once

#include <llvm/ExecutionEngine/Orc/ObjectLinkingLayer.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lcjit::jit {

struct CachedObject;

// A place in the source; `file` is an absolute path.
struct SourcePlace {
  std::string file;
  unsigned line = 0;
  unsigned column = 0;  // 0: not known
};

namespace detail {

class CodeMap : public llvm::orc::ObjectLinkingLayer::Plugin {
 public:
  CodeMap();
  ~CodeMap() override;

  // The next object linked into `jd` is `object` (call before adding it): its functions are
  // mapped. Objects linked without one (ORC's support code) are not.
  void expect(llvm::orc::JITDylib& jd, std::shared_ptr<const CachedObject> object);

  // Folders whose files are not the model's: lcjit's runtime header and the system's headers
  // (the C++ library's code inlined into model code).
  void addLibraryDirs(const std::vector<std::string>& dirs);

  // The source of the code at `address` in the model's own files, innermost inlined call first;
  // empty when the address is not in mapped model code or its object has no line table.
  // `returnAddress`: the address is where a call returns to, so the call before it is meant.
  std::vector<SourcePlace> placesAt(uint64_t address, bool returnAddress) const;

  void modifyPassConfig(llvm::orc::MaterializationResponsibility& mr, llvm::jitlink::LinkGraph& g,
                        llvm::jitlink::PassConfiguration& config) override;
  llvm::Error notifyFailed(llvm::orc::MaterializationResponsibility& mr) override;
  llvm::Error notifyRemovingResources(llvm::orc::JITDylib& jd, llvm::orc::ResourceKey key) override;
  void notifyTransferringResources(llvm::orc::JITDylib& jd, llvm::orc::ResourceKey dst,
                                   llvm::orc::ResourceKey src) override;

 private:
  struct Object;  // one linked object: its bytes, its functions, its DWARF once asked
  struct Range {
    uint64_t start, end;
    Object* object;
    std::string function;  // the linker's name of the function holding [start, end)
  };
  mutable std::mutex mutex_;
  std::map<llvm::orc::JITDylib*, std::shared_ptr<const CachedObject>> expected_;
  std::map<llvm::orc::ResourceKey, std::vector<std::unique_ptr<Object>>> objects_;
  std::vector<Range> ranges_;  // by start
  std::vector<std::string> libraryDirs_;  // normalised, each ending in '/'
  bool inLibrary(const std::string& absolutePath) const;
};

}  // namespace detail
}  // namespace lcjit::jit
