// Parses a Context Free design (Parser.h). A recursive-descent reading of CFDG 3's grammar:
// statements at file level, elements in rule bodies, expressions at three levels (a comma list,
// a full expression, and the narrower argument of an adjustment term, where `x 1 -2` is two
// arguments).
#include "frontend/cfdg/Parser.h"

#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "frontend/cfdg/Entropy.h"  // builtinFunction
#include "runtime/cfdg/Paths.h"  // Context Free's path flags
#include "runtime/include/lcjit/cfdg.h"  // __cf_StateDoubles
#include "support/InputFile.h"

namespace lcjit::frontend::cfdg {

std::string adjustmentWord(std::string_view w) {
  static const std::map<std::string_view, std::string_view> kWords = {
      {"x", "x"}, {"y", "y"}, {"z", "z"}, {"size", "s"}, {"s", "s"}, {"rotate", "r"}, {"r", "r"},
      {"flip", "f"}, {"f", "f"}, {"skew", "skew"}, {"transform", "trans"}, {"trans", "trans"},
      {"hue", "h"}, {"h", "h"}, {"saturation", "sat"}, {"sat", "sat"}, {"brightness", "b"},
      {"b", "b"}, {"alpha", "a"}, {"a", "a"}, {"blend", "blend"}, {"time", "time"},
      {"timescale", "timescale"}};
  auto it = kWords.find(w);
  return it == kWords.end() ? std::string() : std::string(it->second);
}

namespace {

struct ParseError {
  Place at;
  std::string message;
};

// Where an imported design is found: beside the design that imports it, else among Context
// Free's own examples (which Context Free builds in: designs import them by name).
constexpr const char* kContextFreeExamples = "/usr/share/doc/contextfree/examples";

class Parser {
 public:
  // `space`: the namespace the file's names are put in ("ns::", or "" for none); `depth`: how deep
  // in imports the file is.
  Parser(std::vector<Token> tokens, const std::string& file, std::set<std::string>& open, std::string space = {},
         int depth = 0)
      : t_(std::move(tokens)), file_(file), open_(open), space_(std::move(space)), depth_(depth) {}

  void parseInto(Design& d, bool imported, bool forceVersion3 = false, bool commandLine = false) {
    design_ = &d;
    imported_ = imported;
    commandLine_ = commandLine;
    v2_ = !forceVersion3 && isVersion2();
    if (!imported) d.version = v2_ ? 2 : 3;
    while (peek().kind != Tok::End) v2_ ? statement2(d) : statement(d);
  }

 private:
  std::vector<Token> t_;
  size_t i_ = 0;
  std::string file_;
  std::set<std::string>& open_;  // the files being read (an import of one of them is skipped)
  bool imported_ = false;
  std::string current_;  // the shape the rules being read belong to
  bool v2_ = false;      // CFDG 2, the older syntax
  bool commandLine_ = false;  // reading -D definitions
  bool inPath_ = false;  // reading a path's body: FILL and STROKE are its commands
  bool v2Command_ = false;  // reading a CFDG 2 path command's adjustment (width and p words)
  std::string space_;  // the namespace of an `import @ns` file: "ns::"
  int depth_ = 0;      // of imports
  Design* design_ = nullptr;

  // A name written in a file imported with a namespace (`import @ns file`) is that namespace's,
  // `ns::NAME`, as Context Free names it: shapes, paths, functions, variables and parameters
  // alike, but not CF:: names, built-in functions, nor a primitive while the namespace declares
  // no shape of its name. The seeds take the name as written.
  std::string qualify(const std::string& name) const {
    if (space_.empty() || name.rfind("CF::", 0) == 0) return name;
    if (name == "CIRCLE" || name == "SQUARE" || name == "TRIANGLE" || name == "FILL") {
      bool declared = false;
      for (const ShapeDecl& s : design_->shapes) declared |= s.name == space_ + name;
      if (!declared) return name;
    }
    return space_ + name;
  }
  // The name and, when it differs, the name as written (Ast.h's `written` fields).
  void qualify(const std::string& name, std::string& qualified, std::string& written) const {
    qualified = qualify(name);
    written = qualified == name ? std::string() : name;
  }

