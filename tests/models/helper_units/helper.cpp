// A translation unit of the model's own, compiled beside it as lpfg.mak would: it does not see
// lpfgall.h, so its own val() does not clash with lpfg's.
#include "geometry.h"
#include <cmath>
int calls = 0;
static float val(float x) { return x * 2; }
float scaled(float x) {
  ++calls;
  return val(std::sqrt(x));
}
