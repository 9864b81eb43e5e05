// Files in lcjit's disk caches (compiled PCHs and objects, the preprocessor's macro image):
// written whole or not at all, and keyed by what they were made from.
#pragma once

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/Error.h>
#include <llvm/Support/SHA256.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace lcjit::support {

// Writes `bytes` as the whole of `path` (ReplacingFile.h): a reader never sees a
// partial file; false (and nothing written) on failure.
bool writeCacheFile(const std::string& path, llvm::StringRef bytes);

// Cache files whose contents are loaded and run (object code) carry a SHA-256 of themselves,
// checked when read: a file damaged on disk is never loaded.
bool writeCheckedCacheFile(const std::string& path, llvm::StringRef bytes);
struct CheckedRead {
  std::optional<std::string> bytes;  // the contents, when the file is there and whole
  std::string problem;               // a file that was there and damaged (now deleted): why
};
CheckedRead readCheckedCacheFile(const std::string& path);

// A cache folder lcjit may trust: what is in it is loaded and run as the user, so it must be the
// user's alone. Creates `dir` (mode 0700, parents as needed) when it is missing; then it must be a
// directory, not a symbolic link, owned by the user, and writable by no one else. Otherwise an
// error saying why (a planted object file would run as the user).
llvm::Error useAsCacheFolder(const std::string& dir);

// A fresh folder of this process's own (mode 0700, an unpredictable name in $TMPDIR or /tmp),
// for the caches when no trusted one can be had; the caller removes it (removeCacheFolder).
llvm::Expected<std::string> privateCacheFolder();
void removeCacheFolder(const std::string& dir);

// Adds every regular file under `dir` (names and contents, in name order) to `h`: what a cache
// entry made from the runtime headers depends on.
void hashDirectoryTree(llvm::SHA256& h, const std::string& dir);

// Files a cached result was made from, as lines "// F SIZE MTIME CTIME PATH" (times in
// nanoseconds) before the result: the result holds while every one of them is unchanged (ccache's
// direct-mode check; the status-change time cannot be set back). Folders may be stamped too (an
// entry added or removed changes their times). Used by the macro image, the kept preprocessed
// text and the kept cc1 lines.
// A file's stamp ("" when it cannot be read); `changed`: its latest modification or status change.
std::string fileStamp(llvm::StringRef file, int64_t* changed = nullptr);
// The stamp lines of `files`; nullopt when one cannot be read or changed after `notAfter`.
std::optional<std::string> stampLines(const std::vector<std::string>& files,
                                      int64_t notAfter = std::numeric_limits<int64_t>::max());
// Whether the stamp lines at the start of `text` all still hold and `follows` comes after them (a
// file of another format or version does not); `rest`: the text after `follows`.
bool stampsHold(llvm::StringRef text, llvm::StringRef follows, llvm::StringRef* rest = nullptr);

}  // namespace lcjit::support
