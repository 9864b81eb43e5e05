// Fuzz target: texture images (PNG, JPEG, SGI .rgb; the format from the first bytes), decodeImage.
#include "runtime/files/Images.h"
#include "tests/fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto img = lcjit::runtime::decodeImage(data, size, "fuzz.img");
  if (lcjit::fuzz::check(img, "fuzz.img") && img->rgba.size() != size_t(img->width) * size_t(img->height) * 4) std::abort();
  return 0;
}
