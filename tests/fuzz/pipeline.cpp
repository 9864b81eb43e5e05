// Fuzz target: the whole pipeline — model text (.l) preprocessed, rewritten, compiled by the JIT,
// a few steps derived and the string interpreted by the turtle, under the model guard with small
// limits (app/session/Session, as a batch run does it). Faults of model code are answers, not findings.
// LCJIT_FUZZ_VERBOSE=1: what became of each input (to check that inputs get as far as the turtle).
#include <fstream>

#include "app/session/Session.h"
#include "runtime/Engine.h"
#include "runtime/ModelGuard.h"
#include "runtime/turtle/Geometry.h"
#include "tests/fuzz/FuzzSession.h"
#include "tests/fuzz/FuzzSupport.h"

using namespace lcjit;

namespace {

app::Session* session;
std::string modelPath;
const bool verbose = std::getenv("LCJIT_FUZZ_VERBOSE") != nullptr;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  runtime::EngineLimits limits;
  limits.maxModules = 20000;
  limits.maxMemory = runtime::residentBytes() + (size_t(512) << 20);
  limits.timeLimit = 2;
  session = fuzz::guardedSession(limits);
  modelPath = fuzz::scratchDir() + "/model.l";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::ofstream(modelPath, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
  app::ModelFiles files;
  files.lsystem = modelPath;
  app::PhaseTimes times;
  if (auto e = session->load(files, 0, times)) {
    std::string msg = llvm::toString(std::move(e));
    if (verbose) std::fprintf(stderr, "load: %s\n", msg.c_str());
    if (msg.find("error") == std::string::npos) {
      std::fprintf(stderr, "lcjit fuzz: an error without 'error' in it:\n%s\n", msg.c_str());
      std::abort();
    }
    return 0;
  }
  runtime::Engine& engine = session->engine();
  runtime::EngineHooks hooks;
  hooks.print = [](const char*) {};
  hooks.outputFrame = [](const char*) {};
  engine.begin(hooks);
  for (int i = 0; i < 4 && engine.step(); ++i) {
  }
  engine.finish();
  llvm::Error fault = engine.takeFault();
  std::string transcript;
  runtime::Geometry geometry;
  llvm::Error interpreted = engine.interpret(nullptr, &geometry, &transcript);
  if (verbose)
    std::fprintf(stderr, "derived %d steps, %zu modules, %zu bytes of turtle text%s%s%s%s\n", engine.stepsDone(),
                 engine.moduleCount(), transcript.size(), fault ? "; fault: " : "",
                 fault ? llvm::toString(std::move(fault)).c_str() : "", interpreted ? "; interpretation: " : "",
                 interpreted ? llvm::toString(std::move(interpreted)).c_str() : "");
  llvm::consumeError(std::move(fault));
  llvm::consumeError(std::move(interpreted));
  return 0;
}
