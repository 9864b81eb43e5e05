// XL → L+C (Translate.h): the translation written whole (Translator.h says where each part is),
// GroIMP's turtle commands looked up, and the front end's entry points.
#include "frontend/xl/Translate.h"

#include "frontend/xl/Translator.h"

namespace lcjit::frontend::xl {

std::vector<std::pair<std::string, int>> Translator::ruleMethods() const {
  std::vector<std::pair<std::string, int>> named;
  for (size_t k = 0; k < methods_.size(); ++k) named.emplace_back(t_[methods_[k].name].text, groupOf(k));
  return named;
}

std::string Translator::run() {
  while (cur().kind != Token::End) topLevel();
  chooseMethod();
  if (!init_) axiomNode();
  return write();
}

const Module* Translator::userModule(const std::string& name) const {
  for (const Module& m : modules_)
    if (t_[m.name].text == name) return &m;
  return nullptr;
}

const TurtleCommand* Translator::turtle(size_t at, int arity, std::vector<std::string>* defaults) {
  const std::string& name = t_[at].text;
  if (arity == 0 && !(*defaults = defaultArguments(name)).empty()) arity = (int)defaults->size();
  bool known = false;
  for (const TurtleCommand& c : kTurtleCommands) {
    known = known || c.name == name;
    if (c.name == name && c.arity == arity) return &c;
  }
  if (known) throw XlError{t_[at], "GroIMP's " + name + " with " + std::to_string(arity) + " arguments is not supported yet"};
  return nullptr;
}

const TurtleCommand* Translator::turtleOrError(const Node& n, std::vector<std::string>* defaults) {
  const TurtleCommand* c = turtle(n.name, (int)n.args.size(), defaults);
  if (!c)
    throw XlError{t_[n.name], "no module '" + t_[n.name].text + "': declare it (`module " + t_[n.name].text +
                                  ";`); of GroIMP's turtle commands lcjit has " + turtleNames()};
  used_.insert(c);
  return c;
}

void Translator::checkCount(const Node& n, const Module& m) {
  const int arity = (int)n.args.size(), params = (int)m.params.size();
  if (n.parens && arity != params)
    throw XlError{t_[n.name], "'" + t_[n.name].text + "' has " + std::to_string(params) + " parameter" +
                                  (params == 1 ? "" : "s") + ", given " + std::to_string(arity)};
  // `A` without parentheses: on the left any A, on the right an A made with the constructor
  // without arguments every module has (its parameters' fallbacks).
}

std::string Translator::write() {
  // The body (axiom, productions, interpretation rules) first: it says which of GroIMP's turtle
  // commands the model uses, declared in the head after the user's modules.
  LcWriter head(t_);
  for (const Module& m : modules_) {
    std::vector<std::string> types;
    for (size_t k = 0; k < m.fieldCount(); ++k) types.push_back(m.fieldType(k));
    head.at(m.keyword, "module " + m.lcName + (types.empty() ? "" : "(" + joined(types) + ")") + ";");
  }
  // XL's library, then the model's fields and methods (each method declared first: Java's may
  // call one written after it).
  // The shaders' names a model does not declare itself (its own `const int YELLOW = 14;` is its).
  std::string shaders;
  for (size_t k = 0; k < std::size(kShaders); ++k) {
    bool declared = false;
    for (const Declaration& d : declarations_) declared = declared || t_[d.name].text == kShaders[k];
    if (!declared) shaders += (shaders.empty() ? "" : ", ") + std::string(kShaders[k]) + " = " + std::to_string(k);
  }
  w_.add("enum : int { " + shaders + " };");
  for (const Declaration& d : declarations_)
    if (d.method) w_.add(signature(d) + ";");
  // The model's fields, then the structs of the modules' fields (their methods may read the
  // model's fields), then the model's methods (their graph queries copy nodes into the structs).
  for (const Declaration& d : declarations_) {
    if (d.method) continue;
    w_.at(d.type, (d.constant ? "const " : "") + javaTypeAt(d.type));
    java(d.rest);
    w_.add(";");
  }
  // The fields of each module with methods, as a struct with the methods on them: its labels'
  // copies are of it, so that `l.area()` is C++ as written.
  for (const Module& m : modules_) {
    const std::vector<const Declaration*> methods = methodsOf(m);
    if (methods.empty()) continue;
    std::string fields;
    for (size_t k = 0; k < m.fieldCount(); ++k) fields += " " + m.fieldType(k) + " " + m.fieldName(k) + ";";
    w_.at(m.name, "struct " + fieldsStruct(m) + " {" + fields);
    for (const Declaration* d : methods) {
      w_.at(d->type, signature(*d));
      java(d->rest);
    }
    w_.add("};");
  }
  for (const Declaration& d : declarations_) {
    if (!d.method) continue;
    w_.at(d.type, signature(d));
    java(d.rest);
  }
  if (axiomIsNode_) {
    w_.at(axiomAt(), "derivation length: 0; axiom: XL_Axiom;");
  } else if (const Rule& axiom = init_->rules.front(); hasControl(axiom.right) || hasBlock(axiom.right)) {
    // An axiom with for, if or Java: its nodes are made by a rule, the decomposition of the
    // node XL_Init, which L+C applies to the axiom before anything else (manual §4.3.1).
    w_.at(axiom.left.front().name, "derivation length: 0; axiom: XL_Init;");
  } else {
    w_.at(axiom.left.front().name, "derivation length: 0;");
    w_.add("axiom:");
    for (const Node& n : axiom.right)
      if (n.kind == Node::Block) notYet(t_[n.name], "a block of Java statements in the axiom");
    rightModules(axiom.right, true);
    w_.at(axiom.end, ";");
  }
  // Each rule method's rules are a production group of their own when the model has several:
  // group k + 1 for the k-th (ruleMethods(): GroIMP's buttons, the window's Rules menu), the run
  // starting in the step method's (--run). Blocks among the rules: init()'s run once, before the
  // axiom is made (L+C's Start), a rule method's before each step that applies it (StartEach).
  const bool grouped = methods_.size() > 1;
  size_t stepGroup = 0;
  for (size_t k = 0; k < methods_.size(); ++k)
    if (step_ && methods_[k].name == step_->name) stepGroup = groupOf(k);
  auto blocks = [&](const Method& m) {
    for (const Range& b : m.blocks) block(Node{Node::Block, {}, b.first, false, {}, {}, b});
  };
  if (grouped || (init_ && !init_->blocks.empty())) {
    if (init_ && !init_->blocks.empty()) w_.at(init_->blocks.front().first, "Start: {");
    else w_.add("Start: {");
    if (grouped) w_.add("UseGroup(" + std::to_string(stepGroup) + ");");
    if (init_) blocks(*init_);
    w_.add("}");
  }
  // Each method's blocks run in the steps that apply it: those of its group.
  bool any = false;
  for (const Method& m : methods_) any = any || !m.blocks.empty();
  if (any) {
    w_.add("StartEach: { switch (lcjit_current_group()) {");
    for (size_t k = 0; k < methods_.size(); ++k) {
      if (methods_[k].blocks.empty()) continue;
      w_.at(methods_[k].blocks.front().first, "case " + std::to_string(groupOf(k)) + ": {");
      blocks(methods_[k]);
      w_.add("} break;");
    }
    w_.add("} }");
  }
  bool noRule = false;
  for (size_t k = 0; k < methods_.size(); ++k) {
    if (grouped) {
      w_.at(methods_[k].name, "group " + std::to_string(groupOf(k)) + ":");
      // A method of blocks alone is a group too (UseGroup takes only groups with productions):
      // one production of a module no string holds.
      if (methods_[k].rules.empty()) {
        w_.add("XL_NoRule : { produce ; }");
        if (!noRule) head.add("module XL_NoRule;");
        noRule = true;
      }
    }
    for (const Rule& r : methods_[k].rules) {
      production(r);
      // Right after it, as XL tries its rules in order: the same rule for the subclasses.
      for (const Module* m : subclassesMatched(r)) production(r, m);
    }
  }
  if (grouped) w_.add("endgroup");
  if (init_ && (hasControl(init_->rules.front().right) || hasBlock(init_->rules.front().right))) {
    const Rule& axiom = init_->rules.front();
    w_.add("decomposition:");
    w_.at(axiom.arrow, "XL_Init : {");
    stepwise(axiom.right);
    w_.at(axiom.end, "produce ; }");
    head.at(axiomAt(), "module XL_Init;");
  }
  std::vector<std::pair<size_t, std::string>> interpretation;  // (at, rule)
  for (const Module& m : modules_) {
    if (instantiationOf(m)) continue;  // below
    if (std::string body = ownDrawing(m); !body.empty()) interpretation.push_back({m.name, pattern(m) + " : { " + body + " }"});
  }
  // Instantiation rules: what the nodes of a module are drawn as, in a branch (what they do to
  // the turtle does not reach the nodes after it), then the module's own drawing.
  bool interpreting = false;
  for (const Module& m : modules_) {
    const Rule* instantiation = instantiationOf(m);
    if (!instantiation) continue;
    // What it makes is drawn by the rules of GroIMP's commands (RU is Right …) and the
    // instantiation rules of the modules it makes: a few levels deep.
    if (!interpreting) w_.add("interpretation: maximum depth: 8;");
    interpreting = true;
    labels_.clear();
    instantiating_ = true;
    w_.at(instantiation->arrow, pattern(m) + " : { nproduce SB;");
    stepwise(instantiation->right);
    const std::string own = ownDrawing(m);
    w_.at(instantiation->end, "nproduce EB; " + (own.empty() ? "produce ;" : own) + " }");
    instantiating_ = false;
  }
  std::string turtleDecls;
  for (const TurtleCommand& c : kTurtleCommands) {
    if (!used_.count(&c) || c.own) continue;
    bool twice = false;  // one declaration per module
    for (const TurtleCommand& d : kTurtleCommands)
      twice = twice || (&d < &c && d.module == c.module && used_.count(&d));
    if (twice) continue;
    turtleDecls += "module " + std::string(c.module) + (c.declared.empty() ? "" : "(" + std::string(c.declared) + ")") + "; ";
    if (c.drawn.empty() && c.body.empty() && c.solid.empty()) continue;
    std::vector<std::string> args;
    std::string rule = std::string(c.module);
    if (c.arity > 0) {
      rule += "(";
      for (int i = 0; i < c.arity; ++i) {
        args.push_back("__xl_" + std::to_string(i));
        rule += (i ? ", " : "") + args.back();
      }
      rule += ")";
    }
    std::string body = c.body.empty() ? "produce " + drawn(c.drawn, args) + ";" : drawn(c.body, args);
    if (!c.solid.empty()) body = drawn(c.solid, args) + "produce f(" + drawn(c.advance, args) + ");";
    interpretation.push_back({axiomAt(), rule + " : { " + body + " }"});
  }
  if (!interpretation.empty()) {
    if (!interpreting) w_.add("interpretation:");
    for (const auto& [at, rule] : interpretation) w_.at(at, rule);
  }
  if (!turtleDecls.empty()) head.at(axiomAt(), turtleDecls);
  // XL's library (lcjit/xl.h): random, println, Java's strings …
  return "#include <lpfgall.h>\n#include <lcjit/xl.h>\n" + head.take() + w_.take();
}

std::vector<const Declaration*> Translator::methodsOf(const Module& m) const {
  std::vector<const Declaration*> methods;
  for (const Module* at = &m; at; at = at->base ? userModule(t_[*at->base].text) : nullptr)
    for (const Declaration& d : at->methods) {
      bool overridden = false;
      for (const Declaration* own : methods) overridden = overridden || t_[own->name].text == t_[d.name].text;
      if (!overridden) methods.push_back(&d);
    }
  return methods;
}

std::string Translator::fieldsStruct(const Module& m) { return "__xl_fields_" + m.lcName; }

const Rule* Translator::instantiationOf(const Module& m) const {
  for (const Module* at = &m; at;) {
    auto it = instantiations_.find(t_[at->name].text);
    if (it != instantiations_.end()) return &it->second;
    at = at->base ? userModule(t_[*at->base].text) : nullptr;
  }
  return nullptr;
}

std::string Translator::pattern(const Module& m) const {
  std::vector<std::string> names;
  for (size_t k = 0; k < m.fieldCount(); ++k) names.push_back(m.fieldName(k));
  return m.lcName + (names.empty() ? "" : "(" + joined(names) + ")");
}

std::string Translator::ownDrawing(const Module& m) {
  if (m.command.empty()) return "";
  const std::string& base = m.command;
  if (base == "F") {
    // GroIMP's F: its own diameter and colour when it has them (≥ 0), else the turtle state's.
    return drawn(kOwnCylinder, {m.baseField("length"), m.baseField("diameter"), m.baseField("color")});
  }
  std::vector<std::string> args;
  for (const Field* f : fieldsOf(base))
    if (f->name != "shader") args.push_back(m.baseField(std::string(f->name)));
  const TurtleCommand* c = turtleNamed(base, (int)args.size());
  if (!c) throw XlError{t_[*m.base], "no turtle command '" + base + "' to extend (lcjit has " + turtleNames() + ")"};
  if (!c->solid.empty()) {
    // Its shader (−1: the turtle's colour) for itself alone, in a branch; then to its top.
    const std::string solid = drawn(c->solid, args), top = "f(" + drawn(c->advance, args) + ")";
    const std::string shader = m.baseField("shader");
    if (shader.empty()) return solid + "produce " + top + ";";
    return "if (" + shader + " < 0) { " + solid + "produce " + top + "; } nproduce SB SetColor(" + shader + " + 2); " +
           solid + "produce EB " + top + ";";
  }
  if (c->drawn.empty()) return c->body.empty() ? "" : drawn(c->body, args);
  std::string body = "produce " + drawn(c->drawn, args) + ";";
  // Its shader (−1: the turtle's colour) for itself alone; what follows starts where it ends.
  if (const std::string shader = m.baseField("shader"); !shader.empty())
    body = "if (" + shader + " < 0) " + body + " else produce SB SetColor(" + shader + " + 2) " + drawn(c->drawn, args) + " EB" +
           (c->advance.empty() ? "" : " f(" + drawn(c->advance, args) + ")") + ";";
  return body;
}

std::string Translator::javaTypeAt(size_t at) const {
  std::string type = javaType(t_[at].text);
  for (size_t i = at + 1; i + 1 < t_.size() && t_[i].is("[") && t_[i + 1].is("]"); i += 2)
    type = "__xl_Array<" + type + ">";
  return type;
}

std::string Translator::signature(const Declaration& d) const {
  std::string s = (t_[d.type].is("void") ? std::string("void") : javaTypeAt(d.type)) + " " + t_[d.name].text + "(";
  for (size_t k = 0; k < d.params.size(); ++k)
    s += (k ? ", " : "") + javaTypeAt(d.params[k].first) + " " + t_[d.params[k].second].text;
  return s + ")";
}

namespace {

std::string errorLine(const XlError& e) {
  return e.at.file + ":" + std::to_string(e.at.line) + ":" + std::to_string(e.at.col) + ": error: " + e.message;
}

}  // namespace

std::string_view shownName(std::string_view lcName) {
  if (lcName == "SB") return "[";
  if (lcName == "EB") return "]";
  if (lcName == "F_d" || lcName == "F_dc") return "F";
  if (lcName == "Null_t") return "Null";
  if (lcName.substr(0, 3) == "XL_") return lcName.substr(3);
  return lcName;
}

namespace {
// Where the REPL's own C++ begins in its unit (app/session/Session.cpp: a file named <repl> that
// includes the model, then adds declarations and statements in C++): the line marker returning
// into it (GNU flag 2) from the first file it includes (flag 1) other than the preprocessor's
// own (<built-in>, <command line>). npos: a model alone.
size_t replText(const std::string& preprocessed) {
  bool inModel = false;
  for (size_t at = 0; at < preprocessed.size();) {
    size_t end = preprocessed.find('\n', at);
    if (end == std::string::npos) end = preprocessed.size();
    std::string_view line(preprocessed.data() + at, end - at);
    if (line.size() > 2 && line[0] == '#' && line[1] == ' ') {
      const bool enters = line.size() > 2 && line.substr(line.size() - 2) == " 1" && line.find("\"<") == std::string_view::npos;
      if (enters) inModel = true;
      if (inModel && line.find("<repl>\" 2") != std::string_view::npos) return at;
    }
    at = end + 1;
  }
  return std::string::npos;
}
}  // namespace

llvm::Expected<std::string> toLplusC(const std::string& preprocessed, const std::string& mainFile, const std::string& run,
                                     std::vector<std::pair<std::string, int>>* ruleMethods) {
  try {
    // In the REPL, the model is XL and what the REPL adds after it C++, which the L+C takes as
    // it is.
    const size_t repl = replText(preprocessed);
    if (repl != std::string::npos) {
      Translator translator(tokenize(preprocessed.substr(0, repl), mainFile), run);
      std::string lc = translator.run() + preprocessed.substr(repl);
      if (ruleMethods) *ruleMethods = translator.ruleMethods();
      return lc;
    }
    Translator translator(tokenize(preprocessed, mainFile), run);
    std::string lc = translator.run();
    if (ruleMethods) *ruleMethods = translator.ruleMethods();
    return lc;
  } catch (const XlError& e) {
    return llvm::createStringError(llvm::inconvertibleErrorCode(), errorLine(e));
  }
}

llvm::Expected<Rewritten> rewrite(const std::string& preprocessed, const std::string& mainFile, const std::string& run) {
  std::vector<std::pair<std::string, int>> methods;
  auto lc = toLplusC(preprocessed, mainFile, run, &methods);
  if (!lc) return lc.takeError();
  auto rewritten = frontend::rewrite(*lc, mainFile);
  if (rewritten) rewritten->namedGroups = std::move(methods);
  return rewritten;
}

}  // namespace lcjit::frontend::xl
