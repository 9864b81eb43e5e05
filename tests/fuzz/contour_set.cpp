// Fuzz target: a contour set (.cset), ContourStore::loadSetText.
#include "runtime/files/Contours.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  lcjit::runtime::ContourStore store;
  lcjit::fuzz::checkError(store.loadSetText(lcjit::fuzz::text(data, size), "fuzz.cset"), "fuzz.cset");
  return 0;
}
