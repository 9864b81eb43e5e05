// A Context Free design run from the command line: read, translated to C++ (frontend/cfdg),
// compiled by the JIT, expanded (runtime/cfdg/Expander) and written as the pictures asked for.
// Both `lcjit design.cfdg …` (lcjit's options) and `lcjit cfdg …` (Context Free's own command
// line) end here.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/common/Defaults.h"
#include "frontend/cfdg/ReadDesign.h"
#include "runtime/cfdg/Expander.h"
#include "runtime/cfdg/VectorPage.h"
#include <llvm/Support/Error.h>

namespace CLI {
class App;
}

namespace lcjit::jit {
class Compiler;
class ModelCode;
}  // namespace lcjit::jit

namespace lcjit::app {

struct Options;

struct DesignRunOptions {
  std::string design;
  std::vector<std::string> outs;  // .svg (Context Free's -V picture) or .png; names with %v %V %f %%
  std::string output;             // cfdg's output file argument: a name as it is (no % codes)
  int width = 500, height = 500;
  std::string variation;          // a code as Context Free takes one ("A", "ABC", "17"); "" = random
  double minimumSize = 0.3;
  double border = 2;
  uint64_t maxShapes = 0;  // -m; 0: CF::MaxShapes if the design sets one above 1, else 500,000,000
  size_t maxMemory = 0;  // --max-memory; 0: half the physical memory
  int optLevel = 1;
  bool emitCpp = false;
  bool quiet = false;
  bool timing = false;  // -t (cfdg's) / -v: where the time went, on stderr
  bool crop = false;    // -c (cfdg's): only the fitted block (not for tiled or frieze designs)
  bool watch = false;   // --watch: draw again when the design is saved
  int frames = 0;       // -a (cfdg's): an animation of this many frames (PNG each), 0: one picture
  int frame = 0;        // -f (cfdg's): only this frame of the animation (1 …)
  int fps = kVideoFps;  // --fps: a video's frames a second (lcjit's -out movie.mp4)
  bool cfdgNames = false;  // output names as cfdg makes them (%f …), not lcjit's numbered files and videos
  bool zoom = false;    // -z (cfdg's): not done by lcjit
  std::vector<std::string> defines;  // -D NAME=VALUE
  std::optional<uint64_t> seed;      // --seed N: variation N (a sweep's runs)
  std::string runRecord;             // --run-record: the run's JSON record, whatever happens
  // --profile: each rule's runs and time (DesignProfile.h): "-" a table on stdout, else this JSON
  // file; "" not counted.
  std::string profile;
  // Told the files each load read (the design and what it imports): a sandboxed run's child
  // reports them to its parent, which watches them.
  std::function<void(const std::vector<std::string>&)> loaded;
  std::string cacheDir;
};

// `lcjit design.cfdg …`: what lcjit's own options ask of a design (-out, -w, -q, -O, --emit-cpp,
// --variation).
DesignRunOptions designRunOptions(const Options& options, const std::string& cacheDir);
// `lcjit cfdg …`: Context Free's command line, `cfdg [options] design.cfdg [output]`.
void declareCfdgOptions(CLI::App& command, DesignRunOptions& into);

// 0 when every picture was written; errors are printed (file:line:col: error: …) and give 1.
int runDesign(const DesignRunOptions& options);

// The pieces of a run that the window's host of designs (DesignWindow.h) shares.

// The JIT set up for designs: the host functions their code calls linked in.
llvm::Expected<std::unique_ptr<jit::Compiler>> designCompiler(const std::string& cacheDir);

// A design compiled and loaded: its code, its table and what its translation says of it.
struct LoadedDesign {
  std::unique_ptr<jit::ModelCode> code;
  const __cf_Design* table = nullptr;
  frontend::cfdg::Translation unit;
  std::vector<std::string> files;  // the design and what it imports
  std::vector<frontend::cfdg::DesignVariable> variables;  // its constant numbers (ReadDesign.h)
  double parseMs = 0, compileMs = 0;
  bool fromCache = false;
};
// Reads, translates and compiles `options.design` (with its -D definitions); errors at
// file:line:col.
llvm::Expected<LoadedDesign> loadDesign(jit::Compiler& compiler, const DesignRunOptions& options);

// The variation a code names (Context Free's letters or a number), or a random one for "";
// 0 when the code is neither.
uint64_t chooseVariation(const std::string& code);

// One expansion of a loaded design at a variation, with the options it ran with (the settings
// of the design and of the command line, merged as cfdg merges them).
struct DesignExpansion {
  runtime::cfdg::ExpandOptions options;
  runtime::cfdg::Expansion expansion;
};
DesignExpansion expandDesign(const LoadedDesign& design, const DesignRunOptions& options, uint64_t variation);

// The vector page a file name asks for (.pdf; .ps, .eps), written by runtime/cfdg/VectorPage.
std::optional<runtime::cfdg::PageFormat> pageFormatFor(const std::string& path);

}  // namespace lcjit::app
