// The animation file reader (manual §8.1, lpfg's animparam.cpp) and the frame schedule (§1.2.3).
#include <gtest/gtest.h>

#include "runtime/files/AnimationFile.h"

using namespace lcjit::runtime;

namespace {

AnimationSettings parse(std::string_view text, std::vector<ViewFileWarning>& w) {
  return parseAnimationFile(text, "anim.a", w);
}

bool hasWarning(const std::vector<ViewFileWarning>& w, int line, const std::string& part) {
  for (const auto& x : w)
    if (x.line == line && x.message.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(AnimationFile, Defaults) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse("", w);
  EXPECT_TRUE(w.empty());
  EXPECT_EQ(a.firstFrame, 0);
  EXPECT_FALSE(a.lastFrame.has_value());
  EXPECT_EQ(a.resolvedLastFrame(17), 17);
  EXPECT_EQ(a.step, 1);
  EXPECT_EQ(a.swapInterval, 0);
  EXPECT_TRUE(a.doubleBuffer);
  EXPECT_TRUE(a.clearBetweenFrames);
  EXPECT_FALSE(a.hcenterBetweenFrames);
  EXPECT_FALSE(a.scaleBetweenFrames);
  EXPECT_FALSE(a.newViewBetweenFrames);
  EXPECT_FALSE(a.displayOnRequest);
  EXPECT_EQ(a.frameNumbers, AnimationSettings::FrameNumbers::Consecutive);
  EXPECT_EQ(a.frameDumpPath, "");
}

TEST(AnimationFile, EveryCommand) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse(
      "first frame: 3\n"
      "last frame: 40\n"
      "step: 5\n"
      "swap interval: 2\n"
      "double buffer: off\n"
      "clear between frames: on\n"
      "hcenter between frames: on\n"
      "scale between frames: on\n"
      "new view between frames: on\n"
      "display on request: on\n"
      "frame numbers: stepno\n"
      "frame dump path: /tmp/frames\n",
      w);
  EXPECT_TRUE(w.empty()) << w[0].message;
  EXPECT_EQ(a.firstFrame, 3);
  EXPECT_EQ(a.lastFrame, 40);
  EXPECT_EQ(a.resolvedLastFrame(17), 40);
  EXPECT_EQ(a.step, 5);
  EXPECT_EQ(a.swapInterval, 2);
  EXPECT_EQ(a.swapIntervalMs(), 20);
  EXPECT_FALSE(a.doubleBuffer);
  EXPECT_TRUE(a.clearBetweenFrames);
  EXPECT_TRUE(a.hcenterBetweenFrames);
  EXPECT_TRUE(a.scaleBetweenFrames);
  EXPECT_TRUE(a.newViewBetweenFrames);
  EXPECT_TRUE(a.displayOnRequest);
  EXPECT_EQ(a.frameNumbers, AnimationSettings::FrameNumbers::StepNo);
  EXPECT_EQ(a.frameDumpPath, "/tmp/frames");
}

TEST(AnimationFile, BlanksCrlfAndLastOneWins) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse("  step:   2  \r\n\r\n\tstep:7\r\nframe numbers: consecutive\r\n", w);
  EXPECT_TRUE(w.empty());
  EXPECT_EQ(a.step, 7);
  EXPECT_EQ(a.frameNumbers, AnimationSettings::FrameNumbers::Consecutive);
}

TEST(AnimationFile, ClearOffTurnsDoubleBufferOff) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse("double buffer: on\nclear between frames: off\n", w);
  EXPECT_FALSE(a.clearBetweenFrames);
  EXPECT_FALSE(a.doubleBuffer);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].line, 2);
  EXPECT_NE(w[0].message.find("double buffer"), std::string::npos);
  w.clear();
  a = parse("clear between frames: off\ndouble buffer: off\n", w);
  EXPECT_TRUE(w.empty());
  EXPECT_FALSE(a.doubleBuffer);
}

