// XL's tokens (Tokens.h).
#include "frontend/xl/Tokens.h"

#include "frontend/lc/Lexer.h"  // readLineMarker

#include <cctype>
#include <cstdlib>

namespace lcjit::frontend::xl {

namespace {

// Longest first: `==>>` before `==>` before `==`.
constexpr const char* kPuncts[] = {"==>>", "==>", "::>", "<<=", ">>=", ">>>", "(*", "*)", "<=", ">=", "==", "!=",
                                   "&&",   "||",  "++",  "--",  "+=",  "-=",  "*=", "/=", "%=", "<<", ">>", "->",
                                   "::",   "+",   "-",   "*",   "/",   "%",   "<",  ">",  "=",  "!",  "~",  "?",
                                   ":",    ";",   ",",   ".",   "(",   ")",   "[",  "]",  "{",  "}",  "&",  "|",
                                   "^",    "@"};

bool identStart(char c) { return std::isalpha((unsigned char)c) || c == '_' || c == '$'; }
bool identChar(char c) { return std::isalnum((unsigned char)c) || c == '_' || c == '$'; }

}  // namespace

std::vector<Token> tokenize(const std::string& text, const std::string& mainFile) {
  std::vector<Token> out;
  std::string file = mainFile;
  int line = 1;
  size_t i = 0, lineStart = 0, n = text.size();
  bool atLineStart = true;
  while (i < n) {
    char c = text[i];
    if (c == '\n') {
      ++i, ++line, lineStart = i, atLineStart = true;
      continue;
    }
    if (std::isspace((unsigned char)c)) {
      ++i;
      continue;
    }
    Token t;
    t.file = file, t.line = line, t.col = (int)(i - lineStart) + 1;
    if (atLineStart && c == '#') {
      // A line marker (`# 12 "model.rgg" 1`): the next line is line 12 of that file. Other
      // directives do not reach here (the preprocessor ran); XL has no `#`.
      size_t e = text.find('\n', i);
      if (e == std::string::npos) e = n;
      std::optional<LineMarker> marker = readLineMarker(std::string_view(text).substr(i, e - i));
      if (!marker) throw XlError{t, "'#' is not XL"};
      if (marker->file) file = *marker->file;
      i = e < n ? e + 1 : e;
      line = marker->line, lineStart = i;
      continue;
    }
    atLineStart = false;
    size_t s = i;
    if (identStart(c)) {
      while (i < n && identChar(text[i])) ++i;
      t.kind = Token::Identifier;
    } else if (std::isdigit((unsigned char)c) || (c == '.' && i + 1 < n && std::isdigit((unsigned char)text[i + 1]))) {
      // Java's numbers: 12, 0x1F, 1.5, 1e-3, 2.5f, 10L.
      while (i < n && (std::isalnum((unsigned char)text[i]) || text[i] == '.' ||
                       ((text[i] == '+' || text[i] == '-') && (text[i - 1] == 'e' || text[i - 1] == 'E') &&
                        !(s + 1 < n && (text[s + 1] == 'x' || text[s + 1] == 'X')))))
        ++i;
      t.kind = Token::Number;
    } else if (c == '"' || c == '\'') {
      ++i;
      while (i < n && text[i] != c && text[i] != '\n') i += text[i] == '\\' ? 2 : 1;
      if (i >= n || text[i] != c) throw XlError{t, c == '"' ? "a string without its closing '\"'" : "a character without its closing \"'\""};
      ++i;
      t.kind = Token::String;
    } else {
      for (const char* p : kPuncts) {
        size_t len = std::char_traits<char>::length(p);
        if (text.compare(i, len, p) == 0) {
          i += len;
          t.kind = Token::Punct;
          break;
        }
      }
      if (t.kind != Token::Punct) throw XlError{t, std::string("'") + c + "' is not XL"};
    }
    t.text = text.substr(s, i - s);
    out.push_back(std::move(t));
  }
  Token end;
  end.kind = Token::End, end.file = file, end.line = line, end.col = (int)(i - lineStart) + 1;
  if (!out.empty()) end.file = out.back().file, end.line = out.back().line, end.col = out.back().col + (int)out.back().text.size();
  out.push_back(end);
  return out;
}

}  // namespace lcjit::frontend::xl
