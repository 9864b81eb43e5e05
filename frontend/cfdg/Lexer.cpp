// Context Free's tokens (Lexer.h).
#include "frontend/cfdg/Lexer.h"

#include <cctype>
#include <cstdlib>
#include <cstring>

namespace lcjit::frontend::cfdg {
namespace {

bool nameStart(unsigned char c) { return std::isalpha(c) || c >= 0x80; }
bool nameChar(unsigned char c) { return std::isalnum(c) || c == '_' || c >= 0x80; }

// The operators Context Free also takes in their Unicode spellings, as UTF-8.
struct Spelling {
  std::string_view utf8, ascii;
};
constexpr Spelling kUnicode[] = {{"\xE2\x80\xA6", ".."}, {"\xC2\xB1", "+/-"}, {"\xE2\x89\xA4", "<="},
                                 {"\xE2\x89\xA5", ">="}, {"\xE2\x89\xA0", "<>"}, {"\xE2\x88\x9E", "CF::Infinity"}};

constexpr std::string_view kPathOps[] = {"MOVETO", "LINETO", "ARCTO", "CURVETO", "MOVEREL",
                                         "LINEREL", "ARCREL", "CURVEREL", "CLOSEPOLY"};

}  // namespace

llvm::Expected<std::vector<Token>> tokenize(std::string_view src, const std::string& file) {
  std::vector<Token> out;
  size_t i = 0;
  int line = 1;
  size_t lineStart = 0;
  bool space = true;
  auto place = [&](size_t at) { return Place{line, int(at - lineStart) + 1}; };
  auto error = [&](size_t at, const std::string& message) {
    Place p = place(at);
    return llvm::createStringError(file + ":" + std::to_string(p.line) + ":" + std::to_string(p.column) +
                                   ": error: " + message);
  };
  auto newline = [&](size_t next) {
    ++line;
    lineStart = next;
  };
  while (i < src.size()) {
    unsigned char c = static_cast<unsigned char>(src[i]);
    if (c == '\n' || (c == '\r')) {
      if (c == '\r' && i + 1 < src.size() && src[i + 1] == '\n') ++i;
      newline(++i);
      space = true;
      continue;
    }
    if (c == ' ' || c == '\t') {
      ++i;
      space = true;
      continue;
    }
    if (c == '#' || (c == '/' && i + 1 < src.size() && src[i + 1] == '/')) {
      while (i < src.size() && src[i] != '\n' && src[i] != '\r') ++i;
      space = true;
      continue;
    }
    if (c == '/' && i + 1 < src.size() && src[i + 1] == '*') {
      Place start = place(i);
      i += 2;
      while (i + 1 < src.size() && !(src[i] == '*' && src[i + 1] == '/')) {
        if (src[i] == '\n') newline(i + 1);
        ++i;
      }
      if (i + 1 >= src.size())
        return llvm::createStringError(file + ":" + std::to_string(start.line) + ":" + std::to_string(start.column) +
                                       ": error: unterminated comment");
      i += 2;
      space = true;
      continue;
    }
    Token t;
    t.at = place(i);
    t.spaceBefore = space;
    space = false;
    // Unicode operators.
    bool matched = false;
    for (const Spelling& s : kUnicode)
      if (src.substr(i, s.utf8.size()) == s.utf8) {
        t.kind = s.ascii == "CF::Infinity" ? Tok::Name : Tok::Punct;
        t.text = std::string(s.ascii);
        i += s.utf8.size();
        matched = true;
        break;
      }
    if (matched) {
      out.push_back(std::move(t));
      continue;
    }
    if (c == '"') {
      size_t start = ++i;
      while (i < src.size() && src[i] != '"' && src[i] != '\n') ++i;
      if (i >= src.size() || src[i] != '"')
        return error(start - 1, "unterminated string");
      t.kind = Tok::String;
      t.text = std::string(src.substr(start, i - start));
      ++i;
      out.push_back(std::move(t));
      continue;
    }
    if (std::isdigit(c) || (c == '.' && i + 1 < src.size() && std::isdigit(static_cast<unsigned char>(src[i + 1])))) {
      size_t start = i;
      while (i < src.size() && std::isdigit(static_cast<unsigned char>(src[i]))) ++i;
      // `1..5`: the number ends before a range.
      if (i < src.size() && src[i] == '.' && !(i + 1 < src.size() && src[i + 1] == '.')) {
        ++i;
        while (i < src.size() && std::isdigit(static_cast<unsigned char>(src[i]))) ++i;
      }
      if (i < src.size() && (src[i] == 'e' || src[i] == 'E')) {
        size_t k = i + 1;
        if (k < src.size() && (src[k] == '+' || src[k] == '-')) ++k;
        if (k < src.size() && std::isdigit(static_cast<unsigned char>(src[k]))) {
          i = k;
          while (i < src.size() && std::isdigit(static_cast<unsigned char>(src[i]))) ++i;
        }
      }
      if (i < src.size() && src[i] == '%') ++i;
      t.kind = Tok::Number;
      t.text = std::string(src.substr(start, i - start));
      out.push_back(std::move(t));
      continue;
    }
    if (nameStart(c)) {
      size_t start = i;
      for (;;) {
        while (i < src.size() && nameChar(static_cast<unsigned char>(src[i]))) {
          // A Unicode operator ends a name.
          bool op = false;
          for (const Spelling& s : kUnicode)
            if (src.substr(i, s.utf8.size()) == s.utf8) op = true;
          if (op) break;
          ++i;
        }
        if (i + 2 < src.size() && src[i] == ':' && src[i + 1] == ':' && nameStart(static_cast<unsigned char>(src[i + 2]))) {
          i += 2;
          continue;
        }
        break;
      }
      // An unquoted file name: letters, digits, _ - . ending in .cfdg.
      size_t k = i;
      while (k < src.size() && (nameChar(static_cast<unsigned char>(src[k])) || src[k] == '-' || src[k] == '.')) ++k;
      std::string_view longer = src.substr(start, k - start);
      if (k > i && longer.size() > 5 && longer.substr(longer.size() - 5) == ".cfdg") {
        t.kind = Tok::FileName;
        t.text = std::string(longer);
        i = k;
        out.push_back(std::move(t));
        continue;
      }
      t.text = std::string(src.substr(start, i - start));
      t.kind = Tok::Name;
      for (std::string_view op : kPathOps)
        if (t.text == op) t.kind = Tok::PathOp;
      if (t.kind == Tok::Name && i < src.size() && src[i] == '[') t.kind = Tok::ArrayName;
      out.push_back(std::move(t));
      continue;
    }
    static constexpr std::string_view kLong[] = {"..", "+/-", "<=", ">=", "==", "<>", "&&", "||", "^^", "--"};
    t.kind = Tok::Punct;
    for (std::string_view op : kLong)
      if (src.substr(i, op.size()) == op) {
        t.text = std::string(op);
        break;
      }
    if (t.text.empty()) {
      if (!std::strchr("()[]{},;:@|+-*/^<>=!", c) || c == 0)
        return error(i, std::string("unexpected character '") + char(c) + "'");
      t.text = std::string(1, char(c));
    }
    i += t.text.size();
    out.push_back(std::move(t));
  }
  Token end;
  end.at = place(i);
  out.push_back(end);
  return out;
}

double numberValue(const std::string& text) {
  std::string t = text;
  bool percent = !t.empty() && t.back() == '%';
  if (percent) t.pop_back();
  double v = std::strtod(t.c_str(), nullptr);
  if (percent) v /= 100.0;
  return v;
}

}  // namespace lcjit::frontend::cfdg
