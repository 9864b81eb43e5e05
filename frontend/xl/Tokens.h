// XL's tokens (GroIMP's relational growth grammars, .rgg/.xl), read from the model as the C
// preprocessor left it: GNU line markers (`# LINE "FILE"`) move the position, so every token knows
// the file, line and column it was written at, and the translator's errors and the L+C it writes
// name the user's file. XL's rule arrows (`==>`, `==>>`, `::>`) and query brackets (`(*`, `*)`) are
// tokens of their own.
#pragma once
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace lcjit::frontend::xl {

struct Token {
  enum Kind { Identifier, Number, String, Punct, End } kind = End;
  std::string text;
  std::string file;  // as the line marker spelled it (between its quotes)
  int line = 1, col = 1;
  bool is(const char* t) const { return kind != String && text == t; }
};

using Range = std::pair<size_t, size_t>;  // tokens [first, last)

struct XlError {
  Token at;
  std::string message;
};

// Throws XlError at a character no XL token starts with, or at an unterminated string.
std::vector<Token> tokenize(const std::string& preprocessed, const std::string& mainFile);

}  // namespace lcjit::frontend::xl
