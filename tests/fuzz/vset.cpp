// Fuzz target: the parameter file .vset, read by FunctionStore::loadParameters (FunctionFiles.h).
#include "tests/fuzz/FunctionFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return lcjit::fuzz::functionFile(data, size, ".vset", &lcjit::runtime::FunctionStore::loadParameters);
}
