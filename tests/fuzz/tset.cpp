// Fuzz target: the timeline file .tset, read by FunctionStore::loadTimeline (FunctionFiles.h).
#include "tests/fuzz/FunctionFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return lcjit::fuzz::functionFile(data, size, ".tset", &lcjit::runtime::FunctionStore::loadTimeline);
}
