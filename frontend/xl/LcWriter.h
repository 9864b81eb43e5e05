// The L+C the XL front end writes (frontend/xl/Translate.cpp), each of the user's tokens at its
// own file, line and column (GNU line markers, then spaces up to its column), so that the
// rewriter's and the compiler's errors name the .rgg where it was written. Internal to
// frontend/xl.
#pragma once
#include <cctype>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frontend/xl/Tokens.h"

namespace lcjit::frontend::xl {

// The L+C being written. Each token of the user's text goes at its own line and column; what the
// translation adds goes where the writing is (after the token before it).
class LcWriter {
public:
  explicit LcWriter(const std::vector<Token>& tokens) : t_(tokens) {}
  // `text` at token `at`'s place.
  void at(size_t at, std::string_view text) {
    // Two names written together (`X]` is `X EB`) would be one: the second starts a line of its own.
    bool joined = !text.empty() && word(text.front()) && !out_.empty() && word(out_.back()) && t_[at].file == file_ &&
                  t_[at].line == line_ && col_ == t_[at].col;
    if (joined) file_.clear();
    moveTo(t_[at]);
    put(text);
  }
  void token(size_t i) { at(i, spelled(t_[i])); }
  void tokens(Range r) {
    for (size_t i = r.first; i < r.second; ++i) token(i);
  }
  void add(std::string_view text) {
    if (!out_.empty() && out_.back() != '\n') put(" ");
    put(text);
  }
  std::string take() { return std::move(out_) + "\n"; }
  // Java's numbers as C++'s: `1.5d` is a double without its suffix.
  static std::string spelled(const Token& t) {
    std::string s = t.text;
    bool hex = s.size() > 1 && (s[1] == 'x' || s[1] == 'X');
    if (t.kind == Token::Number && !hex && (s.back() == 'd' || s.back() == 'D')) s.pop_back();
    return s;
  }

private:
  static bool word(char c) { return std::isalnum((unsigned char)c) || c == '_'; }
  void put(std::string_view s) {
    out_ += s;
    col_ += (int)s.size();
  }
  void moveTo(const Token& t) {
    if (t.file == file_ && t.line == line_ && col_ <= t.col) {
    } else if (t.file == file_ && t.line == line_ + 1) {
      out_ += '\n', ++line_, col_ = 1;
    } else {
      if (!out_.empty() && out_.back() != '\n') out_ += '\n';
      out_ += "# " + std::to_string(t.line) + " \"" + t.file + "\"\n";
      file_ = t.file, line_ = t.line, col_ = 1;
    }
    if (col_ < t.col) out_.append(t.col - col_, ' '), col_ = t.col;
  }
  const std::vector<Token>& t_;
  std::string out_, file_;
  int line_ = 0, col_ = 1;
};

}  // namespace lcjit::frontend::xl