  // CFDG 2 writes `rule NAME {`; CFDG 3 declares shapes with `shape NAME`.
  bool isVersion2() const {
    for (size_t k = 0; k + 2 < t_.size(); ++k) {
      const Token& t = t_[k];
      if (t.kind == Tok::Name && t.text == "shape" && (k == 0 || t_[k - 1].text == "}" || t_[k - 1].kind != Tok::Name))
        return false;
      if (t.kind == Tok::Name && t.text == "rule" && t_[k + 1].kind == Tok::Name &&
          (t_[k + 2].text == "{" || t_[k + 2].kind == Tok::Number))
        return true;
      // CFDG 2's directives with an adjustment in braces (CFDG 3 writes CF::Tile = [ … ]).
      if (t.kind == Tok::Name && (t.text == "tile" || t.text == "background" || t.text == "size") &&
          t_[k + 1].text == "{")
        return true;
      if (t.kind == Tok::PathOp && t_[k + 1].kind == Tok::Punct && t_[k + 1].text == "{")  // MOVETO {x 1}
        return true;
    }
    return false;
  }

  // ---- CFDG 2 ----
  void statement2(Design& d) {
    const Token& t = peek();
    if (t.kind != Tok::Name) unexpected("startshape, rule, path, include or background");
    if (t.text == "startshape") {
      next();
      Token name = expectName("a shape name after startshape");
      if (imported_ && !d.startShape.empty()) return;
      d.startShape = name.text;
      d.startAt = name.at;
      return;
    }
    if (t.text == "include" || t.text == "import") {
      next();
      const Token& f = peek();
      if (f.kind != Tok::FileName && f.kind != Tok::String && f.kind != Tok::Name) unexpected("a file name");
      Token name = next();
      importFile(name, d);
      return;
    }
    if (t.text == "background" || t.text == "tile" || t.text == "size" || t.text == "s" || t.text == "time") {
      Token word = next();
      Definition def;
      def.name = word.text == "background" ? "CF::Background" : word.text == "tile" ? "CF::Tile"
                 : word.text == "time" ? "CF::Time" : "CF::Size";
      def.at = word.at;
      def.depth = depth_;
      def.config = true;
      auto e = make(Expr::Modification, peek().at);
      e->adjustment = std::make_shared<Adjustment>(modification2());
      def.value = std::move(e);
      d.definitions.push_back(std::move(def));
      return;
    }
    if (t.text == "rule") {
      next();
      Token name = expectName("a shape name after rule");
      size_t existing = 0;
      while (existing < d.shapes.size() && d.shapes[existing].name != name.text) ++existing;
      if (existing == d.shapes.size()) {
        ShapeDecl s;
        s.name = name.text;
        s.at = name.at;
        d.shapes.push_back(std::move(s));
      }
      Rule r;
      r.shape = name.text;
      r.at = t.at;
      if (peek().kind == Tok::Number) weight(next(), r);
      expect("{");
      while (!accept("}")) {
        if (peek().kind == Tok::End) unexpected("'}'");
        r.body.push_back(replacement2());
      }
      addRule(d, std::move(r));
      return;
    }
    if (t.text == "path") {
      next();
      Token name = expectName("a path name after path");
      ShapeDecl s;
      s.name = name.text;
      s.at = name.at;
      s.isPath = true;
      d.shapes.push_back(std::move(s));
      Rule r;
      r.shape = name.text;
      r.at = name.at;
      r.isPath = true;
      expect("{");
      while (!accept("}")) {
        if (peek().kind == Tok::End) unexpected("'}'");
        r.body.push_back(pathElement2());
      }
      addRule(d, std::move(r));
      return;
    }
    unexpected("startshape, rule, path, include or background");
  }

  // A CFDG 2 path's element: `MOVETO {x 1 y 2}`, `STROKE {width 0.1 p roundjoin}`, `N * {adj} …`.
  std::unique_ptr<Element> pathElement2() {
    auto e = std::make_unique<Element>();
    e->at = peek().at;
    if (peek().kind == Tok::Number) {
      loop2(*e, &Parser::pathElement2);
      return e;
    }
    if (peek().kind == Tok::PathOp) {
      e->kind = Element::PathOp;
      e->name = next().text;
      pathOpArguments2(*e);
      return e;
    }
    if (is("STROKE") || is("FILL")) {
      e->kind = Element::PathCommand;
      e->name = next().text;
      v2Command_ = true;
      e->adjustment = modification2();
      v2Command_ = false;
      // `p` words are flags (they add nothing to the seed); `width` stays a term for its bytes.
      auto& terms = e->adjustment.terms;
      for (auto it = terms.begin(); it != terms.end();) {
        if (it->word != "p") {
          ++it;
          continue;
        }
        e->flags |= flagsOfWords(it->args[0]->text);
        it = terms.erase(it);
      }
      return e;
    }
    unexpected("a path operation (MOVETO …), STROKE, FILL or a loop");
  }

