// Phase times, in the one unit every report gives them (--stats, -v, CompileStats, the REPL's
// `time`): milliseconds on the steady clock.
#pragma once

#include <chrono>

namespace lcjit::support {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace lcjit::support
