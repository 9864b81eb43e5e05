// Fuzz target: the function set .fset, read by FunctionStore::loadFunctionSet (FunctionFiles.h).
#include "tests/fuzz/FunctionFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return lcjit::fuzz::functionFile(data, size, ".fset", &lcjit::runtime::FunctionStore::loadFunctionSet);
}