  // `{x 1 y 2 x1 … rx … r … p cw}`: Context Free's named arguments of a CFDG 2 path operation,
  // put in the order CFDG 3 writes them: x y, then (arcs) rx ry angle or the radius, (curves) the
  // first control point if given (else the curve continues the previous one), the second.
  void pathOpArguments2(Element& e) {
    const Place at = peek().at;
    expect("{");
    std::map<std::string, ExprP> args;
    while (!accept("}")) {
      Token w = expectName("a path operation argument (x, y, x1, y1, x2, y2, rx, ry, r, p)");
      std::string word = w.text == "rotate" ? "r" : w.text == "param" ? "p" : w.text;
      if (word == "p") {
        e.flags |= flagsOfWords(next().text);
        continue;
      }
      static const std::set<std::string> kWords = {"x", "y", "x1", "y1", "x2", "y2", "rx", "ry", "r"};
      if (!kWords.count(word)) fail(w.at, "'" + w.text + "' is not an argument of a path operation");
      if (args.count(word)) fail(w.at, "'" + w.text + "' is given twice");
      args[word] = adjArg();
    }
    if (e.name == "CLOSEPOLY") {
      if (!args.empty()) fail(at, "CLOSEPOLY takes no arguments, only flags");
      return;
    }
    auto list = make(Expr::List, at);
    auto take = [&](const char* word, const char* number) {
      auto it = args.find(word);
      list->args.push_back(it != args.end() ? std::move(it->second) : make(Expr::Number, at, number));
      if (it != args.end()) args.erase(it);
    };
    take("x", "0"), take("y", "0");
    const std::string& op = e.name;
    if (op == "ARCTO" || op == "ARCREL") {
      if (args.count("rx") || args.count("ry")) take("rx", "1"), take("ry", "1"), take("r", "0");
      else take("r", "1");
    } else if (op == "CURVETO" || op == "CURVEREL") {
      if (args.count("x1") || args.count("y1")) take("x1", "0"), take("y1", "0");
      else e.flags |= runtime::cfdg::kContinuous;
      if (args.count("x2") || args.count("y2")) take("x2", "0"), take("y2", "0");
    }
    if (!args.empty()) fail(at, "'" + args.begin()->first + "' is not an argument of " + op);
    e.value = std::move(list);
  }

  // CFDG 2's `N * {adj} body`, whose body is one element or a block of them, each read by `item`
  // (a rule's replacements or a path's operations).
  void loop2(Element& e, std::unique_ptr<Element> (Parser::*item)()) {
    Token count = next();
    expect("*");
    e.kind = Element::Loop;
    e.v2Loop = true;
    e.v2Count = count.text;
    e.value = make(Expr::Number, count.at, count.text);
    e.adjustment = modification2();
    if (accept("{")) {
      while (!accept("}")) {
        if (peek().kind == Tok::End) unexpected("'}'");
        e.body.push_back((this->*item)());
      }
    } else {
      e.body.push_back((this->*item)());
    }
  }

  // NAME {adj} | NAME [adj] | N * {adj} body
  std::unique_ptr<Element> replacement2() {
    auto e = std::make_unique<Element>();
    e->at = peek().at;
    if (peek().kind == Tok::Number) {
      loop2(*e, &Parser::replacement2);
      return e;
    }
    e->kind = Element::Replace;
    Token name = expectName("a shape name");
    e->shape = name.text;
    e->shapeAt = name.at;
    e->adjustment = modification2();
    return e;
  }

  // Context Free's flags named in a CFDG 2 `p` word (or string): each name it contains counts.
  static int flagsOfWords(const std::string& words) {
    using namespace runtime::cfdg;
    static const std::pair<const char*, int> kFlags[] = {
        {"evenodd", kEvenOdd}, {"iso", kIsoWidth}, {"miterjoin", 0 | kJoinPresent},
        {"roundjoin", 2 | kJoinPresent}, {"beveljoin", 3 | kJoinPresent}, {"buttcap", (0 << 4) | kCapPresent},
        {"squarecap", (1 << 4) | kCapPresent}, {"roundcap", (2 << 4) | kCapPresent}, {"large", kArcLarge},
        {"cw", kArcCW}, {"align", kAlign}};
    int flags = 0;
    for (const auto& [name, value] : kFlags)
      if (words.find(name) != std::string::npos) flags |= value;
    return flags;
  }