TEST(AnimationFile, WarningsWithLinesAndColumns) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse(
      "first frame: 2\n"            // 1 ok
      "bogus: 1\n"                  // 2 unknown
      "step: 0\n"                   // 3 step < 1
      "last frame: x\n"             // 4 not a number
      "double buffer: maybe\n"      // 5 bad flag
      "  scale between frames: onn\n"  // 6 bad flag, indented
      "first frame: -1\n"           // 7 negative
      "last frame: -3\n"            // 8 negative
      "swap interval: 4 ticks\n"    // 9 trailing text (value still applies, as in lpfg)
      "frame numbers: odd\n"        // 10
      "frame dump path:\n"          // 11
      "swap interval: -2\n",        // 12
      w);
  EXPECT_EQ(a.firstFrame, 2);
  EXPECT_EQ(a.step, 1);
  EXPECT_FALSE(a.lastFrame.has_value());
  EXPECT_TRUE(a.doubleBuffer);
  EXPECT_FALSE(a.scaleBetweenFrames);
  EXPECT_EQ(a.swapInterval, 4);
  EXPECT_EQ(a.frameNumbers, AnimationSettings::FrameNumbers::Consecutive);
  EXPECT_TRUE(hasWarning(w, 2, "unrecognized command"));
  EXPECT_TRUE(hasWarning(w, 3, "step"));
  EXPECT_TRUE(hasWarning(w, 4, "last frame"));
  EXPECT_TRUE(hasWarning(w, 5, "double buffer"));
  EXPECT_TRUE(hasWarning(w, 6, "scale between frames"));
  EXPECT_TRUE(hasWarning(w, 7, "first frame"));
  EXPECT_TRUE(hasWarning(w, 8, "last frame"));
  EXPECT_TRUE(hasWarning(w, 9, "ignored"));
  EXPECT_TRUE(hasWarning(w, 10, "frame numbers"));
  EXPECT_TRUE(hasWarning(w, 11, "frame dump path"));
  EXPECT_TRUE(hasWarning(w, 12, "swap interval"));
  EXPECT_EQ(w.size(), 11u);
  for (const auto& x : w) EXPECT_EQ(x.file, "anim.a");
  // Columns: the unknown command at its first character, the bad value where it starts.
  EXPECT_EQ(w[0].column, 1);
  EXPECT_EQ(w[3].line, 5);
  EXPECT_EQ(w[3].column, 16);
  EXPECT_EQ(w[4].line, 6);
  EXPECT_EQ(w[4].column, 25);  // 2 blanks + "scale between frames: " (22) + 1
}

TEST(AnimationFile, LineMarkersMapToTheSource) {
  std::vector<ViewFileWarning> w;
  parse("# 1 \"anim.a\"\n# 1 \"<built-in>\"\n# 1 \"anim.a\"\n\n\nnope\n# 10 \"inc.h\" 1\nbad: 1\n#pragma x\nworse\n", w);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].file, "anim.a");
  EXPECT_EQ(w[0].line, 3);
  EXPECT_EQ(w[1].file, "inc.h");
  EXPECT_EQ(w[1].line, 10);
  EXPECT_EQ(w[2].line, 12);  // #pragma is a line of its own, not a marker
}

TEST(AnimationFile, GarbageNeverCrashes) {
  std::string junk;
  for (int i = 0; i < 4096; ++i) junk += char((i * 7919 + 13) % 256);
  junk += "\nfirst frame: 99999999999999999999\nstep: 2147483648\n# 99999999999999999999999 \"x\nlast frame:";
  junk += std::string("step: 3\0 junk", 14);
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parse(junk, w);
  EXPECT_FALSE(w.empty());
  EXPECT_GE(a.step, 1);
  EXPECT_GE(a.firstFrame, 0);
}

// ---- schedule ---------------------------------------------------------------------------------

namespace {
AnimationSettings frames(int first, std::optional<int> last, int step) {
  AnimationSettings a;
  a.firstFrame = first;
  a.lastFrame = last;
  a.step = step;
  return a;
}
}  // namespace

