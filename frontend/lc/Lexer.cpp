// Tokenizer for preprocessed L+C text (see Lexer.h).
#include "frontend/lc/Lexer.h"

#include <cctype>
#include <cstdlib>
#include <cstring>

namespace lcjit::frontend {
namespace {

bool identStart(char c) { return std::isalpha((unsigned char)c) || c == '_' || c == '$'; }
bool identChar(char c) { return std::isalnum((unsigned char)c) || c == '_' || c == '$'; }

const char* const kPuncts[] = {"<<=", ">>=", "...", "->*", "<=>", "::", "->", "++", "--", "<<", ">>", "<=", ">=",
                               "==",  "!=",  "&&",  "||",  "+=",  "-=", "*=", "/=", "%=", "&=", "|=", "^=", ".*", "##"};

}  // namespace

Lexed lex(const std::string& text, const std::string& mainFile) {
  Lexed out;
  out.files.push_back(mainFile);
  int file = 0, line = 1;
  size_t i = 0, n = text.size();
  size_t lineStart = 0;
  bool atLineStart = true, space = true;

  auto fileIndex = [&](const std::string& name) {
    for (size_t k = 0; k < out.files.size(); ++k)
      if (out.files[k] == name) return (int)k;
    out.files.push_back(name);
    return (int)out.files.size() - 1;
  };

  while (i < n) {
    char c = text[i];
    if (c == '\n') {
      ++i;
      ++line;
      lineStart = i;
      atLineStart = true;
      space = true;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++i;
      space = true;
      continue;
    }
    int col = (int)(i - lineStart) + 1;
    if (atLineStart && c == '#') {
      // A directive line: a line marker updates the position, anything else passes through.
      size_t e = text.find('\n', i);
      if (e == std::string::npos) e = n;
      std::string d = text.substr(i, e - i);
      if (std::optional<LineMarker> marker = readLineMarker(d)) {
        if (marker->file) file = fileIndex(*marker->file);
        i = e < n ? e + 1 : e;
        line = marker->line;
        lineStart = i;
        atLineStart = true;
        space = true;
        continue;
      }
      Token t{Token::Directive, d, file, line, col, true};
      out.tokens.push_back(std::move(t));
      i = e;
      continue;
    }
    atLineStart = false;
    Token t;
    t.file = file;
    t.line = line;
    t.col = col;
    t.spaceBefore = space;
    space = false;
    size_t s = i;
    if (identStart(c)) {
      while (i < n && identChar(text[i])) ++i;
      // String/char literal prefixes (u8"...", L'x', R"(...)").
      if (i < n && (text[i] == '"' || text[i] == '\'')) {
        std::string p = text.substr(s, i - s);
        if (p == "u8" || p == "u" || p == "U" || p == "L" || p == "R" || p == "u8R" || p == "uR" || p == "UR" || p == "LR")
          goto literal;
      }
      t.kind = Token::Identifier;
    } else if (std::isdigit((unsigned char)c) || (c == '.' && i + 1 < n && std::isdigit((unsigned char)text[i + 1]))) {
      while (i < n) {
        char d = text[i];
        if ((d == '+' || d == '-') && (text[i - 1] == 'e' || text[i - 1] == 'E' || text[i - 1] == 'p' || text[i - 1] == 'P')) {
          ++i;
        } else if (identChar(d) || d == '.' || (d == '\'' && i + 1 < n && std::isalnum((unsigned char)text[i + 1]))) {
          ++i;
        } else {
          break;
        }
      }
      t.kind = Token::Number;
    } else if (c == '"' || c == '\'') {
    literal:
      char q = text[i];
      bool raw = i > s && text[i - 1] == 'R' && q == '"';
      if (raw) {
        size_t open = text.find('(', i);
        std::string delim = open == std::string::npos ? "" : text.substr(i + 1, open - i - 1);
        std::string close = ")" + delim + "\"";
        size_t e = open == std::string::npos ? std::string::npos : text.find(close, open);
        i = e == std::string::npos ? n : e + close.size();
        t.unterminated = e == std::string::npos;
      } else {
        ++i;
        while (i < n && text[i] != q && text[i] != '\n') {
          if (text[i] == '\\' && i + 1 < n) ++i;
          ++i;
        }
        t.unterminated = i >= n || text[i] != q;
        if (!t.unterminated) ++i;
      }
      t.kind = q == '"' ? Token::String : Token::Char;
    } else {
      t.kind = Token::Punct;
      size_t len = 1;
      for (const char* p : kPuncts) {
        size_t l = std::strlen(p);
        if (text.compare(i, l, p) == 0) {
          len = l;
          break;
        }
      }
      i += len;
    }
    t.text = text.substr(s, i - s);
    // Raw strings may span lines: keep the line count right.
    for (size_t k = s; k < i; ++k)
      if (text[k] == '\n') {
        ++line;
        lineStart = k + 1;
      }
    out.tokens.push_back(std::move(t));
  }
  Token end;
  end.file = file;
  end.line = line;
  end.col = (int)(i - lineStart) + 1;
  out.tokens.push_back(end);
  return out;
}

std::optional<LineMarker> readLineMarker(std::string_view d) {
  size_t k = 1;
  while (k < d.size() && d[k] == ' ') ++k;
  if (d.substr(k, 4) == "line") {
    k += 4;
    while (k < d.size() && d[k] == ' ') ++k;
  }
  if (d.empty() || d[0] != '#' || k >= d.size() || !std::isdigit((unsigned char)d[k])) return std::nullopt;
  LineMarker m;
  m.line = std::atoi(std::string(d.substr(k)).c_str());
  size_t q = d.find('"', k);
  if (q != std::string_view::npos) {
    size_t q2 = d.find('"', q + 1);
    if (q2 != std::string_view::npos) m.file = std::string(d.substr(q + 1, q2 - q - 1));
  }
  return m;
}

}  // namespace lcjit::frontend
