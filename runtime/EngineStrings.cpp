// The string as files: its text (.str, `-out x.str`), lpfg's `-dtf` turtle text, and binary
// strings (.strb: lpfg's in-memory layout, no header), read back only after every record is
// checked. Text goes out a megabyte at a time (ChunkedText), never held whole.
//
// Sections, in order (each begins with a `// ----` rule): Text (ChunkedText, writeTurtleText,
// text, writeText, writeTextFile) · Binary strings (writeBinary, readBinary).
#include <sstream>
#include <string_view>

#include "runtime/Engine.h"
#include "support/ReplacingFile.h"
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// Text

namespace {
// Text made in `text` and written to a stream a megabyte at a time (spill()), the rest when it
// goes: a string's text need not be held whole.
struct ChunkedText {
  static constexpr size_t kChunk = size_t(1) << 20;
  explicit ChunkedText(std::ostream& out) : out(out) { text.reserve(kChunk + 4096); }
  ~ChunkedText() { out.write(text.data(), (std::streamsize)text.size()); }
  void spill() {
    if (text.size() < kChunk) return;
    out.write(text.data(), (std::streamsize)text.size());
    text.clear();
  }
  std::ostream& out;
  std::string text;
};
}  // namespace

llvm::Error Engine::writeTurtleText(std::ostream& out, int vgroup) {
  ChunkedText chunks(out);
  return interpret([&](const char*) { chunks.spill(); }, nullptr, &chunks.text, vgroup);  // after each module
}

std::string Engine::text(const ModuleBuffer& str) const {
  std::ostringstream out;
  writeText(str, out);
  return std::move(out).str();
}

void Engine::writeText(const ModuleBuffer& str, std::ostream& out) const {
  ChunkedText chunks(out);
  for (size_t p = 0; p < str.size() && out; p = modules_.next(str.data(), p)) {
    modules_.format(str.data() + p, chunks.text);
    chunks.text += '\n';
    chunks.spill();
  }
}

llvm::Error Engine::writeTextFile(const std::string& path) const {
  return support::writeWholeFile(path, [&](std::ostream& out) {
    writeText(string_, out);
    return llvm::Error::success();
  });
}

// ---------------------------------------------------------------------------------------------
// Binary strings

llvm::Error Engine::writeBinary(const std::string& path) const {
  return support::writeWholeFile(path, llvm::StringRef(string_.data(), string_.size()));
}

llvm::Error Engine::readBinary(const std::string& path) {
  auto file = textfile::readFile(path);
  if (!file) return file.takeError();
  const llvm::StringRef bytes = (*file)->getBuffer();
  // Validate every record before replacing the string.
  size_t p = 0;
  while (p < bytes.size()) {
    if (bytes.size() - p < 4)
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: truncated module at byte %zu", path.c_str(), p);
    __lc_ModuleId id = ModuleTable::idAt(bytes.data() + p);
    if (!modules_.valid(id))
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: unknown module id %u at byte %zu", path.c_str(),
                                     (unsigned)id, p);
    size_t size = modules_.recordSize(id);
    if (bytes.size() - p < size || ModuleTable::idAt(bytes.data() + p + size - 2) != id)
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: corrupt module '%s' at byte %zu", path.c_str(),
                                     modules_.info(id).name, p);
    // A pointer (Label's text, a T* parameter) written by another run points into that run's
    // memory: the turtle or model code would follow it into whatever is there now (found by
    // fuzz_strb). A struct or typedef hiding a pointer is not seen here.
    const __lc_ModuleInfo& info = modules_.info(id);
    for (uint32_t i = 0; i < info.nFields; ++i) {
      const __lc_Field& f = info.fields[i];
      std::string_view type = f.typeName ? f.typeName : "";
      while (!type.empty() && type.back() == ' ') type.remove_suffix(1);
      if (f.kind == __lc_FK_Text || (!type.empty() && type.back() == '*'))
        return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                       "%s: error: module '%s' at byte %zu has a pointer parameter (%s), which a binary "
                                       "string cannot carry from one run to another",
                                       path.c_str(), info.name, p, f.kind == __lc_FK_Text ? "const char*" : f.typeName);
    }
    p += size;
  }
  forgetCount();
  forgetOrigins();
  string_.clear();
  string_.append(bytes.data(), bytes.size());
  return llvm::Error::success();
}

}  // namespace lcjit::runtime
