// The C++ the rewriter generates apart from the model's own text: each module's struct, emitting
// function and field table; a module list's calls; a large axiom as a table read by a loop; and
// the model's description (__lc_model(): modules, rules, filters, the control functions), written
// after the model's text under a #line of its own.
//
// Sections, in order (each begins with a `// ----` rule): Modules (emitModule, emitCall) · Large
// axioms (tableLiteral, axiomTable) · The model description (cString, emitTables).
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>

#include "frontend/lc/Rewriter.h"
#include "frontend/lc/RewriterImpl.h"

namespace lcjit::frontend::detail {

// ---------------------------------------------------------------------------------------------
// Modules

// Each parameter type is written once, as a typedef with the user's tokens at their own columns,
// and the generated code names the alias: a misspelt type is one error at the type in the .l
// file, not one per generated use at columns past the line's end.
void Rewriter::emitModule(const Token& at, const Token& nameToken, int id, const std::vector<std::string>& types,
                          const std::vector<std::vector<Token>>& typeTokens) {
  const std::string& name = nameToken.text;
  std::vector<std::string> alias(types.size());
  for (size_t i = 0; i < types.size(); ++i) {
    alias[i] = "__lc_P_" + name + "_" + std::to_string(i);
    // A typedef whose type is unknown still declares the name (as invalid), which keeps Clang
    // quiet about its uses; an alias-declaration would not. Types with declarators (function
    // pointers, arrays) need the alias form.
    bool declarator = false;
    for (const Token& t : typeTokens[i]) declarator |= t.is("(") || t.is("[");
    out_.glueAt(typeTokens[i].front(), declarator ? "using " + alias[i] + " =" : "typedef");
    for (const Token& t : typeTokens[i]) out_.token(t);
    out_.glue(declarator ? ";" : " " + alias[i] + ";");
  }
  std::string R = "__lc_R_" + name;
  std::string s = "struct " + R + " { __lc_ModuleId id;";
  for (size_t i = 0; i < types.size(); ++i) s += " " + alias[i] + " p" + std::to_string(i) + ";";
  s += " __lc_ModuleId id2; }; enum : __lc_ModuleId { __lc_id_" + name + " = " + std::to_string(id) + " }; ";
  // The emitting function is placed at the module's name, for Clang's errors about it; its
  // code gets no lines of its own (nodebug): inlined, it takes the line of the produce or
  // nproduce that calls it, and called, its frame is passed over for the caller's. A fault or
  // a stop inside it (the string growing) is then named at the statement that was running,
  // not at the declaration with a column of the generated text past the line's end.
  s += "static inline __attribute__((__nodebug__)) void";
  out_.glueAt(at, s);
  s = "__lc_emit_" + name + "(__lc_Ctx* c";
  for (size_t i = 0; i < types.size(); ++i) s += ", " + alias[i] + " a" + std::to_string(i);
  s += ") { " + R + " r; __builtin_memset(&r, 0, sizeof r); r.id = r.id2 = " + std::to_string(id) + ";";
  for (size_t i = 0; i < types.size(); ++i) s += " r.p" + std::to_string(i) + " = a" + std::to_string(i) + ";";
  s += " __lc_put(c, &r, sizeof r); }";
  out_.replaceAt(nameToken, s);
  s = " static const __lc_Field __lc_fields_" + name + "[" + std::to_string(std::max<size_t>(types.size(), 1)) + "] = {";
  for (size_t i = 0; i < types.size(); ++i) {
    std::string quoted;
    for (char c : types[i]) quoted += c == '"' ? std::string("\\\"") : std::string(1, c);
    s += "{(uint32_t)__builtin_offsetof(" + R + ", p" + std::to_string(i) + "), (uint32_t)sizeof(" + alias[i] + "), __lc_kind_of<" +
         alias[i] + ">(), \"" + quoted + "\"},";
  }
  s += "};";
  out_.glue(s);
}

// `__lc_emit_A(__lc_ctx, <the parameters' tokens>);`, the name at the module's column.
void Rewriter::emitCall(const ModuleList& list, const ModuleCall& c) {
  const Token& name = lx_.tokens[c.name];
  out_.replaceAt(name, "__lc_emit_" + name.text + "(__lc_ctx");
  for (size_t k = 0; k < c.nargs; ++k) {
    out_.glue(",");
    auto [first, end] = list.args[c.firstArg + k];
    for (size_t i = first; i < end; ++i) out_.token(lx_.tokens[i]);
  }
  out_.glue(");");
}

// ---------------------------------------------------------------------------------------------
// Large axioms

// A parameter of a large axiom's module goes in its table (Rewriter::axiomTable) only where it
// means there exactly what it means in the call: converted to the parameter's type, the same value
// and no error either way (an array's initializer refuses the narrowing conversions a call
// takes). So: a plain decimal literal (no suffix but f, no digit separators), maybe signed, for a
// parameter of an arithmetic type that holds its value. An integer in the type's range (exactly
// representable in a float or double); a floating literal in a float or double without overflow
// or underflow. The table's element is then the literal as written; nullopt: keep the call.
std::optional<std::string> tableLiteral(const Token* sign, const Token& number, const std::string& type) {
  static const std::map<std::string, std::pair<long long, long long>> kIntegers = {
      {"int", {INT32_MIN, INT32_MAX}},   {"short", {INT16_MIN, INT16_MAX}},  {"unsigned short", {0, UINT16_MAX}},
      {"unsigned", {0, UINT32_MAX}},     {"unsigned int", {0, UINT32_MAX}},  {"long", {INT64_MIN, INT64_MAX}},
      {"long long", {INT64_MIN, INT64_MAX}}, {"unsigned long", {0, INT64_MAX}}, {"unsigned long long", {0, INT64_MAX}},
      {"float", {-(1LL << 24), 1LL << 24}}, {"double", {-(1LL << 53), 1LL << 53}}};
  const std::string& s = number.text;
  if (number.kind != Token::Number || s.empty()) return std::nullopt;
  const bool negative = sign && sign->text == "-";
  const std::string text = (sign ? sign->text : "") + s;
  // An integer: decimal digits, without a leading 0 (octal); up to 18 of them fit a long long.
  if (std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit((unsigned char)c); })) {
    if ((s.size() > 1 && s[0] == '0') || s.size() > 18) return std::nullopt;
    long long v = std::stoll(s) * (negative ? -1 : 1);
    auto range = kIntegers.find(type);
    if (range == kIntegers.end() || v < range->second.first || v > range->second.second) return std::nullopt;
    return text;
  }
  // A floating literal: digits with a '.' or an exponent or both, and maybe an f.
  if (type != "float" && type != "double") return std::nullopt;
  size_t i = 0, digits = 0;
  while (i < s.size() && std::isdigit((unsigned char)s[i])) ++i, ++digits;
  bool point = i < s.size() && s[i] == '.', exponent = false;
  if (point)
    for (++i; i < s.size() && std::isdigit((unsigned char)s[i]); ++i) ++digits;
  if (digits == 0) return std::nullopt;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    size_t e = ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) e = ++i;
    while (i < s.size() && std::isdigit((unsigned char)s[i])) ++i;
    if (i == e) return std::nullopt;
    exponent = true;
  }
  const bool isFloat = i < s.size() && (s[i] == 'f' || s[i] == 'F');
  if (i + isFloat != s.size() || !(point || exponent)) return std::nullopt;
  errno = 0;
  double d = std::strtod(s.substr(0, i).c_str(), nullptr);
  if (errno == ERANGE) return std::nullopt;
  if (isFloat || type == "float") {
    errno = 0;
    if (std::fabs(d) > FLT_MAX) return std::nullopt;
    float f = isFloat ? std::strtof(s.substr(0, i).c_str(), nullptr) : (float)d;
    if (errno == ERANGE || !std::isfinite(f) || (f == 0) != (d == 0) || (f != 0 && std::fabs(f) < FLT_MIN)) return std::nullopt;
  } else if (d != 0 && std::fabs(d) < DBL_MIN) {
    return std::nullopt;
  }
  return text;
}

