// The REPL's text handling (see ReplText.h).
#include "repl/ReplText.h"

#include "runtime/files/TextLines.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace lcjit::repl {
namespace {

std::vector<std::string> withPrefix(const std::vector<std::string>& words, std::string_view prefix) {
  std::vector<std::string> out;
  for (const std::string& w : words)
    if (w.compare(0, prefix.size(), prefix) == 0) out.push_back(w);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

llvm::Expected<std::vector<std::string>> splitWords(std::string_view line) {
  std::vector<std::string> words;
  size_t i = 0;
  while (i < line.size()) {
    if (std::isspace((unsigned char)line[i])) {
      ++i;
      continue;
    }
    std::string w;
    while (i < line.size() && !std::isspace((unsigned char)line[i])) {
      if (line[i] != '"') {
        w += line[i++];
        continue;
      }
      size_t close = line.find('"', i + 1);
      if (close == std::string_view::npos)
        return llvm::createStringError("error: missing closing quote");
      w.append(line.substr(i + 1, close - i - 1));
      i = close + 1;
    }
    words.push_back(std::move(w));
  }
  return words;
}

bool isCompleteCpp(std::string_view text) {
  auto identChar = [](char c) { return std::isalnum((unsigned char)c) || c == '_' || c == '$'; };
  int depth = 0;
  enum { Code, LineComment, BlockComment, String, Char, RawString } state = Code;
  std::string rawEnd;  // `)delimiter"`, which ends the raw string
  for (size_t i = 0; i < text.size(); ++i) {
    char c = text[i], next = i + 1 < text.size() ? text[i + 1] : '\0';
    // A backslash at the end of a line joins the next line to it, before anything else is read
    // (in a comment and a literal too), except in a raw string.
    if (c == '\\' && state != RawString && (next == '\n' || (next == '\r' && text.substr(i + 2, 1) == "\n"))) {
      i += next == '\r' ? 2 : 1;
      continue;
    }
    switch (state) {
      case Code:
        if (c == '/' && next == '/') state = LineComment, ++i;
        else if (c == '/' && next == '*') state = BlockComment, ++i;
        else if (c == '"') state = String;
        else if (c == '\'') state = Char;
        else if (c == '(' || c == '[' || c == '{') ++depth;
        else if (c == ')' || c == ']' || c == '}') --depth;
        else if (std::isdigit((unsigned char)c) || (c == '.' && std::isdigit((unsigned char)next))) {
          // A number: its ' are digit separators (1'000'000), not a character literal.
          while (i + 1 < text.size() &&
                 (identChar(text[i + 1]) || text[i + 1] == '.' ||
                  (text[i + 1] == '\'' && i + 2 < text.size() && identChar(text[i + 2])) ||
                  ((text[i + 1] == '+' || text[i + 1] == '-') && std::strchr("eEpP", text[i]))))
            ++i;
        } else if (identChar(c)) {
          size_t start = i;
          while (i + 1 < text.size() && identChar(text[i + 1])) ++i;
          std::string_view word = text.substr(start, i + 1 - start);
          bool raw = (word == "R" || word == "u8R" || word == "uR" || word == "UR" || word == "LR") &&
                     i + 1 < text.size() && text[i + 1] == '"';
          size_t open = raw ? text.find_first_of("( )\\\t\n\"", i + 2) : std::string_view::npos;
          if (open != std::string_view::npos && text[open] == '(' && open - (i + 2) <= 16) {
            // R"delimiter( … )delimiter": nothing inside counts, line breaks included.
            rawEnd = ")" + std::string(text.substr(i + 2, open - (i + 2))) + "\"";
            state = RawString;
            i = open;
          }
          // An encoding prefix (u8"…", L'x') is read as the literal after it, next time round.
        }
        break;
      case LineComment:
        if (c == '\n') state = Code;
        break;
      case BlockComment:
        if (c == '*' && next == '/') state = Code, ++i;
        break;
      case String:
      case Char:
        if (c == '\\') ++i;
        else if (c == (state == String ? '"' : '\'') || c == '\n') state = Code;  // no literal spans lines
        break;
      case RawString:
        if (text.substr(i, rawEnd.size()) == rawEnd) state = Code, i += rawEnd.size() - 1;
        break;
    }
  }
  size_t end = text.find_last_not_of(" \t\r\n");
  bool continued = end != std::string_view::npos && text[end] == '\\' && state != RawString;
  return depth <= 0 && state != BlockComment && state != RawString && !continued;
}

std::vector<std::string> completeFileName(std::string_view prefix) {
  namespace fs = std::filesystem;
  size_t slash = prefix.rfind('/');
  std::string dir = slash == std::string_view::npos ? "" : std::string(prefix.substr(0, slash + 1));
  std::string_view base = slash == std::string_view::npos ? prefix : prefix.substr(slash + 1);
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::string name = it->path().filename().string();
    if (name.compare(0, base.size(), base) != 0) continue;
    if (name[0] == '.' && (base.empty() || base[0] != '.')) continue;
    std::error_code dirEc;
    out.push_back(dir + name + (it->is_directory(dirEc) ? "/" : ""));
  }
  std::sort(out.begin(), out.end());
  return out;
}

Completion complete(std::string_view line, size_t cursor, const CompletionSources& sources) {
  cursor = std::min(cursor, line.size());
  Completion c;
  size_t breakAt = line.substr(0, cursor).find_last_of(kWordBreaks);
  c.start = breakAt == std::string_view::npos ? 0 : breakAt + 1;
  std::string_view word = line.substr(c.start, cursor - c.start);
  // The words before the one being completed, split on blanks only (quotes do not matter here).
  const std::vector<std::string_view> before = runtime::textfile::words(line.substr(0, c.start));

  size_t first = line.find_first_not_of(" \t");
  bool command = first != std::string_view::npos && first < cursor && line[first] == ':';
  if (!command) {
    c.candidates = withPrefix(sources.modules, word);
    return c;
  }
  if (before.empty()) {
    c.candidates = withPrefix(sources.commands, word);
    return c;
  }
  const std::string_view name = before[0];
  if (name == ":load" || name == ":save") {
    c.candidates = completeFileName(word);
  } else if (name == ":string") {
    // Module names follow --module up to the next option.
    auto option = std::find_if(before.rbegin(), before.rend(), [](std::string_view w) { return w.substr(0, 2) == "--"; });
    if (!word.empty() && word[0] == '-') c.candidates = withPrefix({"--count", "--from", "--module"}, word);
    else if (option != before.rend() && *option == "--module") c.candidates = withPrefix(sources.modules, word);
  } else if (name == ":set" && before.size() == 1) {
    c.candidates = withPrefix(sources.parameters, word);
  } else if (name == ":watch" && before.size() == 1) {
    c.candidates = withPrefix({"off", "on"}, word);
  } else if (name == ":view" && before.size() == 1) {
    c.candidates = withPrefix({"close"}, word);
  } else if (name == ":help" && before.size() == 1) {
    c.candidates = withPrefix(sources.commands, word);
  }
  return c;
}

}  // namespace lcjit::repl
