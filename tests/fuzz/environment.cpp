// Fuzz target: the environmental program's specification (.e), parseCommSpec.
#include "runtime/files/CommSpec.h"
#include "tests/fuzz/FuzzSupport.h"

using namespace lcjit::runtime;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<ViewFileWarning> warnings;
  auto spec = parseCommSpec(lcjit::fuzz::text(data, size), "fuzz.e", warnings);
  if (lcjit::fuzz::check(spec, "fuzz.e")) (void)environmentArguments(*spec);
  (void)communicationValues(lcjit::fuzz::text(data, size), 40);
  return 0;
}