TEST(AnimationSchedule, DefaultsEveryStepFromAxiom) {
  AnimationSchedule s(AnimationSettings{}, 4);
  EXPECT_EQ(s.firstFrame(), 0);
  EXPECT_EQ(s.lastFrame(), 4);
  EXPECT_EQ(s.frames(), (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(AnimationSchedule, StepGridEndsOnLastFrame) {
  // first 2, step 3, last 10: 2 5 8 then the last frame 10 (off the grid, always shown).
  AnimationSchedule s(frames(2, 10, 3), 50);
  EXPECT_EQ(s.frames(), (std::vector<int>{2, 5, 8, 10}));
  // On the grid: 1 4 7.
  EXPECT_EQ(AnimationSchedule(frames(1, 7, 3), 0).frames(), (std::vector<int>{1, 4, 7}));
  // Last frame unset: the derivation length.
  EXPECT_EQ(AnimationSchedule(frames(0, std::nullopt, 2), 5).frames(), (std::vector<int>{0, 2, 4, 5}));
}

// The window's next frame goes on from the step it shows, which a run may leave off the grid (a
// DisplayFrame(), a fault): first 1, step 3, last 9 is 1 4 7 9; after step 5 comes 7.
TEST(AnimationSchedule, GoesOnFromTheStepShown) {
  AnimationSchedule s(frames(1, 9, 3), 20);
  s.setCurrent(5);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Run), 7);
  s.setCurrent(9);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Run), std::nullopt);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Forever), 1);
  s.setCurrent(0);  // before the first frame: the first frame
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Step), 1);
}

TEST(AnimationSchedule, StepRunStopAtEndForeverWraps) {
  AnimationSchedule s(frames(1, 5, 2), 99);
  EXPECT_EQ(s.current(), 1);
  EXPECT_EQ(s.next(), 3);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Run), 5);
  EXPECT_TRUE(s.atEnd());
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Step), std::nullopt);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Run), std::nullopt);
  EXPECT_EQ(s.current(), 5);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Forever), 1);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Forever), 3);
  EXPECT_EQ(s.rewind(), 1);
  EXPECT_EQ(s.current(), 1);
}

TEST(AnimationSchedule, FirstAtOrAfterLast) {
  AnimationSchedule s(frames(6, 4, 1), 10);
  EXPECT_TRUE(s.atEnd());
  EXPECT_EQ(s.frames(), (std::vector<int>{6}));
  EXPECT_EQ(s.next(), std::nullopt);
  EXPECT_EQ(s.next(AnimationSchedule::Mode::Forever), 6);
  AnimationSchedule z(frames(0, 0, 1), 10);
  EXPECT_EQ(z.frames(), (std::vector<int>{0}));
}

TEST(AnimationSchedule, HugeValuesDoNotLoop) {
  AnimationSchedule s(frames(0, 2000000000, 1000000000), 0);
  EXPECT_EQ(s.frames(), (std::vector<int>{0, 1000000000, 2000000000}));
}

TEST(AnimationSchedule, DisplayOnRequest) {
  AnimationSettings a = frames(2, 9, 3);
  a.displayOnRequest = true;
  AnimationSchedule s(a, 0);
  // Only the first and last frames are automatic; DisplayFrame() decides the rest.
  EXPECT_EQ(s.frames(), (std::vector<int>{2, 9}));
  EXPECT_FALSE(s.stopsAfter(5));
  EXPECT_TRUE(s.stopsAfter(4, true));
  EXPECT_TRUE(s.stopsAfter(9));
  // Without it, the grid rule.
  AnimationSchedule g(frames(2, 9, 3), 0);
  EXPECT_TRUE(g.stopsAfter(5));
  EXPECT_FALSE(g.stopsAfter(4, true));
  EXPECT_TRUE(g.stopsAfter(9));
}

TEST(AnimationSchedule, ParsedFileDrivesSchedule) {
  std::vector<ViewFileWarning> w;
  AnimationSettings a = parseAnimationFile("first frame: 1\nstep: 4\n", "x.a", w);
  EXPECT_EQ(AnimationSchedule(a, 10).frames(), (std::vector<int>{1, 5, 9, 10}));
}
