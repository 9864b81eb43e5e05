// Fuzz target: the colormap (.map), Palette::loadColormap (it reads a path: the input is a file).
#include "runtime/files/Palette.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = lcjit::fuzz::inputFile(data, size, ".map");
  lcjit::runtime::Palette palette;
  std::vector<std::string> warnings;
  lcjit::fuzz::checkError(palette.loadColormap(path, &warnings), path);
  palette.selectPage(palette.pageCount() - 1);
  (void)palette.color(255);
  return 0;
}
