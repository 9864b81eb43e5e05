// Phase times, in the one unit every report gives them (--stats, -v, CompileStats, the REPL's
// `time`): milliseconds on the steady clock.
#pragma once

#include <chrono>
#include <cstdint>

namespace lcjit::support {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The same in whole nanoseconds, for counters that add up many short times (profiles).
inline uint64_t nsSince(Clock::time_point t0) {
  return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
}

}  // namespace lcjit::support
