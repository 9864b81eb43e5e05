// Fuzz target: the function file .tset (a timeline), FunctionStore::loadTimeline (it reads a path: the input
// is a file), then every entry evaluated.
#include "runtime/Functions.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = lcjit::fuzz::inputFile(data, size, ".tset");
  lcjit::runtime::FunctionStore store;
  lcjit::fuzz::checkError(store.loadTimeline(path), path);
  for (int id = 1; id <= store.size(); ++id)
    for (float x : {-1.0f, 0.0f, 0.37f, 1.0f, 2.0f}) {
      (void)store.func(id, x);
      (void)store.pfunc(id, x, -3, 3);
      (void)store.tfunc(id, x);
      (void)store.funcTangent(id, x);
      (void)store.val(id);
    }
  return 0;
}
