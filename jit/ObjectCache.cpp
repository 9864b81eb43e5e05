// The object cache of ObjectCache.h: its key, its file format, and the in-memory and on-disk
// stores of Compiler::Impl.
#include "jit/ObjectCache.h"
#include "support/CacheFiles.h"
#include "jit/CompilerImpl.h"

#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/SHA256.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <optional>
#include <utility>

namespace lcjit::jit {

namespace {

// Cache files: "lcjit-object 3\n", the anchor line, a count line, "SIZE NAME" per state global,
// a count line, "NAME FILE:LINE:COL" per declared variable, then the object bytes.
std::string serialize(const CachedObject& c) {
  std::string out = "lcjit-object 3\n" + c.anchor + "\n" + std::to_string(c.stateNames.size()) + "\n";
  for (size_t i = 0; i < c.stateNames.size(); ++i)
    out += std::to_string(c.stateSizes[i]) + " " + c.stateNames[i] + "\n";
  std::string places;
  size_t n = 0;
  for (const auto& [name, place] : c.declaredAt)
    if (place.find('\n') == std::string::npos) {  // a file name with a newline is left out
      places += name + " " + place + "\n";
      ++n;
    }
  return out + std::to_string(n) + "\n" + places + c.object;
}

std::optional<CachedObject> deserialize(llvm::StringRef text) {
  CachedObject c;
  auto line = [&]() -> std::optional<llvm::StringRef> {
    size_t nl = text.find('\n');
    if (nl == llvm::StringRef::npos)
      return std::nullopt;
    llvm::StringRef l = text.substr(0, nl);
    text = text.substr(nl + 1);
    return l;
  };
  auto magic = line(), anchor = line(), count = line();
  size_t n = 0;
  if (!magic || *magic != "lcjit-object 3" || !anchor || !count || count->getAsInteger(10, n))
    return std::nullopt;
  c.anchor = anchor->str();
  for (size_t i = 0; i < n; ++i) {
    auto entry = line();
    uint64_t size = 0;
    if (!entry)
      return std::nullopt;
    auto [number, name] = entry->split(' ');
    if (number.getAsInteger(10, size) || name.empty())
      return std::nullopt;
    c.stateSizes.push_back(size);
    c.stateNames.push_back(name.str());
  }
  auto places = line();
  if (!places || places->getAsInteger(10, n))
    return std::nullopt;
  for (size_t i = 0; i < n; ++i) {
    auto entry = line();
    if (!entry)
      return std::nullopt;
    auto [name, place] = entry->split(' ');
    if (name.empty() || place.empty())
      return std::nullopt;
    c.declaredAt[name.str()] = place.str();
  }
  c.object = text.str();
  return c;
}

}  // namespace

std::string objectKey(llvm::StringRef pchPath, llvm::StringRef unitKind, llvm::StringRef bufferName,
                      llvm::StringRef source, const std::set<std::string>& shared, int level) {
  llvm::SHA256 h;
  // This build of lcjit's code generation too: an object made by an older one (other IR
  // passes) is not this one's. jit/CMakeLists.txt rebuilds this file whenever any file of the
  // JIT changes, so that its build time stands for them all.
  static constexpr const char* kBuild = __DATE__ " " __TIME__;
  for (llvm::StringRef part : {llvm::StringRef(kBuild), pchPath, unitKind, bufferName, source}) {
    h.update(part);
    h.update(llvm::StringRef("\0", 1));
  }
  for (const std::string& name : shared) {  // which globals are declarations
    h.update(name);
    h.update(llvm::StringRef("\0", 1));
  }
  return llvm::toHex(h.final(), /*LowerCase=*/true).substr(0, 32) + "-O" + std::to_string(level);
}

std::shared_ptr<const CachedObject> Compiler::Impl::findObject(const std::string& key, bool& fromDisk,
                                                              std::string& problem) {
  fromDisk = false;
  {
    std::lock_guard<std::mutex> lock(objectsMutex);
    for (auto& [k, object] : objects)
      if (k == key)
        return object;
  }
  support::CheckedRead file = support::readCheckedCacheFile(objectPath(key));
  problem = file.problem;
  if (!file.bytes)
    return nullptr;
  auto object = deserialize(*file.bytes);
  if (!object)
    return nullptr;  // a foreign file: compile again (and overwrite it)
  fromDisk = true;
  auto shared = std::make_shared<const CachedObject>(std::move(*object));
  keepObject(key, shared);
  return shared;
}

void Compiler::Impl::keepObject(const std::string& key, std::shared_ptr<const CachedObject> object) {
  std::lock_guard<std::mutex> lock(objectsMutex);
  std::erase_if(objects, [&](auto& e) { return e.first == key; });
  objects.emplace_back(key, std::move(object));
  if (objects.size() > kObjectsInMemory)
    objects.erase(objects.begin());
}

void Compiler::Impl::dropObject(const std::string& key) {
  {
    std::lock_guard<std::mutex> lock(objectsMutex);
    std::erase_if(objects, [&](auto& e) { return e.first == key; });
  }
  llvm::sys::fs::remove(objectPath(key));
}

void Compiler::Impl::storeObject(const std::string& key, const CachedObject& object) {
  static std::atomic<unsigned> stores{0};
  namespace fs = std::filesystem;
  const std::string dir = objectsDir();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!support::writeCheckedCacheFile(objectPath(key), serialize(object)))
    return;
  if (stores++ % 32 != 0)
    return;
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".o")
      files.emplace_back(it->last_write_time(ec), it->path());
  if (files.size() <= kObjectsOnDisk)
    return;
  std::sort(files.begin(), files.end());
  for (size_t i = 0; i + kObjectsOnDisk < files.size(); ++i)
    fs::remove(files[i].second, ec);
}

}  // namespace lcjit::jit
