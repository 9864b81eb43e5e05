// Fuzz target: the materials file (.mat), Palette::loadMaterials (it reads a path: the input is a
// file).
#include "runtime/files/Palette.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = lcjit::fuzz::inputFile(data, size, ".mat");
  lcjit::runtime::Palette palette;
  lcjit::fuzz::checkError(palette.loadMaterials(path), path);
  for (int i = 0; i < 256; i += 51) (void)palette.color(i);
  return 0;
}
