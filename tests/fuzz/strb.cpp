// Fuzz target: binary strings (.strb), Engine::readBinary (it reads a path: the input is a file)
// on a compiled model with modules of every parameter kind, then a derivation step and the turtle
// interpreting the string (app/session/Session, as LoadString and a batch run do it).
// LCJIT_FUZZ_STRB_SEED=FILE: the model's own string after two steps is written there (a seed).
// LCJIT_FUZZ_VERBOSE=1: what became of each input.
#include <fstream>

#include "app/session/Session.h"
#include "runtime/Engine.h"
#include "runtime/turtle/Geometry.h"
#include "tests/fuzz/FuzzSession.h"
#include "tests/fuzz/FuzzSupport.h"

using namespace lcjit;

namespace {

app::Session* session;
const bool verbose = std::getenv("LCJIT_FUZZ_VERBOSE") != nullptr;

// The model's own code cannot crash whatever its parameters: a crash while deriving or
// interpreting a string readBinary accepted is lcjit's (the guard would hide it otherwise).
void report(const char* what, llvm::Error e) {
  if (!e) return;
  std::string msg = llvm::toString(std::move(e));
  if (verbose) std::fprintf(stderr, "%s: %s\n", what, msg.c_str());
  if (msg.find("crashed") != std::string::npos) {
    std::fprintf(stderr, "lcjit fuzz: %s of a string readBinary accepted crashed:\n%s\n", what, msg.c_str());
    std::abort();
  }
}

const char* const kModel = R"(#include <lpfgall.h>
module A(int), B(float, double), C(char, bool), D(V3f), E, P(long, int);
derivation length: 2;
axiom: SetColor(2) SetWidth(0.1) A(1) B(0.5, 2) SB Left(30) F(1) D(V3f(1, 2, 3)) EB C('x', true) E
       StartGC F(1) Circle(0.2) PointGC Sphere(0.3) EndGC P(7, 8) GetPos(0, 0, 0) f(1) Cut F(2);
A(n) : { produce A(n + 1) B(n, n * 2) F(n) RollR(45); }
B(x, y) < C(c, b) : { produce C(c + 1, !b); }
interpretation:
B(x, y) : { produce F(x) Right(y); }
E : { produce Sphere(0.1) SetColor(3); }
)";

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  runtime::EngineLimits limits;
  limits.maxModules = 200000;
  limits.timeLimit = 2;
  session = fuzz::guardedSession(limits);
  std::string model = fuzz::scratchDir() + "/strb_model.l";
  std::ofstream(model) << kModel;
  app::ModelFiles files;
  files.lsystem = model;
  app::PhaseTimes times;
  if (auto e = session->load(files, 0, times)) {
    std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
    std::abort();
  }
  if (const char* seed = std::getenv("LCJIT_FUZZ_STRB_SEED")) {
    runtime::Engine& engine = session->engine();
    if (auto e = engine.run()) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
    if (auto e = engine.writeBinary(seed)) std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  runtime::Engine& engine = session->engine();
  runtime::EngineHooks hooks;
  hooks.print = [](const char*) {};
  hooks.outputFrame = [](const char*) {};
  engine.begin(hooks);
  const std::string& path = fuzz::inputFile(data, size, ".strb");
  if (auto e = engine.readBinary(path)) {
    if (verbose) std::fprintf(stderr, "read: %s\n", llvm::toString(engine.readBinary(path)).c_str());
    return fuzz::checkError(std::move(e), path), 0;
  }
  std::string transcript;
  runtime::Geometry geometry;
  report("interpretation", engine.interpret(nullptr, &geometry, &transcript));
  engine.step();
  engine.finish();
  report("derivation", engine.takeFault());
  report("interpretation after a step", engine.interpret(nullptr, &geometry, &transcript));
  if (verbose) std::fprintf(stderr, "%zu modules, %zu bytes of turtle text\n", engine.moduleCount(), transcript.size());
  return 0;
}
