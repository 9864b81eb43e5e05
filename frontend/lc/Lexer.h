// Tokenizer for preprocessed L+C text. Positions map back to the user's files through the GNU
// line markers the preprocessor leaves in its output.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lcjit::frontend {

struct Token {
  enum Kind { Identifier, Number, String, Char, Punct, Directive, End };
  Kind kind = End;
  std::string text;
  int file = 0;    // index into Lexed::files
  int line = 1;
  int col = 1;
  bool spaceBefore = false;  // whitespace or a line break precedes it in the source
  bool unterminated = false;  // a String or Char the line (a raw string: the text) ends inside

  bool is(const char* s) const { return (kind == Punct || kind == Identifier) && text == s; }
};

struct Lexed {
  std::vector<std::string> files;
  std::vector<Token> tokens;  // always ends with an End token
};

// `text` is preprocessor output; `mainFile` names it until the first line marker says otherwise.
Lexed lex(const std::string& text, const std::string& mainFile);

// A GNU line marker (`# 12 "model.l" 1`, or `#line 12 "model.l"`): the next line is line `line`
// of `file` (unchanged when it names none). `directive` is its line, from the '#', without the
// newline; nullopt when it is another directive. XL's tokens read them too (frontend/xl).
struct LineMarker {
  int line = 0;
  std::optional<std::string> file;
};
std::optional<LineMarker> readLineMarker(std::string_view directive);

}  // namespace lcjit::frontend
