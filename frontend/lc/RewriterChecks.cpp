// The checks the rewriter makes before anything parses a model (Rewriter.cpp's rewrite() calls
// checkBeforeParsing first): how deep its statements nest, how long its names are, whether its
// brackets pair, and directive lines the compiler would meet before any line of the model.
//
// Sections, in order (each begins with a `// ----` rule): Limits (the nesting, brackets and
// names clang takes) · checkBeforeParsing.
#include <cctype>
#include <set>

#include "frontend/lc/RewriterImpl.h"

namespace lcjit::frontend::detail {

// ---------------------------------------------------------------------------------------------
// Limits

// Clang's parser (and this rewriter) recurse once per bracket, per operator in prefix position,
// per right-associative operator (=, ?:) and per statement inside a statement (if, else if,
// while, for…). A model nested deeper than the compiling thread's stack allows would end lcjit,
// and with it a live session (2,000 '!' in one expression, 8,000 nested ifs). So
// before anything parses, each statement's nesting is measured token by token: the depth is the
// open brackets plus, at every bracket level, the nesting operators and statements since that
// level's last ';' or ','. Deeper than kMaxNesting is an error at the token that goes too deep;
// clang managed ~1,500 nested '!' on an 8 MB stack, so 1,000 leaves room for the rest.
// checkBeforeParsing does that, and refuses directive lines the compiler would meet before any
// line of the model.
constexpr int kMaxBrackets = 256;  // clang's -fbracket-depth default
constexpr int kMaxNesting = 1000;
// Clang's typo correction of an unknown name costs its length times every candidate's: 100,000
// characters took a minute. No model's names come near this.
constexpr size_t kMaxIdentifier = 1024;

bool isNestingKeyword(const std::string& s) {
  static const std::set<std::string> kWords = {"if", "while", "for", "do", "switch", "case", "default",
                                               "return", "sizeof", "alignof", "new", "delete", "throw", "co_await",
                                               "co_yield", "co_return", "typeid", "noexcept", "decltype"};
  return kWords.count(s) != 0;
}
bool isPrefixOperator(const std::string& s) {
  static const std::set<std::string> kOps = {"!", "~", "-", "+", "*", "&", "++", "--", "&&", "::"};
  return kOps.count(s) != 0;
}
bool isRightAssociative(const std::string& s) {
  static const std::set<std::string> kOps = {"=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=", "?", ":"};
  return kOps.count(s) != 0;
}

// ---------------------------------------------------------------------------------------------
// checkBeforeParsing

// Also pairs the brackets: one left open (or a stray closer) would swallow or cut the generated
// code that follows the model's text, and Clang's errors would land there, in lcjit's tables,
// instead of at the bracket. The first unpaired one is returned, not thrown: the
// rewriter's own errors ("expected ')' to close the parameter list of module 'A'") say more
// where they apply, so it is reported only when rewriting finds nothing.
std::optional<RewriteError> checkBeforeParsing(const Lexed& lx) {
  struct Level {
    int chain = 0;      // nesting tokens since this level's last ';' or ','
    int lastChain = 0;  // the chain its last ';' ended: an 'else' continues it
    const Token* open = nullptr;  // its bracket
  };
  std::optional<RewriteError> unpaired;
  auto closing = [](const std::string& b) { return std::string(b == "(" ? ")" : b == "[" ? "]" : "}"); };
  std::vector<Level> levels(1);
  int depth = 0;  // the sum of the open levels' chains and the brackets
  const Token* prev = nullptr;
  auto deeper = [&](const Token& t) {
    ++levels.back().chain;
    if (++depth > kMaxNesting)
      throw RewriteError{t, "this nests more than " + std::to_string(kMaxNesting) +
                                " operators, brackets or statements inside one another: too deep to compile"};
  };
  for (const Token& t : lx.tokens) {
    if (t.kind == Token::End) break;
    if (t.kind == Token::Directive) {
      // What the preprocessor leaves is '#pragma …' or a kept '#include <…>'; a line that starts
      // with '#' and no directive name ('##include', a doubled '#') would reach the compiler
      // before any line of the model, as an error in a '.l.cpp' file.
      size_t k = 1;
      while (k < t.text.size() && (t.text[k] == ' ' || t.text[k] == '\t')) ++k;
      if (k < t.text.size() && !std::isalpha((unsigned char)t.text[k]))
        throw RewriteError{t, "'" + t.text.substr(0, k + 1) + "' starts no preprocessor directive (a directive is '#' and its name: #include, #define…)"};
      continue;
    }
    const std::string& s = t.text;
    // The literal takes in the rest of its line, brackets and all: said as Clang (and g++) say
    // it, at the literal, rather than as a bracket it swallowed that is never closed.
    if (t.unterminated) {
      size_t quote = s.find_first_of("\"'");
      if (t.kind == Token::Char) throw RewriteError{t, "missing terminating ' character"};
      if (quote == 0 || s[quote - 1] != 'R') throw RewriteError{t, "missing terminating '\"' character"};
      std::string delimiter = s.substr(quote + 1, s.find('(', quote) - quote - 1);
      throw RewriteError{t, "raw string missing terminating delimiter )" + delimiter + "\""};
    }
    if (t.kind == Token::Identifier && s.size() > kMaxIdentifier)
      throw RewriteError{t, "an identifier of " + std::to_string(s.size()) + " characters: lcjit takes names of up to " +
                                std::to_string(kMaxIdentifier)};
    const bool punct = t.kind == Token::Punct;
    if (punct && (s == "(" || s == "[" || s == "{")) {
      if ((int)levels.size() > kMaxBrackets)
        throw RewriteError{t, "brackets nest more than " + std::to_string(kMaxBrackets) + " deep"};
      deeper(t);
      levels.emplace_back().open = &t;
    } else if (punct && (s == ")" || s == "]" || s == "}")) {
      if (!unpaired && levels.size() == 1) unpaired = RewriteError{t, "'" + s + "' closes no bracket"};
      if (!unpaired && levels.size() > 1 && closing(levels.back().open->text) != s) {
        const Token& o = *levels.back().open;
        unpaired = RewriteError{t, "'" + s + "' does not close the '" + o.text + "' at line " + std::to_string(o.line) +
                                       ", column " + std::to_string(o.col)};
      }
      if (levels.size() > 1) {
        depth -= levels.back().chain + 1;
        levels.pop_back();
        --levels.back().chain;  // the bracket itself
      }
      if (s == "}") {  // a compound statement ends a statement as ';' does
        levels.back().lastChain = levels.back().chain;
        depth -= levels.back().chain;
        levels.back().chain = 0;
      }
    } else if (punct && (s == ";" || s == ",")) {
      levels.back().lastChain = s == ";" ? levels.back().chain : 0;
      depth -= levels.back().chain;
      levels.back().chain = 0;
    } else if (t.kind == Token::Identifier && s == "else") {
      depth += levels.back().lastChain - levels.back().chain;  // back inside its if
      levels.back().chain = levels.back().lastChain;
    } else if ((t.kind == Token::Identifier && isNestingKeyword(s)) || (punct && isRightAssociative(s))) {
      deeper(t);
    } else if (punct && isPrefixOperator(s)) {
      // In prefix position: after an operator or an opening bracket, or at the start.
      bool prefix = !prev || (prev->kind == Token::Punct && prev->text != ")" && prev->text != "]" && prev->text != "}") ||
                    (prev->kind == Token::Identifier && isNestingKeyword(prev->text));
      if (prefix) deeper(t);
    }
    prev = &t;
  }
  if (!unpaired && levels.size() > 1) {
    const Token& o = *levels.back().open;
    unpaired = RewriteError{o, "'" + o.text + "' is never closed (no '" + closing(o.text) + "' matches it)"};
  }
  return unpaired;
}

}  // namespace lcjit::frontend::detail