  // { … } in canonical order, [ … ] as written.
  Adjustment modification2() {
    Adjustment a;
    a.at = peek().at;
    if (accept("{")) {
      terms(a, "}");
      expect("}");
      return a;
    }
    expect("[");
    a.ordered = true;
    terms(a, "]");
    expect("]");
    return a;
  }

  // `space`: the namespace the imported file's names go in (within this file's own).
  void importFile(const Token& name, Design& d, const std::string& space = {}) {
    namespace fs = std::filesystem;
    fs::path beside = fs::path(file_).parent_path() / name.text;
    fs::path path = fs::exists(beside) ? beside : fs::path(kContextFreeExamples) / fs::path(name.text).filename();
    std::string key = fs::weakly_canonical(path).string();
    if (open_.count(key)) return;
    auto text = support::readInputFile(path.string(), /*nullTerminated=*/false);
    if (!text) fail(name.at, "cannot read " + name.text + ": " + text.getError().message());
    auto tokens = tokenize((*text)->getBuffer(), path.string());
    if (!tokens) {
      std::string message = llvm::toString(tokens.takeError());
      fail(name.at, "in " + name.text + ": " + message);
    }
    open_.insert(key);
    d.imports.push_back(path.string());
    Parser inner(std::move(*tokens), path.string(), open_, space_ + space, depth_ + 1);
    inner.parseInto(d, true);
  }

  const Token& peek(size_t k = 0) const { return t_[std::min(i_ + k, t_.size() - 1)]; }
  Token next() { return t_[i_ < t_.size() - 1 ? i_++ : i_]; }
  bool is(std::string_view text, size_t k = 0) const {
    const Token& t = peek(k);
    return (t.kind == Tok::Punct || t.kind == Tok::Name) && t.text == text;
  }
  bool accept(std::string_view text) {
    if (!is(text)) return false;
    ++i_;
    return true;
  }
  [[noreturn]] void fail(const Place& at, const std::string& message) { throw ParseError{at, message}; }
  // A rule (or a path's body) is the design's with the file it is written in.
  void addRule(Design& d, Rule r) {
    r.file = file_;
    d.rules.push_back(std::move(r));
  }
  [[noreturn]] void unexpected(const std::string& wanted) {
    const Token& t = peek();
    fail(t.at, t.kind == Tok::End ? "unexpected end of file, expected " + wanted
                                  : "unexpected '" + t.text + "', expected " + wanted);
  }
  void expect(std::string_view text) {
    if (!accept(text)) unexpected("'" + std::string(text) + "'");
  }
  Token expectName(const std::string& what) {
    if (peek().kind != Tok::Name && peek().kind != Tok::ArrayName) unexpected(what);
    return next();
  }

  static bool isType(std::string_view w) {
    return w == "number" || w == "natural" || w == "adjustment" || w == "shape" ||
           (w.substr(0, 6) == "vector" && w.size() > 6);
  }

