// A Context Free design's picture settings → C++ (Translator.h, section 8): CF::Tile, CF::Size,
// CF::Symmetry, the borders, the pixel format, CF::StartShape.
#include "frontend/cfdg/Translator.h"

#include <cstdio>

namespace lcjit::frontend::cfdg::translate {

// ---------------------------------------------------------------------------------------------
// 8. Picture settings
// ---------------------------------------------------------------------------------------------

// Records a setting this section compiles; false for the others.
bool Translator::pictureSetting(const Definition& def) {
  static const std::set<std::string> kNames = {"CF::Tile",  "CF::Size",  "CF::Symmetry",   "CF::BorderFixed",
                                               "CF::BorderDynamic", "CF::Color", "CF::Alpha", "CF::ColorDepth",
                                               "CF::StartShape"};
  if (!kNames.count(def.name)) return false;
  settings_.emplace(def.name, &def);
  return true;
}

const Expr* Translator::setting(const std::string& name) const {
  auto it = settings_.find(name);
  return it == settings_.end() ? nullptr : it->second->value.get();
}

std::string Translator::placeString(const Place& at) const { return placeString(at, d_.file); }

std::string Translator::placeString(const Place& at, const std::string& file) {
  std::string text = file + ":" + std::to_string(at.line) + ":" + std::to_string(at.column), out = "\"";
  for (char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

// Whether Context Free can evaluate `e` when it reads the design (CF::Tile and CF::Size must be
// such): no random numbers, no functions of the design, only constant names.
bool Translator::constantExpr(const Expr& e) const {
  switch (e.kind) {
    case Expr::Number: return true;
    case Expr::Name: {
      if (e.text.rfind("CF::", 0) == 0) return true;
      const Binding* b = lookup(e.text);
      return b ? b->constant && b->kind != Binding::Function : shapeIds_.count(e.text) > 0;
    }
    case Expr::Binary:
      if (e.text == ".." || e.text == "+/-") return false;
      break;
    case Expr::Call: {
      const Binding* b = lookup(e.text);
      if ((b && b->kind == Binding::Function) || e.text == "rand" || e.text == "randint" ||
          e.text.rfind("rand::", 0) == 0 || e.text.rfind("randint::", 0) == 0)
        return false;
      break;
    }
    case Expr::Modification:
      for (const auto& t : e.adjustment->terms)
        for (const auto& a : t.args)
          if (!constantExpr(*a)) return false;
      return true;
    default: break;
  }
  for (const auto& a : e.args)
    if (!constantExpr(*a)) return false;
  return true;
}

// Code setting `state` (a fresh identity) to adjustment `e`; a setting's adjustment.
void Translator::settingAdjustment(const Expr& e, const std::string& name, const std::string& state) {
  if (e.kind != Expr::Modification) fail(e.at, name + " must be an adjustment: [ … ]");
  line("__cf_identity(&" + state + ");");
  applyAdjustment(*e.adjustment, prepare(*e.adjustment), state);
}

// The settings' code, run by the start function after the global definitions: the values in
// __cf_Settings, handed to the engine (which then computes the background).
std::string Translator::settingsCode() {
  code_.clear();
  indent_ = 1;
  scopes_.clear();
  scopes_.emplace_back();
  line("{");
  ++indent_;
  line("__cf_Settings _set;");
  line("__builtin_memset(&_set, 0, sizeof _set);");
  for (const char* name : {"CF::Tile", "CF::Size"}) {
    const Expr* e = setting(name);
    if (!e) continue;
    if (!constantExpr(*e)) fail(e->at, "This expression must be constant");
    std::string field = std::string(name) == "CF::Tile" ? "tile" : "size";
    line("_set.has" + std::string(field == "tile" ? "Tile" : "Size") + " = 1;");
    line("_set." + field + "At = " + placeString(e->at) + ";");
    settingAdjustment(*e, name, "_set." + field);
  }
  // Numbers, in the order Context Free reads them: the borders, then the symmetry list.
  const std::pair<const char*, const char*> numbers[] = {{"CF::BorderFixed", "BorderFixed"},
                                                         {"CF::BorderDynamic", "BorderDynamic"},
                                                         {"CF::Color", "Colour"},
                                                         {"CF::Alpha", "Alpha"},
                                                         {"CF::ColorDepth", "ColourDepth"}};
  for (const auto& [name, field] : numbers) {
    const Expr* e = setting(name);
    if (!e) continue;
    Value v = scalar(*e);
    std::string lower = field;
    lower[0] = char(std::tolower(lower[0]));
    line("_set.has" + std::string(field) + " = 1;");
    line("_set." + lower + " = " + v.parts[0] + ";");
  }
  if (const Expr* e = setting("CF::Symmetry")) {
    std::vector<std::string> items = symmetryItems(*e, false);
    std::string list;
    for (auto& i : items) list += i + ", ";
    line("const __cf_SymmetryItem _sym[] = {" + list + "};");
    line("_set.symmetryCount = " + std::to_string(items.size()) + ";");
    line("_set.symmetry = _sym;");
  }
  line("__cf_configure(c, &_set);");
  --indent_;
  line("}");
  scopes_.clear();
  return code_;
}

// A symmetry list's elements as __cf_SymmetryItem initialisers, their values computed in order
// by code written before them. In a transform statement (`statement`), adjustments other than
// transforms are not elements (the statement applies them itself).
std::vector<std::string> Translator::symmetryItems(const Expr& list, bool statement) {
  std::vector<const Expr*> elements;
  if (list.kind == Expr::List)
    for (const auto& a : list.args) elements.push_back(a.get());
  else
    elements.push_back(&list);
  std::vector<std::string> items;
  for (const Expr* x : elements) {
    std::string values = temp();
    std::string kind, count;
    if (x->kind == Expr::Name && x->text.rfind("CF::", 0) == 0 && x->text != "CF::Infinity") {
      kind = "__cf_SymmetryFlag";
      count = "1";
      line("static const double " + values + "[] = {" + flag(*x) + "};");
    } else if (Value v = probe(*x); x->kind == Expr::Modification || v.adjustment) {
      // [ … ], or a constant adjustment variable: a transform when it only moves, turns, sizes.
      constexpr int kGeometry = 1 | 4;  // as geometryOnly
      if (x->kind != Expr::Modification && !v.constant) fail(x->at, "Wrong type");
      if (x->kind == Expr::Modification ? !geometryOnly(*x->adjustment) : (v.info.classes & ~kGeometry) != 0) {
        if (statement) continue;
        fail(x->at, "At least one term was invalid");
      }
      std::string state = temp();
      line("__cf_State " + state + ";");
      if (x->kind == Expr::Modification) {
        settingAdjustment(*x, "CF::Symmetry", state);
      } else {
        line("__cf_identity(&" + state + ");");
        foldedValue(v, state);
      }
      kind = "__cf_SymmetryTransform";
      count = "6";
      line("const double " + values + "[] = {" + state + ".sx, " + state + ".shy, " + state + ".shx, " + state + ".sy, " +
           state + ".tx, " + state + ".ty};");
    } else {
      std::vector<std::string> numbers = emitted(this->numbers(*x));
      kind = "__cf_SymmetryNumbers";
      count = std::to_string(numbers.size());
      std::string parts;
      for (auto& p : numbers) parts += p + ", ";
      line("const double " + values + "[] = {" + parts + "};");
    }
    items.push_back("{" + kind + ", " + count + ", " + values + ", " + placeString(x->at) + "}");
  }
  return items;
}

}  // namespace lcjit::frontend::cfdg::translate
