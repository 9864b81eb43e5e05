// Small pieces the text-format readers share: "file:line[:column]: error: …" errors, line
// splitting (CRLF tolerated), trimming and splitting into words.
#pragma once
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>
#include <llvm/Support/MemoryBuffer.h>

#include "support/InputFile.h"

namespace lcjit::runtime::textfile {

// "FILE:LINE: error: MSG"; line 0: an error of the whole file, "FILE: error: MSG".
inline llvm::Error fail(const std::string& file, size_t line, const std::string& msg) {
  if (line == 0) return llvm::createStringError(file + ": error: " + msg);
  return llvm::createStringError(file + ":" + std::to_string(line) + ": error: " + msg);
}

inline llvm::Error failAt(const std::string& file, size_t line, size_t column, const std::string& msg) {
  return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s:%zu:%zu: error: %s", file.c_str(), line, column,
                                 msg.c_str());
}

// The whole file, or "PATH: error: cannot open file: why" (why: "not a regular file (a FIFO)"
// too, InputFile.h).
inline llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> readFile(const std::string& path) {
  auto buf = support::readInputFile(path);
  if (!buf) return fail(path, 0, "cannot open file: " + buf.getError().message());
  return std::move(*buf);
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

// The blank-separated words of `s` (views into it).
inline std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace((unsigned char)s[i])) ++i;
    size_t b = i;
    while (i < s.size() && !std::isspace((unsigned char)s[i])) ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// A GNU cpp line marker `# N "file" flags…` or `#line N "file"` (p at the '#'): the next line is
// line N of `file` (kept when the marker names none). Returns false for other directives.
inline bool lineMarker(const char* p, std::string& file, int& line) {
  auto blank = [](char c) { return c == ' ' || c == '\t'; };
  ++p;
  while (blank(*p)) ++p;
  if (std::string_view(p).substr(0, 4) == "line" && blank(p[4]))
    for (p += 4; blank(*p);) ++p;
  if (*p < '0' || *p > '9') return false;
  long n = 0;
  for (; *p >= '0' && *p <= '9'; ++p) n = n < 100000000 ? n * 10 + (*p - '0') : n;
  while (blank(*p)) ++p;
  if (*p == '"') {
    std::string name;
    for (++p; *p && *p != '"'; ++p) {
      if (*p == '\\' && p[1]) ++p;
      name += *p;
    }
    file = name;
  }
  line = int(n < 1 ? 1 : n) - 1;
  return true;
}

}  // namespace lcjit::runtime::textfile
