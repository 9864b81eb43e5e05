// An object's static data (StaticData.h), from its ELF sections and symbols.
#include "jit/StaticData.h"

#include <llvm/BinaryFormat/ELF.h>
#include <llvm/Demangle/Demangle.h>
#include <llvm/Object/ELFObjectFile.h>

namespace lcjit::jit {

ObjectData dataOf(const CachedObject& object) {
  ObjectData d;
  auto file = llvm::object::ObjectFile::createObjectFile(llvm::MemoryBufferRef(object.object, "model object"));
  if (!file) {
    llvm::consumeError(file.takeError());
    return d;  // the link says what is wrong with it
  }
  auto* elf = llvm::dyn_cast<llvm::object::ELFObjectFileBase>(file->get());
  if (!elf)
    return d;
  // Sections loaded into memory that are not code (nor thread-local templates, which are not
  // placed as they are): data, zero fill, constants, unwind tables.
  auto counted = [](const llvm::object::ELFSectionRef& s) {
    const uint64_t flags = s.getFlags();
    return (flags & llvm::ELF::SHF_ALLOC) && !(flags & llvm::ELF::SHF_EXECINSTR) && !(flags & llvm::ELF::SHF_TLS);
  };
  for (const llvm::object::ELFSectionRef s : elf->sections())
    if (counted(s))
      d.data.bytes += s.getSize();
  std::string largest;
  for (const llvm::object::ELFSymbolRef sym : elf->symbols()) {
    auto section = sym.getSection();
    auto name = sym.getName();
    if (!section || !name || *section == elf->section_end() || sym.getELFType() != llvm::ELF::STT_OBJECT ||
        !counted(llvm::object::ELFSectionRef(**section))) {
      if (!section) llvm::consumeError(section.takeError());
      if (!name) llvm::consumeError(name.takeError());
      continue;
    }
    if ((*section)->isBSS())
      d.zeroFilled.insert(name->str());
    if (sym.getSize() > d.data.largestBytes) {
      d.data.largestBytes = sym.getSize();
      largest = name->str();
    }
  }
  if (!largest.empty()) {
    d.data.largest = llvm::demangle(largest);
    if (auto it = object.declaredAt.find(largest); it != object.declaredAt.end())
      d.data.declaredAt = it->second;
  }
  return d;
}

}  // namespace lcjit::jit