// A large axiom is data (a model of a million modules is a 10 MB axiom), but as one function
// of calls its code generation grew faster than its length: 32,000 modules compiled in 2 s,
// 128,000 in 15 s, a million not in minutes. So an axiom of more than kAxiomPart modules is a
// table read by a loop: the module ids in order, and the parameters that are plain numbers
// (tableLiteral) in one array per type. A module with any other parameter (an expression, a
// constant's name, a call with side effects) keeps its call, at its own line and column, in a
// part: a function of at most kAxiomPart such calls, where each run of them (consecutive in the
// axiom) is one case of a switch. The ids say kAxiomCall where a run stands, and the loop calls
// its case there. Every module is written in its place and every expression evaluated in the
// axiom's order, as in the one function; each compiled function is bounded, and there are few
// of them (ORC's linking grows faster than their number), so the whole is linear in the axiom.
void Rewriter::axiomTable(const ModuleList& list, const Token& semi) {
  std::vector<std::string> types, values;  // the value arrays: each one's type and elements
  auto typeIndex = [&](const std::string& type) {
    auto it = std::find(types.begin(), types.end(), type);
    if (it != types.end()) return (size_t)(it - types.begin());
    types.push_back(type);
    values.emplace_back();
    return types.size() - 1;
  };
  std::map<int, std::string> cases;  // the loop's case of each module id in the table
  // The ids as a string, one character each: a million of them lex as one token, where an
  // array's initializer makes and checks an expression for each.
  std::string ids;
  auto hex = [](int id) {
    char b[8];
    std::snprintf(b, sizeof b, "\\x%x", id);
    return std::string(b);
  };
  std::vector<std::string> literals;
  size_t parts = 0, calls = 0, runs = 0;  // the parts so far; the calls and the runs in the open one
  bool inRun = false;                     // the module before was a call
  auto closePart = [&] { out_.glue("break; } return __lc_k == " + std::to_string(runs - 1) + "; }"); };
  for (const ModuleCall& c : list.calls) {
    const ModuleEntry& m = *c.module;
    const Token& name = lx_.tokens[c.name];
    literals.clear();
    for (size_t k = 0; k < c.nargs; ++k) {
      auto [first, end] = list.args[c.firstArg + k];
      const bool sign = end - first == 2 && (lx_.tokens[first].is("-") || lx_.tokens[first].is("+"));
      std::optional<std::string> v;
      if (end - first == 1 + sign) v = tableLiteral(sign ? &lx_.tokens[first] : nullptr, lx_.tokens[end - 1], m.paramTypes[k]);
      if (!v) break;
      literals.push_back(std::move(*v));
    }
    if (literals.size() == c.nargs) {
      inRun = false;
      ids += hex(m.id);
      std::map<size_t, int> taken;  // per value array, this module's elements
      std::string args;
      for (size_t k = 0; k < c.nargs; ++k) {
        size_t v = typeIndex(m.paramTypes[k]);
        values[v] += literals[k] + ",";
        args += ", __lc_v" + std::to_string(v) + "[" + std::to_string(taken[v]++) + "]";
      }
      if (!cases.count(m.id)) {
        std::string& s = cases[m.id];
        s = "case " + std::to_string(m.id) + ": __lc_emit_" + name.text + "(__lc_ctx" + args + ");";
        for (auto [v, count] : taken) s += " __lc_v" + std::to_string(v) + " += " + std::to_string(count) + ";";
        s += " break; ";
      }
      continue;
    }
    if (calls == kAxiomPart) {
      closePart();
      calls = 0;
      inRun = false;
    }
    if (calls == 0) {
      out_.glueAt(name, "__attribute__((optnone, noinline)) static bool __lc_axiom_part_" + std::to_string(parts++) +
                            "(__lc_Ctx* __lc_ctx, unsigned __lc_k) { switch (__lc_k) {");
      runs = 0;
    }
    if (!inRun) {
      ids += hex(kAxiomCall);
      out_.glueAt(name, (runs > 0 ? "break; case " : "case ") + std::to_string(runs) + ":");
      ++runs;
      inRun = true;
    }
    emitCall(list, c);
    ++calls;
  }
  if (calls > 0) closePart();
  // One line, that of the axiom's ';': anything said about the table belongs there.
  std::string s = "static const char16_t __lc_axiom_ids[] = u\"" + ids + "\";";
  for (size_t v = 0; v < types.size(); ++v)
    s += "static const " + types[v] + " __lc_axiom_values_" + std::to_string(v) + "[] = {" + values[v] + "};";
  if (parts > 0) {
    s += "static bool (*const __lc_axiom_parts[])(__lc_Ctx*, unsigned) = {";
    for (size_t p = 0; p < parts; ++p) s += "__lc_axiom_part_" + std::to_string(p) + ",";
    s += "};";
  }
  s += "static void __lc_axiom(__lc_Ctx* __lc_ctx) {";
  for (size_t v = 0; v < types.size(); ++v)
    s += "const " + types[v] + "* __lc_v" + std::to_string(v) + " = __lc_axiom_values_" + std::to_string(v) + ";";
  if (parts > 0) s += "unsigned __lc_part = 0, __lc_run = 0;";
  s += "for (unsigned __lc_i = 0; __lc_i < sizeof __lc_axiom_ids / 2 - 1; ++__lc_i) switch (__lc_axiom_ids[__lc_i]) {";
  for (auto& [id, c] : cases) s += c;
  if (parts > 0) s += "default: if (__lc_axiom_parts[__lc_part](__lc_ctx, __lc_run++)) ++__lc_part, __lc_run = 0;";
  s += "}}";
  out_.glueAt(semi, s);
}

