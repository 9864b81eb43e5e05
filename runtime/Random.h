// lpfg's random numbers: a 48-bit linear congruential generator (erand48's recurrence) with
// lpfg's seeding, so ran()/sran() sequences and Gillespie choices match lpfg's.
#pragma once
#include <cstdint>

namespace lcjit::runtime {

class Rand48 {
 public:
  // The state starts at 0x330E; sran(s) sets it to s mod 2^32 (not srand48's (s<<16)|0x330E).
  void seed(long s) { x_ = (uint64_t)(uint32_t)s; }
  // Advances first, then returns X/2^48 in [0,1).
  double next() {
    x_ = (0x5DEECE66DULL * x_ + 0xBULL) & ((1ULL << 48) - 1);
    return (double)x_ / (double)(1ULL << 48);
  }

 private:
  uint64_t x_ = 0x330E;
};

}  // namespace lcjit::runtime
