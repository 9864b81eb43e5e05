// lpfg's random numbers: a 48-bit linear congruential generator (erand48's recurrence) with
// lpfg's seeding, so ran()/sran() sequences and Gillespie choices match lpfg's.
#pragma once
#include <cstdint>
#include <optional>

namespace lcjit::runtime {

class Rand48 {
 public:
  // The state starts at 0x330E; sran(s) sets it to s mod 2^32 (not srand48's (s<<16)|0x330E).
  void seed(long s) { x_ = start((uint32_t)s); }
  // --seed N, one member of an ensemble (docs/sweeps.md): every state lpfg would take from a
  // seed (the first, 0x330E, and each sran(s)'s) is that seed mixed with N instead, so a model
  // seeded in Start, or not at all, gives another reproducible stream for every N. None: lpfg's.
  void setMember(std::optional<uint64_t> n) {
    member_ = n;
    x_ = start(0x330E);
  }
  // Advances first, then returns X/2^48 in [0,1).
  double next() {
    x_ = (0x5DEECE66DULL * x_ + 0xBULL) & ((1ULL << 48) - 1);
    return (double)x_ / (double)(1ULL << 48);
  }

 private:
  // SplitMix64's finaliser: every bit of the seed and of N reaches every bit of the state.
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  uint64_t start(uint64_t s) const {
    return member_ ? mix(s ^ mix(*member_ + 0x9E3779B97F4A7C15ULL)) & ((1ULL << 48) - 1) : s;
  }
  std::optional<uint64_t> member_;
  uint64_t x_ = 0x330E;
};

}  // namespace lcjit::runtime
