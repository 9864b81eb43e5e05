// Fuzz target: the front end up to Clang's parse — the in-process preprocessor, then the L+C to
// C++ rewriter: model text in, C++ or an error out.
#include "frontend/lc/Preprocess.h"
#include "frontend/lc/Rewriter.h"
#include "tests/fuzz/FuzzSupport.h"

namespace {

// The model's folder (searched first for quoted includes): empty, this process's own.
const std::string& modelPath() {
  static const std::string path = [] {
    return lcjit::fuzz::scratchDir() + "/model.l";
  }();
  return path;
}

void checkFailed(llvm::Error e) {
  std::string msg = llvm::toString(std::move(e));
  if (msg.find("error") == std::string::npos) {
    std::fprintf(stderr, "lcjit fuzz: an error without 'error' in it:\n%s\n", msg.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lcjit::frontend::PreprocessOptions pp;
  pp.runtimeIncludeDir = LCJIT_RUNTIME_INCLUDE_DIR;
  pp.cacheDir = LCJIT_FUZZ_CACHE_DIR;
  pp.mainText = std::string(lcjit::fuzz::text(data, size));
  auto text = lcjit::frontend::preprocess(modelPath(), pp);
  if (!text) return checkFailed(text.takeError()), 0;
  auto cpp = lcjit::frontend::rewrite(*text, modelPath());
  if (!cpp) checkFailed(cpp.takeError());
  return 0;
}
