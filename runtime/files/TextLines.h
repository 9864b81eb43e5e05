// Small pieces the text-format readers share: "file:line: error: …" errors, line splitting
// (CRLF tolerated) and trimming.
#pragma once
#include <cctype>
#include <string>
#include <string_view>
#include <vector>

#include "llvm/Support/Error.h"

namespace lcjit::runtime::textfile {

inline llvm::Error fail(const std::string& file, size_t line, const std::string& msg) {
  return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s:%zu: error: %s", file.c_str(), line, msg.c_str());
}

// The lines of `text` without their '\n' (and '\r'); no empty last line after a final newline.
inline std::vector<std::string_view> splitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t nl = text.find('\n', start);
    std::string_view l = text.substr(start, nl == std::string_view::npos ? std::string_view::npos : nl - start);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    lines.push_back(l);
    if (nl == std::string_view::npos) break;
    start = nl + 1;
  }
  return lines;
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace((unsigned char)s.front())) s.remove_prefix(1);
  while (!s.empty() && std::isspace((unsigned char)s.back())) s.remove_suffix(1);
  return s;
}

}  // namespace lcjit::runtime::textfile
