// JIT addresses back to the model's source (CodeMap.h).
#include "jit/CodeMap.h"

#include "jit/ObjectCache.h"

#include <llvm/ADT/StringMap.h>
#include <llvm/DebugInfo/DWARF/DWARFContext.h>
#include <llvm/ExecutionEngine/JITLink/JITLink.h>
#include <llvm/Object/ObjectFile.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/Path.h>

#include <algorithm>

namespace lcjit::jit::detail {

namespace orc = llvm::orc;
namespace jitlink = llvm::jitlink;

struct CodeMap::Object {
  std::shared_ptr<const CachedObject> bytes;
  // Parsed on the first lookup.
  bool parsed = false;
  std::unique_ptr<llvm::object::ObjectFile> file;
  std::unique_ptr<llvm::DWARFContext> dwarf;
  llvm::StringMap<uint64_t> sectionOf;  // function name -> the index of its section
  llvm::StringMap<uint64_t> linkedAt;   // function name -> its address in memory

  // Where the linker put each section of the object (found through the functions in it). DWARF
  // is read as if the object had been loaded there: in a relocatable object every section
  // starts at 0, and the inlined calls at an address would be looked up in whichever function
  // of another section has code at the same offset.
  struct Placement : llvm::LoadedObjectInfo {
    std::map<uint64_t, uint64_t> loadAddress;  // section index -> address
    uint64_t getSectionLoadAddress(const llvm::object::SectionRef& sec) const override {
      auto it = loadAddress.find(sec.getIndex());
      return it == loadAddress.end() ? 0 : it->second;
    }
    std::unique_ptr<llvm::LoadedObjectInfo> clone() const override { return std::make_unique<Placement>(*this); }
  };
  Placement placement;

  void parse() {
    parsed = true;
    auto obj = llvm::object::ObjectFile::createObjectFile(
        llvm::MemoryBufferRef(bytes->object, "model object"));
    if (!obj) {
      llvm::consumeError(obj.takeError());
      return;
    }
    file = std::move(*obj);
    bool hasLines = false;
    for (const auto& section : file->sections())
      if (auto name = section.getName(); name && *name == ".debug_line") hasLines = true;
    if (!hasLines) return;
    for (const auto& sym : file->symbols()) {
      auto type = sym.getType();
      auto name = sym.getName();
      auto section = sym.getSection();
      auto value = sym.getValue();
      if (!type || !name || !section || !value || *type != llvm::object::SymbolRef::ST_Function ||
          *section == file->section_end()) {
        if (!type) llvm::consumeError(type.takeError());
        if (!name) llvm::consumeError(name.takeError());
        if (!section) llvm::consumeError(section.takeError());
        if (!value) llvm::consumeError(value.takeError());
        continue;
      }
      sectionOf[*name] = (*section)->getIndex();
      if (auto at = linkedAt.find(*name); at != linkedAt.end())
        placement.loadAddress[(*section)->getIndex()] = at->second - *value;
    }
    auto quiet = [](llvm::Error e) { llvm::consumeError(std::move(e)); };
    dwarf = llvm::DWARFContext::create(*file, llvm::DWARFContext::ProcessDebugRelocations::Process, &placement, "",
                                       quiet, quiet);
  }
};

CodeMap::CodeMap() = default;
CodeMap::~CodeMap() = default;

void CodeMap::expect(orc::JITDylib& jd, std::shared_ptr<const CachedObject> object) {
  std::lock_guard<std::mutex> lock(mutex_);
  expected_[&jd] = std::move(object);
}

void CodeMap::modifyPassConfig(orc::MaterializationResponsibility& mr, jitlink::LinkGraph& g,
                               jitlink::PassConfiguration& config) {
  std::shared_ptr<const CachedObject> object;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = expected_.find(&mr.getTargetJITDylib());
    // Only the model's own object: ORC links its support modules into the same JITDylib, and
    // their graphs are named after their modules, not after the JITDylib.
    if (it == expected_.end() || g.getName() != mr.getTargetJITDylib().getName()) return;
    object = std::move(it->second);
    expected_.erase(it);
  }
  // The object refers to its local functions through their sections' symbols, so the linker
  // would drop their own (named) symbols as unused: keep them, they name the code for lookups.
  config.PrePrunePasses.push_back([](jitlink::LinkGraph& graph) -> llvm::Error {
    for (jitlink::Symbol* sym : graph.defined_symbols())
      if (sym->hasName() && sym->isCallable()) sym->setLive(true);
    return llvm::Error::success();
  });
  // Once the linker has placed the blocks: every function's final address.
  config.PostAllocationPasses.push_back([this, &mr, object](jitlink::LinkGraph& graph) -> llvm::Error {
    auto entry = std::make_unique<Object>();
    entry->bytes = object;
    std::vector<Range> found;
    for (jitlink::Symbol* sym : graph.defined_symbols()) {
      if (!sym->hasName() || sym->getSize() == 0 ||
          !(unsigned(sym->getBlock().getSection().getMemProt()) & unsigned(orc::MemProt::Exec)))
        continue;
      uint64_t start = sym->getAddress().getValue();
      found.push_back({start, start + sym->getSize(), entry.get(), sym->getName().str()});
      entry->linkedAt[sym->getName()] = start;
    }
    return mr.withResourceKeyDo([&](orc::ResourceKey key) {
      std::lock_guard<std::mutex> lock(mutex_);
      objects_[key].push_back(std::move(entry));
      ranges_.insert(ranges_.end(), found.begin(), found.end());
      std::sort(ranges_.begin(), ranges_.end(), [](const Range& a, const Range& b) { return a.start < b.start; });
    });
  });
}

