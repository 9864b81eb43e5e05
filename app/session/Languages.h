// The grammar languages lcjit runs, keyed by the extension of their model files. This table is the
// one place where the command line, the watcher, the window, the REPL, sweeps and the sandbox learn
// which language a file is written in and which engine runs its models (InputKinds.h takes the
// model files' rows from it; classifyInputs names the language of a run's model).
//
// A language is a front end (frontend/<language>/: its text → the C++ the JIT compiles and the
// tables that describe the model) and the engine its models run on (runtime/). Adding one is its
// own folder and one row of kLanguages in Languages.cpp, which names its front end; the engine's
// modes call the front end the row names. docs/architecture.md draws the seam.
#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::frontend {
struct Rewritten;
namespace cfdg {
struct DesignUnit;
}
}  // namespace lcjit::frontend
namespace lcjit::runtime {
class Palette;
struct LanguageWords;
}

namespace lcjit::app {

// The engines a language's models run on. Each hands runtime::Geometry (runtime/turtle/Geometry.h)
// to the one renderer and the exporters.
enum class EngineKind {
  // runtime::Engine: a string of modules rewritten in parallel, step by step, by productions with
  // context, then read by the turtle (L+C).
  LSystem,
  // runtime/cfdg/Expander: shapes replaced by rules chosen at random by weight, the largest
  // unfinished shape first, until they are too small to see (Context Free's CFDG).
  ShapeExpansion,
};

// The front ends, one kind per engine: what the engine's session hands the language's text to.
// The L-system engine's (app/session/Session): the model as the C preprocessor left it (GNU line
// markers, frontend/lc/Preprocess.h) → the C++ of its modules and productions and the tables the
// engine reads (frontend/lc/Rewriter.h's contract); errors at FILE:LINE:COL.
// `run`: the rules a step applies, where a model has several sets (XL's rule methods, --run);
// empty: its first.
using RewriteModel = llvm::Expected<frontend::Rewritten> (*)(const std::string& preprocessed,
                                                             const std::string& mainFile, const std::string& run);
// The shape-expansion engine's (app/cfdg/DesignRun): a design's text and its -D NAME=VALUE
// definitions → the C++ unit the Expander runs (lcjit/cfdg.h's contract), with the files it
// imported (frontend/cfdg/ReadDesign.h).
using ReadDesign = llvm::Expected<frontend::cfdg::DesignUnit> (*)(std::string_view text, const std::string& file,
                                                                  const std::vector<std::string>& defines);

// The colours of a language's models without a colour file (runtime/files/Palette.h).
using DefaultColours = runtime::Palette (*)();

struct Language {
  std::string_view name;   // as its users call it: "L+C"
  std::string_view model;  // what one of its model files is called in messages: "L-system"
  std::span<const std::string_view> extensions;  // of its model files, without the dot
  EngineKind engine;
  // Its front end: the one its engine calls (the other is null).
  RewriteModel rewrite = nullptr;
  ReadDesign readDesign = nullptr;
  // Its models' colours without a colour file; null: lpfg's (lcjit's in the window).
  DefaultColours colours = nullptr;
  // The name its models' string text (`-out x.str`) gives a module of the L+C its front end
  // wrote; null: the L+C name.
  std::string_view (*shownName)(std::string_view lcName) = nullptr;
  // What its faults' messages call the parts of the L+C its front end wrote (its rules, its
  // statements); null: L+C's words.
  const runtime::LanguageWords* words = nullptr;
};

// Every language, in the order messages list them.
std::span<const Language> languages();
// The language whose model files end in `path`'s extension; nullptr for none. Extensions are
// case-sensitive, as lpfg's command line is.
const Language* languageOf(std::string_view path);
// The language called `name` ("CFDG"); nullptr for none. `lcjit cfdg` reads any file as CFDG.
const Language* languageNamed(std::string_view name);
// ".l": the model files' extensions, in the form messages give them ("a .l or .cfdg file").
std::string modelExtensions(const Language& language);

// ".l": every language's model files' extensions.
std::string modelExtensions();
// What a run without a model file is told: "no L-system file (.l) given", each language's model
// file and extensions joined by "or".
std::string noModelGiven();

}  // namespace lcjit::app
