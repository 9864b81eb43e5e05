// Plain-language compile errors (see PlainErrors.h).
#include "app/common/PlainErrors.h"

#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

namespace lcjit::app {
namespace {

// The clang and lcjit messages a beginner meets most, and what they mean in L+C terms. $1 is the
// first quoted name of the message.
struct Meaning {
  std::regex message;
  const char* plain;
};

const std::vector<Meaning>& meanings() {
  static const std::vector<Meaning> table = [] {
    std::vector<std::pair<const char*, const char*>> rows = {
        {"use of undeclared identifier '([^']+)'",
         "'$1' is not defined. Check its spelling; a module must be declared with `module $1(...);` and a "
         "variable or function before the line that uses it."},
        {"undeclared module '([^']+)'",
         "'$1' is not a declared module: add `module $1(...);` with its parameter types before it is used, or "
         "check the spelling."},
        {"unknown type name '([^']+)'",
         "'$1' is not a type. Check its spelling, or whether `module $1(...);` or an #include is missing."},
        {"expected ';'", "A ';' is missing at the end of a statement or declaration (look at the end of this line "
                         "and the one before)."},
        {"expected '\\}'", "A closing '}' is missing: every '{' needs one."},
        {"expected '\\)'", "A closing ')' is missing: every '(' needs one."},
        {"expected '\\]'", "A closing ']' is missing."},
        {"expected expression", "A value is missing here (after an operator, a comma or an opening parenthesis?)."},
        {"expected unqualified-id|expected identifier",
         "This line is not something lcjit can read here: a statement outside a production or function body, or "
         "a stray word or symbol?"},
        {"no matching function for call to '([^']+)'",
         "'$1' is called with arguments it does not take: check how many there are and their types."},
        {"too (many|few) arguments", "A call or module has too $1 arguments."},
        {"redefinition of '([^']+)'", "'$1' is defined twice."},
        {"no viable conversion|cannot initialize|incompatible",
         "A value of the wrong type is used here (for example a module parameter of another type)."},
        {"no member named '([^']+)'", "There is no '$1' here: check the spelling of the field or function."},
        {"produce", "Check this produce statement: its modules and their parameters."},
        {"module", "Check this module: its declaration (`module Name(types);`) and the parameters used with it."},
    };
    std::vector<Meaning> t;
    for (auto& [re, plain] : rows) t.push_back({std::regex(re), plain});
    return t;
  }();
  return table;
}

}  // namespace

std::string inPlainLanguage(const std::string& diagnostics) {
  static const std::regex error(R"(^(.+):(\d+):(\d+): error: (.*)$)");
  std::string plain;
  std::set<std::string> said;
  std::istringstream in(diagnostics);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, error)) continue;
    std::string file = m[1], message = m[4];
    if (file.empty() || file[0] == '<') continue;  // lcjit's generated code: follows from an earlier error
    std::string sentence = message;
    for (const Meaning& meaning : meanings()) {
      std::smatch found;
      if (!std::regex_search(message, found, meaning.message)) continue;
      sentence = meaning.plain;
      std::string name = found.size() > 1 ? found[1].str() : "";
      for (size_t at; (at = sentence.find("$1")) != std::string::npos;) sentence.replace(at, 2, name);
      break;
    }
    std::string where = std::filesystem::path(file).filename().string() + ", line " + m[2].str();
    if (!said.insert(where + sentence).second) continue;
    plain += where + ": " + sentence + "\n";
  }
  if (plain.empty()) return diagnostics;
  return plain + "(what the compiler said:)\n" + diagnostics;
}

}  // namespace lcjit::app
