// The defaults of options that several modes take: the command line's Options and each mode's
// own options start from these, so that a batch run, a design's run and the window agree.
#pragma once

namespace lcjit::app {

constexpr int kVideoFps = 25;                // --fps: a video's frames a second
constexpr double kBetterTierAfterMs = 250;   // --tier-after: a batch run's wait for the better tier

}  // namespace lcjit::app
