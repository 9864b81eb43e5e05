// Fuzz target: the animation file (.a), parseAnimationFile and the frame schedule it gives.
#include "runtime/files/AnimationFile.h"
#include "tests/fuzz/FuzzSupport.h"

using namespace lcjit::runtime;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<ViewFileWarning> warnings;
  AnimationSettings a = parseAnimationFile(lcjit::fuzz::text(data, size), "fuzz.a", warnings);
  AnimationSchedule schedule(a, 20);
  for (int i = 0; i < 50 && schedule.next(AnimationSchedule::Mode::Forever); ++i) {
  }
  return 0;
}
