// What the guard around model code (ModelGuard.h) measures of the process and says of a fault in
// the user's words: the resident memory it compares with --max-memory and the default limit, the
// place in the model's files a fault names, sizes in words.
#include "runtime/ModelGuard.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace lcjit::runtime {

size_t residentBytes() {
  static int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  char buf[128];
  ssize_t n = fd >= 0 ? pread(fd, buf, sizeof buf - 1, 0) : -1;
  if (n <= 0) return 0;
  buf[n] = 0;
  unsigned long long size = 0, resident = 0;
  if (std::sscanf(buf, "%llu %llu", &size, &resident) != 2) return 0;
  return size_t(resident) * size_t(sysconf(_SC_PAGESIZE));
}

size_t defaultMemoryLimit() {
  static const size_t limit = [] {
    size_t physical = size_t(sysconf(_SC_PHYS_PAGES)) * size_t(sysconf(_SC_PAGESIZE));
    // In a container, the cgroup's limit (cgroup v2: /proc/self/cgroup's "0::/path").
    std::ifstream cg("/proc/self/cgroup");
    std::string line;
    while (std::getline(cg, line)) {
      if (line.rfind("0::", 0) != 0) continue;
      std::ifstream max("/sys/fs/cgroup" + line.substr(3) + "/memory.max");
      unsigned long long v = 0;
      if (max >> v && v > 0 && v < physical) physical = size_t(v);
    }
    return physical / 2;
  }();
  return limit;
}

std::optional<CodePlace> faultPlace(const Fault& f, const CodeLocator& locate) {
  if (!locate) return std::nullopt;
  if (f.pc)
    if (auto p = locate(f.pc, false)) return p;
  for (uintptr_t a : f.callers)
    if (auto p = locate(a, true)) return p;
  return std::nullopt;
}

std::string placeText(const CodePlace& p, std::initializer_list<std::string_view> names) {
  std::string file = p.file;
  for (std::string_view n : names) {
    std::error_code ec;
    if (!n.empty() && std::filesystem::absolute(n, ec).lexically_normal() == std::filesystem::path(p.file)) {
      file = n;
      break;
    }
  }
  std::string s = file + ":" + std::to_string(p.line);
  if (p.column) s += ":" + std::to_string(p.column);
  return s;
}

std::string sizeInWords(uint64_t n) {
  char text[32];
  if (n >= (uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.2f GB", double(n) / double(uint64_t(1) << 30));
  else if (n >= (uint64_t(1) << 20)) std::snprintf(text, sizeof text, "%.2f MB", double(n) / double(uint64_t(1) << 20));
  else std::snprintf(text, sizeof text, "%.1f KB", double(n) / 1024);
  return text;
}

}  // namespace lcjit::runtime
