// The languages' table (Languages.h).
#include "app/session/Languages.h"

#include "app/session/InputKinds.h"
#include "frontend/cfdg/ReadDesign.h"
#include "frontend/lc/Rewriter.h"
#include "frontend/xl/Translate.h"
#include "runtime/Profile.h"
#include "runtime/files/Palette.h"

#include <vector>

namespace lcjit::app {

namespace {

constexpr std::string_view kLplusC[] = {"l"};
constexpr std::string_view kCfdg[] = {"cfdg"};
constexpr std::string_view kXl[] = {"rgg", "xl"};

// L+C has one set of productions (its groups are the model's to choose).
llvm::Expected<frontend::Rewritten> rewriteLplusC(const std::string& preprocessed, const std::string& mainFile,
                                                  const std::string&) {
  return frontend::rewrite(preprocessed, mainFile);
}

// XL's words for what its L+C holds: each rule a production, init()'s blocks Start, a rule
// method's blocks StartEach, an instantiation rule (or a module's drawing) an interpretation
// rule, an axiom with for or Java the decomposition of XL_Init (frontend/xl/Translate.cpp).
constexpr runtime::LanguageWords kXlWords{"rule", "init()'s rule", "instantiation rule", "init()'s statements",
                                          "the statements of a rule method", nullptr, nullptr};

constexpr Language kLanguages[] = {
    // lpfg's L+C: frontend/lc/ (the preprocessor and the rewriter) on the L-system engine.
    {"L+C", "L-system", kLplusC, EngineKind::LSystem, &rewriteLplusC},
    // Context Free's CFDG: frontend/cfdg/ on the shape-expansion engine.
    {"CFDG", "Context Free design", kCfdg, EngineKind::ShapeExpansion, nullptr, &frontend::cfdg::readDesign},
    // GroIMP's XL: frontend/xl/ (XL → L+C, then L+C's rewriter) on the L-system engine.
    // Its colours are GroIMP's: the EGA's 16, its turtle's yellow first.
    // Its strings in XL's names: [ ] for branches, the model's modules as it names them.
    {"XL", "XL model", kXl, EngineKind::LSystem, &frontend::xl::rewrite, nullptr, &runtime::Palette::ega,
     &frontend::xl::shownName, &kXlWords},
};

}  // namespace

std::span<const Language> languages() { return kLanguages; }

const Language* languageOf(std::string_view path) {
  std::string_view ext = extensionOf(path);
  if (ext.empty()) return nullptr;
  for (const Language& language : kLanguages)
    for (std::string_view e : language.extensions)
      if (e == ext) return &language;
  return nullptr;
}

const Language* languageNamed(std::string_view name) {
  for (const Language& language : kLanguages)
    if (language.name == name) return &language;
  return nullptr;
}

namespace {

std::string listed(const std::vector<std::string_view>& extensions) {
  std::string list;
  for (size_t i = 0; i < extensions.size(); ++i) {
    if (i) list += i + 1 == extensions.size() ? " or " : ", ";
    list += "." + std::string(extensions[i]);
  }
  return list;
}

}  // namespace

std::string modelExtensions(const Language& language) {
  return listed({language.extensions.begin(), language.extensions.end()});
}

std::string modelExtensions() {
  std::vector<std::string_view> all;
  for (const Language& language : kLanguages) all.insert(all.end(), language.extensions.begin(), language.extensions.end());
  return listed(all);
}

std::string noModelGiven() {
  std::string files;
  for (const Language& language : kLanguages)
    files += (files.empty() ? "" : " or ") + std::string(language.model) + " file (" + modelExtensions(language) + ")";
  return "no " + files + " given";
}

}  // namespace lcjit::app
