// Fuzz target: the function file .func (one function), read by FunctionStore::loadFunction (FunctionFiles.h).
#include "tests/fuzz/FunctionFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return lcjit::fuzz::functionFile(data, size, ".func", &lcjit::runtime::FunctionStore::loadFunction);
}