  // ---- file level ----
  void statement(Design& d) {
    const Token& t = peek();
    if (t.kind != Tok::Name) unexpected("a statement");
    if (t.text == "startshape") {
      next();
      Token name = expectName("a shape name after startshape");
      if (imported_ && !d.startShape.empty()) {  // the importing design's start shape counts
        if (is("(")) argList(nullptr);
        if (is("[")) modification();
        return;
      }
      d.startShape = name.text;
      d.startAt = name.at;
      if (is("(")) d.startArgs = argList(nullptr);
      if (is("[")) {
        d.startHasAdjustment = true;
        d.startAdjustment = modification();
      }
      return;
    }
    if (t.text == "import" || t.text == "include") {
      next();
      std::string space;
      const Place at = peek().at;
      if (accept("@")) {
        Token ns = expectName("a namespace");
        if (ns.text == "CF") fail(at, "CF namespace is reserved");
        space = ns.text + "::";
      }
      const Token& f = peek();
      if (f.kind != Tok::FileName && f.kind != Tok::String) unexpected("a file name");
      Token name = next();
      importFile(name, d, space);
      return;
    }
    if (t.text == "shape" && !shapeFunction()) {
      next();
      ShapeDecl s;
      Token name = expectName("a shape name");
      s.name = qualify(name.text);
      s.at = name.at;
      if (is("(")) s.params = params();
      // A shape declared again takes more rules, and the parameters it was first declared with.
      size_t existing = 0;
      while (existing < d.shapes.size() && d.shapes[existing].name != s.name) ++existing;
      if (existing < d.shapes.size()) {
        if (!s.params.empty())
          fail(s.at, "Shape has already been declared. Parameter declaration must be on the first shape declaration only.");
        if (d.shapes[existing].isPath) fail(s.at, "Shape name already in use by another rule or path");
      } else {
        d.shapes.push_back(std::move(s));
      }
      current_ = d.shapes[existing].name;  // the rules that follow are its
      if (is("{")) {
        Rule r;
        r.shape = current_;
        r.at = peek().at;
        r.body = block();
        addRule(d, std::move(r));
      } else {
        while (is("rule")) {
          Rule r;
          r.shape = current_;
          r.at = next().at;
          if (peek().kind == Tok::Number) weight(next(), r);
          r.body = block();
          addRule(d, std::move(r));
        }
      }
      return;
    }
    if (t.text == "rule") {
      if (current_.empty()) fail(t.at, "a rule must follow a shape declaration");
      next();
      Rule r;
      r.shape = current_;
      r.at = t.at;
      if (peek().kind == Tok::Number) weight(next(), r);
      r.body = block();
      addRule(d, std::move(r));
      return;
    }
    if (t.text == "path") {
      next();
      ShapeDecl s;
      Token name = expectName("a path name");
      s.name = qualify(name.text);
      s.at = name.at;
      s.isPath = true;
      if (is("(")) s.params = params();
      Rule r;
      r.shape = s.name;
      d.shapes.push_back(std::move(s));
      r.at = name.at;
      r.isPath = true;
      inPath_ = true;
      r.body = block();
      inPath_ = false;
      addRule(d, std::move(r));
      return;
    }
    // Definitions: NAME = e, CF::Name = e, [TYPE] NAME(params) = e.
    Definition def;
    def.declaredAt = t.at;
    if (isType(t.text) && peek(1).kind == Tok::Name) def.type = next().text;
    Token name = expectName("a definition");
    qualify(name.text, def.name, def.written);
    def.at = name.at;
    def.depth = commandLine_ ? -1 : depth_;
    def.config = def.name.rfind("CF::", 0) == 0;
    if (is("(")) {
      def.isFunction = true;
      def.params = params();
    }
    expect("=");
    def.value = exp2();
    def.commandLine = commandLine_;
    for (const Definition& given : d.definitions)
      if (given.commandLine && given.name == def.name && !commandLine_) return;  // -D's value wins
    d.definitions.push_back(std::move(def));
  }

  // `shape NAME(params) = …`: a function whose value is a shape, not a shape's declaration.
  bool shapeFunction() const {
    if (!is("(", 2)) return false;
    int depth = 0;
    for (size_t k = 2; i_ + k < t_.size(); ++k) {
      const Token& t = peek(k);
      if (t.kind == Tok::End) return false;
      if (t.kind == Tok::Punct && t.text == "(") ++depth;
      if (t.kind == Tok::Punct && t.text == ")" && --depth == 0) return is("=", k + 1);
    }
    return false;
  }

  void weight(const Token& w, Rule& r) {
    std::string text = w.text;
    if (!text.empty() && text.back() == '%') {
      r.percent = true;
      text.pop_back();
      r.weight = std::strtod(text.c_str(), nullptr) / 100.0;
    } else {
      r.weight = std::strtod(text.c_str(), nullptr);
    }
  }

  std::vector<Param> params() {
    std::vector<Param> out;
    expect("(");
    if (accept(")")) return out;
    do {
      Param p;
      p.at = peek().at;
      Token first = expectName("a parameter");
      if (isType(first.text) && peek().kind == Tok::Name) {
        p.type = first.text;
        p.name = qualify(next().text);
      } else {
        p.type = "number";
        p.name = qualify(first.text);
      }
      if (p.type.rfind("vector", 0) == 0) p.width = std::atoi(p.type.c_str() + 6);
      if (p.type == "adjustment") p.width = __cf_StateDoubles;  // the room a __cf_State takes
      out.push_back(std::move(p));
    } while (accept(","));
    expect(")");
    return out;
  }

