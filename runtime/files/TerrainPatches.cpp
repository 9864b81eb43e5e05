// Terrain .patch files (see TerrainPatches.h).
#include "runtime/files/TerrainPatches.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <string>
#include <type_traits>

#include <llvm/Support/MemoryBuffer.h>
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }

// Whitespace-separated tokens with the line each starts on.
class Tokens {
 public:
  Tokens(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  size_t line() const { return line_; }
  size_t remaining() const { return text_.size() - pos_; }

  llvm::Error error(const std::string& message) const { return textfile::fail(file_, line_, message); }

  // The next token; empty at the end of the text (line() is then the last token's line).
  std::string_view next() {
    while (pos_ < text_.size() && isSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ == text_.size()) line_ = tokenLine_;
    tokenLine_ = line_;
    size_t start = pos_;
    while (pos_ < text_.size() && !isSpace(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // A decimal number as a C++ stream reads one: sign, digits with an optional point, optional
  // exponent (no inf, nan or hexadecimal).
  static bool decimal(std::string_view t) {
    size_t i = 0;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    size_t digits = 0;
    while (i < t.size() && isDigit(t[i])) ++i, ++digits;
    if (i < t.size() && t[i] == '.') {
      ++i;
      while (i < t.size() && isDigit(t[i])) ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
      ++i;
      if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
      size_t exponent = 0;
      while (i < t.size() && isDigit(t[i])) ++i, ++exponent;
      if (exponent == 0) return false;
    }
    return i == t.size();
  }

  // Read in the field's own precision: a float straight from the text (strtof), not via a double.
  template <typename Real>
  llvm::Error number(const char* what, Real& out) {
    std::string_view t = next();
    if (auto e = check(t, what)) return e;
    std::string s(t);
    errno = 0;
    if constexpr (std::is_same_v<Real, float>)
      out = std::strtof(s.c_str(), nullptr);
    else
      out = std::strtod(s.c_str(), nullptr);
    if (errno == ERANGE && std::isinf(out)) return error(std::string(what) + " is out of range: " + s);
    return llvm::Error::success();
  }
  llvm::Error integer(const char* what, int& out) {
    std::string_view t = next();
    if (t.empty()) return error(std::string("the file ends where ") + what + " should be");
    size_t i = t[0] == '+' || t[0] == '-' ? 1 : 0;
    bool ok = i < t.size();
    for (size_t k = i; k < t.size(); ++k) ok = ok && isDigit(t[k]);
    if (!ok) return error(std::string(what) + " must be an integer, not '" + std::string(t.substr(0, 40)) + "'");
    std::string s(t);
    errno = 0;
    long v = std::strtol(s.c_str(), nullptr, 10);
    if (errno == ERANGE || v > INT_MAX || v < INT_MIN) return error(std::string(what) + " is out of range: " + s);
    out = int(v);
    return llvm::Error::success();
  }

 private:
  llvm::Error check(std::string_view t, const char* what) const {
    if (t.empty()) return error(std::string("the file ends where ") + what + " should be");
    if (!decimal(t)) return error(std::string(what) + " must be a number, not '" + std::string(t.substr(0, 40)) + "'");
    return llvm::Error::success();
  }

  std::string_view text_;
  const std::string& file_;
  size_t pos_ = 0, line_ = 1, tokenLine_ = 1;
};

// The shortest text an entry can take: six one-character numbers and the blanks between them.
constexpr size_t kMinEntryChars = 11;
constexpr size_t kSmallGrid = 4096;

}  // namespace

llvm::Expected<TerrainPatchFile> parseTerrainPatches(std::string_view text, const std::string& fileName, int levels) {
  if (levels < 1 || levels > kMaxTerrainLevels)
    return textfile::fail(fileName, 1, "a terrain has 1 to " + std::to_string(kMaxTerrainLevels) + " levels, not " +
                                           std::to_string(levels));
  Tokens in(text, fileName);
  TerrainPatchFile f;
  if (auto e = in.number("the terrain width", f.width)) return std::move(e);
  size_t total = 0;
  for (int l = 0; l < levels; ++l) {
    TerrainGrid g;
    std::string level = "level " + std::to_string(l);
    if (auto e = in.integer(("the size of " + level).c_str(), g.numU)) return std::move(e);
    size_t sizeLine = in.line();
    if (auto e = in.integer(("the size of " + level).c_str(), g.numV)) return std::move(e);
    // Each patch of level l is a 2^l-th of the grid per side, and must keep two points per side.
    const long patches = 1L << l;
    for (int n : {g.numU, g.numV}) {
      if (n < 2 || n - 1L < patches)
        return textfile::fail(fileName, sizeLine,
                              level + " is " + std::to_string(g.numU) + " x " + std::to_string(g.numV) +
                                  " points: at least " + std::to_string(patches + 1) + " per side are needed");
    }
    if (l > 0) {
      const TerrainGrid& coarser = f.levels.back();
      if (g.numU - 1L < 2L * (coarser.numU - 1) || g.numV - 1L < 2L * (coarser.numV - 1))
        return textfile::fail(fileName, sizeLine,
                              level + " is " + std::to_string(g.numU) + " x " + std::to_string(g.numV) +
                                  " points: at least " + std::to_string(2 * (coarser.numU - 1) + 1) + " x " +
                                  std::to_string(2 * (coarser.numV - 1) + 1) + " are needed after level " +
                                  std::to_string(l - 1) + "'s " + std::to_string(coarser.numU) + " x " +
                                  std::to_string(coarser.numV));
    }
    const size_t count = size_t(g.numU) * size_t(g.numV);
    if (count > kMaxTerrainPoints - total)
      return textfile::fail(fileName, sizeLine,
                            "the terrain has more than " + std::to_string(kMaxTerrainPoints) + " points");
    // A large grid is allocated only if the file can hold it (a small one is read, and a short
    // file then fails where it ends).
    if (count > kSmallGrid && count > (in.remaining() + 1) / (kMinEntryChars + 1))
      return textfile::fail(fileName, sizeLine,
                            level + " declares " + std::to_string(count) + " points, more than the rest of the file holds");
    total += count;
    g.points.resize(count);
    g.normals.resize(count);
    const std::string point = "a point of " + level, normal = "a normal of " + level;
    for (size_t k = 0; k < count; ++k) {
      V3d& p = g.points[k];
      V3d& n = g.normals[k];
      for (double* c : {&p.x, &p.y, &p.z})
        if (auto e = in.number(point.c_str(), *c)) return std::move(e);
      for (double* c : {&n.x, &n.y, &n.z})
        if (auto e = in.number(normal.c_str(), *c)) return std::move(e);
    }
    f.levels.push_back(std::move(g));
  }
  return f;
}

llvm::Expected<TerrainPatchFile> loadTerrainPatches(const std::string& path, int levels) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  return parseTerrainPatches((*buf)->getBuffer(), path, levels);
}

}  // namespace lcjit::runtime
