// Fuzz target: the view file (.v) as the preprocessor hands it over, parseViewFile.
#include "runtime/files/ViewFile.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<lcjit::runtime::ViewFileWarning> warnings;
  lcjit::runtime::ViewSettings v = lcjit::runtime::parseViewFile(lcjit::fuzz::text(data, size), "fuzz.v", warnings);
  (void)v;
  return 0;
}