  // ---- bodies ----
  Body block() {
    Body b;
    expect("{");
    while (!accept("}")) {
      if (peek().kind == Tok::End) unexpected("'}'");
      b.push_back(element());
    }
    return b;
  }
  Body bodyOrElement() {
    if (is("{")) return block();
    Body b;
    b.push_back(element());
    return b;
  }

  std::unique_ptr<Element> element() {
    auto e = std::make_unique<Element>();
    const Token& t = peek();
    e->at = t.at;
    if (t.kind == Tok::PathOp) {
      e->kind = Element::PathOp;
      e->name = next().text;
      expect("(");
      if (!is(")")) e->value = exp2();
      expect(")");
      return e;
    }
    if (t.kind != Tok::Name && t.kind != Tok::ArrayName) unexpected("a shape, loop, if or definition");
    if (t.text == "loop") {
      next();
      e->kind = Element::Loop;
      if (peek().kind == Tok::Name && is("=", 1)) {
        qualify(next().text, e->name, e->nameWritten);
        next();
      }
      e->value = exp2();
      e->adjustment = modification();
      e->body = bodyOrElement();
      if (accept("finally")) e->otherwise = bodyOrElement();
      return e;
    }
    if (t.text == "if" && !isShapeIf()) {
      next();
      e->kind = Element::If;
      expect("(");
      e->value = exp2();
      expect(")");
      e->body = bodyOrElement();
      if (accept("else")) e->otherwise = bodyOrElement();
      return e;
    }
    if (t.text == "switch") {
      next();
      e->kind = Element::Switch;
      expect("(");
      e->value = exp2();
      expect(")");
      expect("{");
      while (!accept("}")) {
        Element::Case c;
        if (accept("else")) {
          expect(":");
        } else {
          expect("case");
          c.values.push_back(exp2());
          expect(":");
        }
        c.body = bodyOrElement();
        e->cases.push_back(std::move(c));
      }
      return e;
    }
    if (t.text == "transform" || t.text == "trans" || t.text == "clone") {
      e->kind = t.text == "clone" ? Element::Clone : Element::Transform;
      next();
      e->value = exp2();
      e->body = bodyOrElement();
      return e;
    }
    if (t.kind == Tok::Name && is("=", 1)) {
      e->kind = Element::Define;
      qualify(next().text, e->name, e->nameWritten);
      next();
      e->value = exp2();
      return e;
    }
    if (t.text == "if" || t.text == "select" || t.text == "let") {
      e->kind = Element::Replace;
      e->shapeAt = t.at;
      e->shapeExpr = primary();
      e->adjustment = modification();
      return e;
    }
    if ((t.text == "STROKE" || t.text == "FILL") && (is("(", 1) || (inPath_ && is("[", 1)))) {
      e->kind = Element::PathCommand;
      e->name = next().text;
      if (is("(")) e->args = argList(nullptr);
      e->adjustment = modification();
      return e;
    }
    if (t.text == "path") {  // a sub-path
      next();
      e->subpath = true;
    }
    e->kind = Element::Replace;
    Token name = expectName("a shape name");
    qualify(name.text, e->shape, e->shapeWritten);
    e->shapeAt = name.at;
    if (is("(")) {
      e->hasArgs = true;
      e->args = argList(&e->reuseParams);
    }
    e->adjustment = modification();
    return e;
  }

  // `if (…)` that chooses a shape (`if (c, A, B) [adj]`) rather than an if statement: the
  // parenthesis is followed by an adjustment.
  bool isShapeIf() const {
    int depth = 0;
    for (size_t k = 1; i_ + k < t_.size(); ++k) {
      const Token& t = peek(k);
      if (t.kind == Tok::Punct && t.text == "(") ++depth;
      if (t.kind == Tok::Punct && t.text == ")" && --depth == 0) return peek(k + 1).kind == Tok::Punct && peek(k + 1).text == "[";
      if (t.kind == Tok::End) return false;
    }
    return false;
  }

  // ( args ), (=), ()
  std::vector<ExprP> argList(bool* reuse) {
    std::vector<ExprP> out;
    expect("(");
    if (is("=") && is(")", 1)) {
      next();
      next();
      if (reuse) *reuse = true;
      return out;
    }
    if (accept(")")) return out;
    do out.push_back(exp3()); while (accept(","));
    expect(")");
    return out;
  }

