// Fuzz target: OBJ meshes, parseObj.
#include "runtime/files/MeshFiles.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto m = lcjit::runtime::parseObj(lcjit::fuzz::text(data, size), "fuzz.obj");
  lcjit::fuzz::check(m, "fuzz.obj");
  return 0;
}