// ---------------------------------------------------------------------------------------------
// The model description

std::string Rewriter::cString(const std::string& text) {
  std::string q = "\"";
  for (char c : text) {
    if (c == '\\' || c == '"') q += '\\';
    q += c;
  }
  return q + '"';
}

void Rewriter::emitTables() {
  // The tables compile whatever the model says, except after C++ the model leaves unfinished
  // (`template<`, a declaration without its ';'): the name carries where the model's text ends,
  // for DiagCollector to report that instead of errors inside the tables.
  std::string end;
  for (size_t i = lx_.tokens.size(); i-- > 0;) {
    const Token& t = lx_.tokens[i];
    if (t.kind == Token::End || t.kind == Token::Directive) continue;
    end = lx_.files[t.file] + ":" + std::to_string(t.line) + ":" + std::to_string(t.col + (int)t.text.size());
    break;
  }
  std::string s = "#line 1 " + cString(std::string(kTablesFile) + (end.empty() ? "" : " " + end) + ">") + "\n";
  s += "static const __lc_ModuleInfo __lc_user_modules[] = {";
  // One entry per id from the first user module's; ids skipped by `module X = N;` are
  // nameless and never used. userModules_ is in id order: ids only grow.
  int id = __lc_FirstUserModule;
  for (const ModuleDecl& m : userModules_) {
    for (; id < m.id; ++id) s += "{\"\", 4, 0, nullptr},";
    s += "{\"" + m.name + "\", " + "(uint32_t)sizeof(__lc_R_" + m.name + ")" + ", " +
         std::to_string(m.paramTypes.size()) + ", __lc_fields_" + m.name + "},";
    id = m.id + 1;
  }
  for (; id < nextModuleId_; ++id) s += "{\"\", 4, 0, nullptr},";
  if (userModules_.empty()) s += "{nullptr, 0, 0, nullptr}";
  s += "};\n";
  for (size_t i = 0; i < rules_.size(); ++i) {
    s += "static const __lc_ModuleId __lc_pattern_" + std::to_string(i) + "[] = {";
    for (int id : rules_[i].ids) s += std::to_string(id) + ",";
    s += "};\n";
  }
  for (size_t i = 0; i < filters_.size(); ++i) {
    s += "static const __lc_ModuleId __lc_filter_" + std::to_string(i) + "[] = {";
    for (int id : filters_[i].ids) s += std::to_string(id) + ",";
    if (filters_[i].ids.empty()) s += "0";
    s += "};\n";
  }
  s += "static const __lc_Filter __lc_filters[] = {";
  for (size_t i = 0; i < filters_.size(); ++i)
    s += "{" + std::to_string(filters_[i].consider ? 1 : 0) + ", " + std::to_string(filters_[i].ids.size()) + ", __lc_filter_" +
         std::to_string(i) + "},";
  if (filters_.empty()) s += "{0, 0, nullptr}";
  s += "};\n";
  s += "static const __lc_Rule __lc_rules[] = {";
  for (size_t i = 0; i < rules_.size(); ++i) {
    auto& r = rules_[i];
    s += "{" + std::to_string(r.kind) + ", " + std::to_string(r.groupKind) + ", (int16_t)(" + r.group + "), (int16_t)(" +
         r.vgroup + ")";
    for (int c : r.counts) s += ", " + std::to_string(c);
    s += ", " + std::to_string(r.filter) + ", __lc_pattern_" + std::to_string(i) + ", " + r.body + ", " + std::to_string(r.line) +
         ", " + cString(r.predecessor) + ", " + cString(r.file) + "},\n";
  }
  if (rules_.empty()) s += "{}";
  s += "};\n";
  auto fnOrNull = [&](bool have, const char* name) { return have ? std::string(name) : std::string("nullptr"); };
  std::string main = lx_.files.empty() ? "" : lx_.files[0];
  s += "static const __lc_ModuleId __lc_verify[] = {";
  for (int id : verify_) s += std::to_string(id) + ",";
  if (verify_.empty()) s += "0";
  s += "};\n";
  // NumOfViews: lpfg's translator counts the view groups declared, whether or not they hold rules.
  s += "static int __lc_num_of_views() { int n = 0;";
  for (const std::string& id : vgroupsDeclared_) s += " if ((int)(" + id + ") > n) n = (int)(" + id + ");";
  s += " return n + 1; }\n";
  s += "static const __lc_Model __lc_the_model = {" + std::to_string(__lc_AbiVersion) + ", " + std::to_string(nextModuleId_ - __lc_FirstUserModule) +
       ", __lc_user_modules, " + std::to_string(rules_.size()) + ", __lc_rules, " + std::to_string(filters_.size()) +
       ", __lc_filters, __lc_axiom, __lc_derivation_length, " + fnOrNull(haveRing_, "__lc_ring_lsystem") + ", " +
       fnOrNull(haveDecompDepth_, "__lc_decomposition_depth") + ", " + fnOrNull(haveInterpDepth_, "__lc_interpretation_depth") +
       ", " + fnOrNull(controls_.count("__lc_start"), "__lc_start") + ", " +
       fnOrNull(controls_.count("__lc_start_each"), "__lc_start_each") + ", " +
       fnOrNull(controls_.count("__lc_end_each"), "__lc_end_each") + ", " + fnOrNull(controls_.count("__lc_end"), "__lc_end") +
       ", " + cString(main) + ", " + std::to_string(verify_.size()) + ", __lc_verify, __lc_num_of_views};\n";
  s += "extern \"C\" const __lc_Model* __lc_model() { return &__lc_the_model; }\n";
  out_.generated(s);
}

}  // namespace lcjit::frontend::detail