  Adjustment modification() {
    Adjustment a;
    a.at = peek().at;
    expect("[");
    if (is("[")) {
      next();
      a.ordered = true;
      terms(a, "]");
      expect("]");
      expect("]");
      return a;
    }
    terms(a, "]");
    expect("]");
    return a;
  }

  void terms(Adjustment& a, std::string_view close) {
    while (!is(close)) {
      Term term;
      term.at = peek().at;
      bool targetWord = false;
      if (is("|")) {
        next();
        targetWord = true;
      }
      if (peek().kind != Tok::Name) unexpected("an adjustment or '" + std::string(close) + "'");
      Token w = next();
      if (v2Command_ && !targetWord && (w.text == "width" || w.text == "p" || w.text == "param")) {
        // A CFDG 2 path command's stroke width, or its flags (`p roundjoin`), kept as terms: their
        // bytes count in the command's seed.
        term.word = w.text == "width" ? "width" : "p";
        if (term.word == "width") {
          term.args.push_back(adjArg());
        } else {
          Token f = next();
          term.args.push_back(make(Expr::Name, f.at, f.text));
        }
        a.terms.push_back(std::move(term));
        continue;
      }
      std::string word = adjustmentWord(w.text);
      if (word.empty()) fail(w.at, "'" + w.text + "' is not an adjustment (x, y, z, s, r, f, skew, trans, h, sat, b, a, blend, time)");
      term.word = targetWord ? "|" + word : word;
      term.args.push_back(adjArg());
      while (!is(close) && !startsTerm() && (startsExpression() || is("|"))) {
        if (is("|")) {
          next();
          term.targetForm = true;
          break;
        }
        term.args.push_back(adjArg());
      }
      a.terms.push_back(std::move(term));
    }
  }
  bool startsExpression() const {
    const Token& t = peek();
    if (t.kind == Tok::Number || t.kind == Tok::Name || t.kind == Tok::ArrayName) return true;
    return t.kind == Tok::Punct && (t.text == "(" || t.text == "-" || t.text == "+" || t.text == "[");
  }
  bool startsTerm() const {
    const Token& t = peek();
    // `|b` (no space) is a target colour word; `b 0.5| b 0.2` ends a target form.
    if (t.kind == Tok::Punct && t.text == "|") {
      const Token& w = peek(1);
      std::string word = w.kind == Tok::Name && !w.spaceBefore ? adjustmentWord(w.text) : "";
      return word == "h" || word == "sat" || word == "b" || word == "a";
    }
    if (v2Command_ && t.kind == Tok::Name && (t.text == "width" || t.text == "p" || t.text == "param")) return true;
    // Adjustment words are reserved: `s (2)` and `s(2)` start a term, never call a function.
    return t.kind == Tok::Name && !adjustmentWord(t.text).empty();
  }

  // ---- expressions ----
  ExprP make(Expr::Kind k, Place at, std::string text = {}) {
    auto e = std::make_unique<Expr>();
    e->kind = k;
    e->at = at;
    e->text = std::move(text);
    return e;
  }
  ExprP binary(std::string op, Place opAt, ExprP l, ExprP r) {
    auto e = make(Expr::Binary, l->at, std::move(op));
    e->opAt = opAt;
    e->args.push_back(std::move(l));
    e->args.push_back(std::move(r));
    return e;
  }

  // a, b, c
  ExprP exp2() {
    ExprP first = exp3();
    if (!is(",")) return first;
    auto list = make(Expr::List, first->at);
    list->args.push_back(std::move(first));
    while (accept(",")) list->args.push_back(exp3());
    return list;
  }

