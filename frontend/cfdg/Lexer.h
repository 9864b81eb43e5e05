// Context Free's tokens (CFDG 3 and 2): names joined by `::`, numbers keeping their source text
// (a replacement's random seed is made from the text as written: `0.5` and `.5` differ), the
// Unicode spellings of `..` `+/-` `<=` `>=` `<>` and infinity, and comments.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::frontend::cfdg {

struct Place {
  int line = 1, column = 1;
};

enum class Tok {
  End,
  Name,       // shape, variable, function, CF::Setting, namespaced a::b
  ArrayName,  // a name followed at once by `[` (vector indexing)
  Number,     // text kept as written; a trailing % divides by 100
  String,     // "…"
  FileName,   // unquoted `something.cfdg` after import/include
  Punct,      // ( ) [ ] { } , ; : @ | + - * / ^ < > = ! and the multi-character operators
  PathOp,     // MOVETO … CLOSEPOLY
};

struct Token {
  Tok kind = Tok::End;
  std::string text;  // as written (operators in their ASCII form: "..", "+/-", "<=", ">=", "<>", "--")
  Place at;
  bool spaceBefore = false;
};

// `file` names the source in errors.
llvm::Expected<std::vector<Token>> tokenize(std::string_view source, const std::string& file);

// The value of a Number token's text: a trailing % divides by 100 (`50%` is 0.5).
double numberValue(const std::string& text);

}  // namespace lcjit::frontend::cfdg
