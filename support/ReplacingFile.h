// Every file lcjit writes (outputs, saved editors' files, sweep records, cache entries) is written
// whole or not at all: the bytes go to a new file beside the target, renamed over it once
// complete. A reader (an image viewer, the file monitor, `sweep collect`, another lcjit sharing the
// cache) never sees half a file, and a write that fails leaves the last good one in place.
#pragma once
#include <ostream>
#include <string>

#include <llvm/ADT/STLFunctionalExtras.h>
#include <llvm/ADT/StringRef.h>
#include <llvm/Support/Error.h>

namespace lcjit::support {

class ReplacingFile {
 public:
  // Begins replacing `path`. A target that exists but is not a regular file (-out /dev/stdout, a
  // FIFO) or is a symbolic link is written in place instead (a rename would replace the device or
  // the link itself), and so is a target beside which nothing can be created.
  explicit ReplacingFile(std::string path);
  ReplacingFile(ReplacingFile&& other) noexcept;
  ReplacingFile& operator=(ReplacingFile&&) = delete;
  ReplacingFile(const ReplacingFile&) = delete;
  ~ReplacingFile();  // not committed: the new file is removed, the target left as it was

  const std::string& path() const { return path_; }
  // Where the writer writes: a hidden file in the target's folder (so that a glob such as
  // frame*.png never matches it), or the target itself when written in place.
  const std::string& writePath() const { return temporary_.empty() ? path_ : temporary_; }
  // Puts the new file in place (with the permissions the old one had). Errors:
  // "PATH: error: cannot write file: WHY".
  llvm::Error commit();
  // Removes the new file now, as the destructor would; the target stays as it was. Nothing is
  // written or committed after.
  void abandon();

  // Whether a file name is that of a new file not yet put in place (a writer's, or one left by a
  // process that was killed): what a folder's listing (the caches' pruning) should skip.
  static bool isUnfinished(llvm::StringRef fileName);
  // Removes the new files of `path` that a writer killed before commit() left (a sandboxed run
  // stopped at --max-file-size). Only when no other process may be writing it.
  static void removeUnfinished(const std::string& path);

 private:
  std::string path_, temporary_;  // temporary_ empty: written in place
};

// What `write` streams, as the whole of `path`, through a ReplacingFile. Errors: write's own, or
// "PATH: error: cannot write file[: WHY]" when the file cannot be made or the stream fails (a
// full disk).
llvm::Error writeWholeFile(const std::string& path, llvm::function_ref<llvm::Error(std::ostream&)> write);
// `bytes` as the whole of `path`.
llvm::Error writeWholeFile(const std::string& path, llvm::StringRef bytes);

}  // namespace lcjit::support
