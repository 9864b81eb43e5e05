// Fuzz target: PLY meshes (ASCII and binary), parsePly.
#include "runtime/files/MeshFiles.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto m = lcjit::runtime::parsePly(lcjit::fuzz::text(data, size), "fuzz.ply");
  lcjit::fuzz::check(m, "fuzz.ply");
  return 0;
}
