// What the fuzz targets (tests/fuzz, docs/fuzzing.md) share: the input as a file for the readers
// that take a path, and the check that a rejected input gets an error naming its file.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include <llvm/Support/Error.h>

namespace lcjit::fuzz {

inline std::string_view text(const uint8_t* data, size_t size) { return {reinterpret_cast<const char*>(data), size}; }

// A folder of this process (in /dev/shm when there is one: no disk writes per input), removed
// when the process exits normally.
inline const std::string& scratchDir() {
  // Never destroyed: the exit handler below runs after the destructors of statics.
  static const std::string* const dir = [] {
    std::string base = "/dev/shm";
    if (access(base.c_str(), W_OK) != 0) {
      const char* t = std::getenv("TMPDIR");
      base = t && *t ? t : "/tmp";
    }
    auto* d = new std::string(base + "/lcjit-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(*d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratchDir(), ec);
    });
    return d;
  }();
  return *dir;
}

// The input as a file in scratchDir(), named with `extension` (some readers only take a path).
inline const std::string& inputFile(const uint8_t* data, size_t size, const std::string& extension) {
  static std::string path;
  path = scratchDir() + "/input" + extension;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return path;
}

// Bad input must get a clear error naming the file; one that does not is a finding.
inline void checkError(llvm::Error e, const std::string& file) {
  if (!e) return;
  std::string msg = llvm::toString(std::move(e));
  if (msg.find(file) == std::string::npos) {
    std::fprintf(stderr, "lcjit fuzz: the error does not name the file '%s':\n%s\n", file.c_str(), msg.c_str());
    std::abort();
  }
}

template <class T>
bool check(llvm::Expected<T>& value, const std::string& file) {
  if (value) return true;
  checkError(value.takeError(), file);
  return false;
}

}  // namespace lcjit::fuzz
