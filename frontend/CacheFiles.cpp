// See CacheFiles.h.
#include "frontend/CacheFiles.h"

#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/raw_ostream.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace lcjit::frontend {

bool writeCacheFile(const std::string& path, llvm::StringRef bytes) {
  llvm::SmallString<256> tmp;
  int fd = -1;
  if (llvm::sys::fs::createUniqueFile(path + ".tmp-%%%%%%%%", fd, tmp))
    return false;
  llvm::raw_fd_ostream out(fd, /*shouldClose=*/true);
  out << bytes;
  out.close();
  if (out.has_error() || llvm::sys::fs::rename(tmp, path)) {
    out.clear_error();
    llvm::sys::fs::remove(tmp);
    return false;
  }
  return true;
}

void hashDirectoryTree(llvm::SHA256& h, const std::string& dir) {
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
      if (auto buf = llvm::MemoryBuffer::getFile(p, /*IsText=*/false, /*RequiresNullTerminator=*/false)) {
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
}

}  // namespace lcjit::frontend
