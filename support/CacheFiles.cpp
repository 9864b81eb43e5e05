// See CacheFiles.h.
#include "support/CacheFiles.h"

#include "support/InputFile.h"
#include "support/ReplacingFile.h"

#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/BLAKE3.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/raw_ostream.h>

#include <llvm/Support/Path.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

namespace lcjit::support {

bool writeCacheFile(const std::string& path, llvm::StringRef bytes) {
  if (llvm::Error e = writeWholeFile(path, bytes)) {
    llvm::consumeError(std::move(e));
    return false;
  }
  return true;
}

namespace {
constexpr llvm::StringLiteral kChecked = "lcjit-sha256 ";
std::string sha256Hex(llvm::StringRef bytes) { return llvm::toHex(llvm::SHA256::hash(llvm::arrayRefFromStringRef(bytes)), true); }
}  // namespace

bool writeCheckedCacheFile(const std::string& path, llvm::StringRef bytes) {
  return writeCacheFile(path, (kChecked + sha256Hex(bytes) + "\n").str() + bytes.str());
}

CheckedRead readCheckedCacheFile(const std::string& path) {
  CheckedRead r;
  auto file = readInputFile(path, /*nullTerminated=*/false);
  if (!file) return r;
  llvm::StringRef text = (*file)->getBuffer();
  // Another version's file (no checksum line): not loaded, and overwritten by the next store.
  if (!text.consume_front(kChecked)) return r;
  auto [sum, bytes] = text.split('\n');
  if (sum.size() == 64 && sum == sha256Hex(bytes)) {
    r.bytes = bytes.str();
    return r;
  }
  r.problem = "it is damaged (its checksum does not match)";
  llvm::sys::fs::remove(path);
  return r;
}

llvm::Error useAsCacheFolder(const std::string& dir) {
  auto refuse = [&](const std::string& why) { return llvm::createStringError("the cache folder '" + dir + "' " + why); };
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0) {
    if (errno != ENOENT) return refuse(std::string("cannot be read: ") + std::strerror(errno));
    std::string parent = llvm::sys::path::parent_path(dir).str();
    if (!parent.empty())
      if (std::error_code ec = llvm::sys::fs::create_directories(parent))
        return refuse("cannot be made: " + ec.message());
    // Created here, so it is ours and private; another process may have made it meanwhile.
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) return refuse(std::string("cannot be made: ") + std::strerror(errno));
    if (::lstat(dir.c_str(), &st) != 0) return refuse(std::string("cannot be read: ") + std::strerror(errno));
  }
  if (S_ISLNK(st.st_mode)) return refuse("is a symbolic link");
  if (!S_ISDIR(st.st_mode)) return refuse("is not a folder");
  if (st.st_uid != ::geteuid()) return refuse("belongs to another user (uid " + std::to_string(st.st_uid) + ")");
  if (st.st_mode & (S_IWGRP | S_IWOTH)) return refuse("is writable by others (chmod go-w to use it)");
  return llvm::Error::success();
}

llvm::Expected<std::string> privateCacheFolder() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/lcjit-cache-XXXXXX";
  if (!::mkdtemp(pattern.data()))  // mode 0700, a name no one can guess
    return llvm::createStringError("cannot make a private cache folder from '" + pattern + "': " + std::strerror(errno));
  return pattern;
}

void removeCacheFolder(const std::string& dir) {
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

void hashDirectoryTree(llvm::SHA256& out, const std::string& dir) {
  // BLAKE3 over the contents (several times SHA-256's speed: this runs on every start), its
  // digest into `out`.
  llvm::BLAKE3 h;
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    std::error_code ec2;
    if (it->is_regular_file(ec2))
      files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  // A runtime header in a huge directory should not make every start slow; past this many
  // bytes, size + mtime stand in for content (clang's own PCH validation checks those too).
  uint64_t budget = 64ull << 20;
  for (const auto& f : files) {
    std::string p = f.string();
    h.update(p);
    h.update(llvm::StringRef("\0", 1));
    std::error_code ec2;
    auto size = fs::file_size(f, ec2);
    if (!ec2 && size <= budget) {
      if (auto buf = readInputFile(p, /*nullTerminated=*/false)) {
        h.update((*buf)->getBuffer());
        budget -= size;
        continue;
      }
    }
    auto t = fs::last_write_time(f, ec2);
    std::string meta = std::to_string(ec2 ? 0 : size) + ":" +
                       std::to_string(ec2 ? 0 : t.time_since_epoch().count());
    h.update(meta);
  }
  out.update(h.final());
}

std::string fileStamp(llvm::StringRef file, int64_t* changed) {
  struct stat st {};
  if (::stat(file.str().c_str(), &st) != 0)
    return "";
  int64_t m = int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
  int64_t c = int64_t(st.st_ctim.tv_sec) * 1'000'000'000 + st.st_ctim.tv_nsec;
  if (changed)
    *changed = std::max(m, c);
  return std::to_string(st.st_size) + " " + std::to_string(m) + " " + std::to_string(c);
}

std::optional<std::string> stampLines(const std::vector<std::string>& files, int64_t notAfter) {
  std::string out;
  for (const std::string& f : files) {
    int64_t changed = 0;
    std::string st = fileStamp(f, &changed);
    if (st.empty() || changed > notAfter)
      return std::nullopt;
    out += "// F " + st + " " + f + "\n";
  }
  return out;
}

bool stampsHold(llvm::StringRef text, llvm::StringRef follows, llvm::StringRef* rest) {
  while (text.starts_with("// F ")) {
    auto [line, after] = text.split('\n');
    text = after;
    line.consume_front("// F ");
    auto [size, line1] = line.split(' ');
    auto [mtime, line2] = line1.split(' ');
    auto [ctime, file] = line2.split(' ');
    if (fileStamp(file) != (size + " " + mtime + " " + ctime).str())
      return false;
  }
  if (!text.consume_front(follows))
    return false;
  if (rest)
    *rest = text;
  return true;
}

}  // namespace lcjit::support
