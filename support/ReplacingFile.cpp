// ReplacingFile (see the header): a unique hidden name beside the target, renamed over it.
#include "support/ReplacingFile.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <llvm/Support/FileSystem.h>
#include <llvm/Support/Process.h>

namespace lcjit::support {

namespace fs = std::filesystem;

namespace {
constexpr llvm::StringLiteral kUnfinished = ".lcjit-new-";
llvm::Error cannotWrite(const std::string& path, const std::string& why) {
  return llvm::createStringError(path + ": error: cannot write file" + (why.empty() ? "" : ": " + why));
}
}  // namespace

ReplacingFile::ReplacingFile(std::string path) : path_(std::move(path)) {
  std::error_code ec;
  fs::file_status st = fs::symlink_status(path_, ec);
  if (!ec && st.type() != fs::file_type::not_found && st.type() != fs::file_type::regular) return;  // in place
  fs::path target(path_);
  fs::path model = target.parent_path() / ("." + target.filename().string() + kUnfinished.str() + "%%%%%%%%");
  int fd = -1;
  llvm::SmallString<256> made;
  if (llvm::sys::fs::createUniqueFile(model.string(), fd, made)) return;  // in place: the error comes when it is opened
  llvm::sys::Process::SafelyCloseFileDescriptor(fd);
  temporary_ = made.str().str();
  if (st.type() == fs::file_type::regular) fs::permissions(temporary_, st.permissions(), ec);
}

ReplacingFile::ReplacingFile(ReplacingFile&& other) noexcept
    : path_(std::move(other.path_)), temporary_(std::move(other.temporary_)) {
  other.temporary_.clear();
}

ReplacingFile::~ReplacingFile() { abandon(); }

void ReplacingFile::abandon() {
  if (!temporary_.empty()) llvm::sys::fs::remove(temporary_);
  temporary_.clear();
}

llvm::Error ReplacingFile::commit() {
  if (temporary_.empty()) return llvm::Error::success();
  std::error_code ec = llvm::sys::fs::rename(temporary_, path_);
  // The target a mount point (the -out file bound into --sandbox's view), or on another disk: its
  // bytes copied in place, the one case where a reader could see part of it.
  if (ec == std::errc::device_or_resource_busy || ec == std::errc::cross_device_link)
    ec = llvm::sys::fs::copy_file(temporary_, path_);
  if (ec) return cannotWrite(path_, ec.message());  // the destructor removes the new file
  llvm::sys::fs::remove(temporary_);  // after a copy; after a rename it is gone already
  temporary_.clear();
  return llvm::Error::success();
}

bool ReplacingFile::isUnfinished(llvm::StringRef fileName) {
  return fileName.starts_with(".") && fileName.contains(kUnfinished);
}

void ReplacingFile::removeUnfinished(const std::string& path) {
  fs::path target(path);
  const std::string prefix = "." + target.filename().string() + kUnfinished.str();
  std::error_code ec;
  for (fs::directory_iterator it(target.parent_path().empty() ? "." : target.parent_path(), ec), end; !ec && it != end;
       it.increment(ec))
    if (it->path().filename().string().rfind(prefix, 0) == 0) fs::remove(it->path(), ec);
}

llvm::Error writeWholeFile(const std::string& path, llvm::function_ref<llvm::Error(std::ostream&)> write) {
  ReplacingFile file(path);
  std::ofstream out(file.writePath(), std::ios::binary | std::ios::trunc);
  if (!out) return cannotWrite(path, std::strerror(errno));
  if (llvm::Error e = write(out)) return e;
  out.close();
  if (!out) return cannotWrite(path, "the write failed (is the disk full?)");
  return file.commit();
}

llvm::Error writeWholeFile(const std::string& path, llvm::StringRef bytes) {
  return writeWholeFile(path, [&](std::ostream& out) {
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return llvm::Error::success();
  });
}

}  // namespace lcjit::support