  static int precedence(const std::string& op) {
    if (op == "^^") return 1;
    if (op == "||") return 2;
    if (op == "&&") return 3;
    if (op == "==" || op == "<>") return 4;
    if (op == "<" || op == "<=" || op == ">" || op == ">=") return 5;
    if (op == ".." || op == "+/-") return 6;
    if (op == "+" || op == "-" || op == "--") return 7;
    if (op == "*" || op == "/") return 8;
    return 0;
  }
  ExprP exp3(int minPrec = 1) {
    ExprP left = unary();
    for (;;) {
      const Token& t = peek();
      if (t.kind != Tok::Punct) break;
      int p = precedence(t.text);
      if (p == 0 || p < minPrec) break;
      Place opAt = t.at;
      std::string op = next().text;
      ExprP right = exp3(p + 1);
      left = binary(op, opAt, std::move(left), std::move(right));
    }
    return left;
  }
  ExprP unary() {
    const Token& t = peek();
    if (t.kind == Tok::Punct && (t.text == "-" || t.text == "+" || t.text == "!")) {
      Place at = t.at;
      std::string op = next().text;
      auto e = make(Expr::Unary, at, op);
      e->args.push_back(unary());
      return e;
    }
    return power();
  }
  ExprP power() {
    ExprP base = primary();
    if (is("^")) {
      Place opAt = next().at;
      ExprP exponent = unary();  // right-associative, binds tighter than unary on its left
      return binary("^", opAt, std::move(base), std::move(exponent));
    }
    return base;
  }
  // The argument of an adjustment term: no bare binary operators.
  // Signs bind tighter than `..` and `+/-`: `-15..15` is (-15)..15.
  ExprP adjArg() {
    ExprP e = signedPrimary();
    while (is("..") || is("+/-")) {
      Place opAt = peek().at;
      std::string op = next().text;
      e = binary(op, opAt, std::move(e), signedPrimary());
    }
    return e;
  }
  ExprP signedPrimary() {
    if (peek().kind == Tok::Punct && (is("-") || is("+"))) {
      Place at = peek().at;
      std::string op = next().text;
      ExprP e = make(Expr::Unary, at, op);
      e->args.push_back(signedPrimary());
      return e;
    }
    return primary();
  }

  ExprP primary() {
    const Token& t = peek();
    if (t.kind == Tok::Number) {
      Token n = next();
      return make(Expr::Number, n.at, n.text);
    }
    if (t.kind == Tok::Punct && t.text == "(") {
      Place at = next().at;
      auto e = make(Expr::Paren, at);
      e->args.push_back(exp2());
      expect(")");
      return e;
    }
    if (t.kind == Tok::Punct && t.text == "[") {
      auto e = make(Expr::Modification, t.at);
      e->adjustment = std::make_shared<Adjustment>(modification());
      return e;
    }
    if (t.kind == Tok::ArrayName) {
      Token n = next();
      expect("[");
      auto e = make(Expr::Index, n.at, n.text);
      qualify(n.text, e->text, e->written);
      e->args.push_back(exp2());
      expect("]");
      return e;
    }
    if (t.kind == Tok::Name) {
      Token n = next();
      if (n.text == "let") {
        auto e = make(Expr::Let, n.at, "let");
        expect("(");
        for (;;) {
          if (peek().kind == Tok::Name && is("=", 1)) {
            e->names.push_back(qualify(next().text));
            next();
            e->args.push_back(exp2());
            expect(";");
            continue;
          }
          e->args.push_back(exp2());
          break;
        }
        expect(")");
        return e;
      }
      if (is("(")) {
        auto e = make(Expr::Call, n.at, n.text);
        if (!builtinFunction(n.text) && n.text != "if" && n.text != "select") qualify(n.text, e->text, e->written);
        e->args = argList(&e->reuseParams);
        return e;
      }
      auto e = make(Expr::Name, n.at, n.text);
      qualify(n.text, e->text, e->written);
      return e;
    }
    unexpected("an expression");
  }
};

}  // namespace

llvm::Expected<Design> parseDesign(std::string_view source, const std::string& file,
                                   const std::vector<std::string>& defines) {
  auto tokens = tokenize(source, file);
  if (!tokens) return tokens.takeError();
  Design d;
  d.file = file;
  std::set<std::string> open = {std::filesystem::weakly_canonical(file).string()};
  for (const std::string& define : defines) {
    const std::string where = "-D " + define;
    if (define.find('=') == std::string::npos)
      return llvm::createStringError(where + ": error: a definition is NAME=VALUE");
    auto given = tokenize(define, where);
    if (!given) return given.takeError();
    try {
      Parser p(std::move(*given), where, open);
      p.parseInto(d, false, /*forceVersion3=*/true, /*commandLine=*/true);
    } catch (ParseError& e) {
      return llvm::createStringError(where + ":" + std::to_string(e.at.column) + ": error: " + e.message);
    }
  }
  try {
    Parser p(std::move(*tokens), file, open);
    p.parseInto(d, false, /*forceVersion3=*/!defines.empty());
    return d;
  } catch (ParseError& e) {
    return llvm::createStringError(file + ":" + std::to_string(e.at.line) + ":" + std::to_string(e.at.column) +
                                   ": error: " + e.message);
  }
}

}  // namespace lcjit::frontend::cfdg
