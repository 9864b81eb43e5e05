// The animation file (.a, manual §8.1) and the frame schedule it defines (manual §1.2.3: Step,
// Run, Forever, Rewind). Keywords, value syntax and defaults follow lpfg's AnimParam
// (animparam.cpp) and its use in lpfg.cpp/lengine.cpp. Pure data; nothing here draws.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/files/ViewFile.h"  // ViewFileWarning

namespace lcjit::runtime {

struct AnimationSettings {
  // `first frame: n` (n >= 0): Rewind derives up to step n and shows it. lpfg's default is 0 (the
  // axiom), not the 1 of the manual's note.
  int firstFrame = 0;
  // `last frame: n` (n >= 0); unset = the derivation length (see resolvedLastFrame).
  std::optional<int> lastFrame;
  // `step: n` (n >= 1): derivation steps between displayed frames.
  int step = 1;
  // `swap interval: t` (an integer; lpfg waits 10·t milliseconds between frames, i.e. t is in
  // hundredths of a second). Default 0: as fast as possible.
  int swapInterval = 0;
  int swapIntervalMs() const { return swapInterval * 10; }
  bool doubleBuffer = true;         // `double buffer: on|off`
  bool clearBetweenFrames = true;   // `clear between frames: on|off`
  bool hcenterBetweenFrames = false;  // `hcenter between frames: on|off`
  bool scaleBetweenFrames = false;  // `scale between frames: on|off`
  bool newViewBetweenFrames = false;  // `new view between frames: on|off`
  bool displayOnRequest = false;    // `display on request: on|off` (DisplayFrame(), §6.5)
  // `frame numbers: consecutive|stepno` (not in the manual): how recorded frames are numbered —
  // 0,1,2,… or by derivation step number.
  enum class FrameNumbers { Consecutive, StepNo } frameNumbers = FrameNumbers::Consecutive;
  // `frame dump path: text` (not in the manual): the directory recorded frames go to; "" = the
  // model's directory. lpfg appends every such line's text; here the last line wins.
  std::string frameDumpPath;

  // The last frame actually used: `last frame:` if given, else the derivation length.
  int resolvedLastFrame(int derivationLength) const { return lastFrame ? *lastFrame : derivationLength; }
};

// `preprocessedText` is the animation file after the C preprocessor (line markers `# N "file"` map
// lines back to the source; lpfg reads .a files through the same line-marker-aware reader as .v).
// Keywords are case-sensitive and must begin the line (leading blanks are tolerated here; lpfg
// rejects them). A bad line is left out with a warning (file:line:column); the rest applies.
// As lpfg does after reading: `clear between frames: off` forces `double buffer` off (warning).
AnimationSettings parseAnimationFile(std::string_view preprocessedText, const std::string& fileName,
                                     std::vector<ViewFileWarning>& warnings);
// The animation file `path` read (as it is, not preprocessed) and parsed; its warnings as
// "FILE:LINE:COLUMN: warning: …" lines. A file that cannot be read (missing, a FIFO, a device) is
// one warning, "FILE: warning: cannot open file: WHY", and the settings are lpfg's defaults.
AnimationSettings loadAnimationFile(const std::string& path, std::vector<std::string>& warnings);

// Which derivation steps are displayed while animating (lpfg's LPFG::_Step/Timer/_Rewind):
//  * rewind(): derive from the axiom to `first frame` and display it (the current frame);
//  * next step: derive one step at a time until (stepNo − first) is a multiple of `step`, or the
//    last frame is reached — so the last frame is always displayed, even off the step grid;
//  * Step and Run stop at the last frame (next() returns nullopt there); Forever rewinds to the
//    first frame and goes on.
// With `display on request: on` the intermediate frames are the model's DisplayFrame() calls,
// which this schedule cannot know: next() then jumps straight to the last frame (the only other
// frame displayed automatically); a driver calls stopsAfter() after each derivation step instead.
class AnimationSchedule {
 public:
  enum class Mode { Step, Run, Forever };

  AnimationSchedule(const AnimationSettings& settings, int derivationLength);

  int firstFrame() const { return first_; }
  int lastFrame() const { return last_; }
  int stepSize() const { return step_; }
  // The derivation step currently displayed (first frame after construction / rewind()).
  int current() const { return current_; }
  // Whether no further frame follows in Step/Run mode (current >= last frame).
  bool atEnd() const { return current_ >= last_; }

  // Back to the first frame; returns it.
  int rewind();
  // The window shows step `stepNo` (a run may stop off the step grid: at a DisplayFrame(), a
  // fault, a Stop()): next() goes on from there.
  void setCurrent(int stepNo) { current_ = stepNo; }
  // Advances to the next displayed frame and returns its step number; nullopt at the end in Step
  // and Run modes (the current frame stays). Forever wraps to the first frame instead (which,
  // when first >= last, is the only frame: it is shown again).
  std::optional<int> next(Mode mode = Mode::Step);
  // lpfg's stop rule for one derivation step that reached `stepNo`: show a frame now?
  // `displayRequested`: DisplayFrame() was called during that step (only with display on request).
  bool stopsAfter(int stepNo, bool displayRequested = false) const;
  // One pass of displayed step numbers, first frame to last frame (Step/Run).
  std::vector<int> frames() const;

 private:
  int first_, last_, step_;
  bool onRequest_;
  int current_;
};

}  // namespace lcjit::runtime