llvm::Error CodeMap::notifyFailed(orc::MaterializationResponsibility& mr) {
  std::lock_guard<std::mutex> lock(mutex_);
  expected_.erase(&mr.getTargetJITDylib());
  return llvm::Error::success();
}

llvm::Error CodeMap::notifyRemovingResources(orc::JITDylib& jd, orc::ResourceKey key) {
  std::lock_guard<std::mutex> lock(mutex_);
  expected_.erase(&jd);
  auto it = objects_.find(key);
  if (it == objects_.end()) return llvm::Error::success();
  ranges_.erase(std::remove_if(ranges_.begin(), ranges_.end(),
                               [&](const Range& r) {
                                 return std::any_of(it->second.begin(), it->second.end(),
                                                    [&](const auto& o) { return o.get() == r.object; });
                               }),
                ranges_.end());
  objects_.erase(it);
  return llvm::Error::success();
}

void CodeMap::notifyTransferringResources(orc::JITDylib&, orc::ResourceKey dst, orc::ResourceKey src) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = objects_.find(src);
  if (it == objects_.end()) return;
  auto& to = objects_[dst];
  for (auto& o : it->second) to.push_back(std::move(o));
  objects_.erase(src);
}

namespace {
std::string normalised(llvm::StringRef path) {
  llvm::SmallString<256> p(path);
  llvm::sys::path::remove_dots(p, /*remove_dot_dot=*/true);
  return p.str().str();
}
}  // namespace

void CodeMap::addLibraryDirs(const std::vector<std::string>& dirs) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::string& d : dirs) {
    std::string n = normalised(d);
    if (n.empty()) continue;
    if (n.back() != '/') n += '/';
    if (std::find(libraryDirs_.begin(), libraryDirs_.end(), n) == libraryDirs_.end()) libraryDirs_.push_back(n);
  }
}

bool CodeMap::inLibrary(const std::string& absolutePath) const {
  std::string p = normalised(absolutePath);
  return std::any_of(libraryDirs_.begin(), libraryDirs_.end(),
                     [&](const std::string& d) { return llvm::StringRef(p).starts_with(d); });
}

std::vector<SourcePlace> CodeMap::placesAt(uint64_t address, bool returnAddress) const {
  if (returnAddress) --address;  // inside the call instruction, not after it
  std::lock_guard<std::mutex> lock(mutex_);
  auto after = std::upper_bound(ranges_.begin(), ranges_.end(), address,
                                [](uint64_t a, const Range& r) { return a < r.start; });
  if (after == ranges_.begin()) return {};
  const Range& r = *std::prev(after);
  if (address >= r.end) return {};
  Object& o = *r.object;
  if (!o.parsed) o.parse();
  if (!o.dwarf) return {};
  auto section = o.sectionOf.find(r.function);
  if (section == o.sectionOf.end()) return {};
  llvm::object::SectionedAddress at{address, section->second};
  llvm::DIInliningInfo frames = o.dwarf->getInliningInfoForAddress(
      at, llvm::DILineInfoSpecifier(llvm::DILineInfoSpecifier::FileLineInfoKind::AbsoluteFilePath));
  std::vector<SourcePlace> places;
  for (uint32_t i = 0; i < frames.getNumberOfFrames(); ++i) {
    const llvm::DILineInfo& f = frames.getFrame(i);
    // Not the generated tables ("<lcjit: generated …>", made absolute by the compile's folder).
    if (f.FileName == llvm::DILineInfo::BadString || f.Line == 0 || f.FileName.find("/<") != std::string::npos ||
        inLibrary(f.FileName))
      continue;
    llvm::SmallString<256> file(f.FileName);
    llvm::sys::fs::make_absolute(file);
    places.push_back({normalised(file), f.Line, f.Column});
  }
  return places;
}

}  // namespace lcjit::jit::detail
