// Fuzz target: the terrain patches (`terrain:` files), parseTerrainPatches with three levels.
#include "runtime/files/TerrainPatches.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto t = lcjit::runtime::parseTerrainPatches(lcjit::fuzz::text(data, size), "fuzz.patch", 3);
  lcjit::fuzz::check(t, "fuzz.patch");
  return 0;
}
