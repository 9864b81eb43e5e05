// The command line's options (app/cli/Options.h): a sandboxed run's child, given childArguments,
// parses what its parent parsed, field by field, but for the options that stay with the parent —
// and the test's command line holds every option there is, so that a new one is placed (taken by
// the child, or the parent's alone) here as well.
#include "app/cli/Options.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

namespace lcjit::app {
// A failed comparison shows each side as a command line.
void PrintTo(const Options& o, std::ostream* out) {
  for (const std::string& a : commandLine(o)) *out << a << ' ';
}
}  // namespace lcjit::app

namespace {

using lcjit::app::Options;

// lcjit's command line (without the program's name), parsed as the driver parses it; `app`, when
// given, is what parsed it.
Options parse(const std::vector<std::string>& args, std::unique_ptr<CLI::App>* app = nullptr) {
  auto cli = std::make_unique<CLI::App>();
  Options o;
  lcjit::app::declareOptions(*cli, o);
  std::vector<char*> argv{const_cast<char*>("lcjit")};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  cli->parse(lcjit::app::argumentsForParse((int)argv.size(), argv.data()));
  if (app) *app = std::move(cli);
  return o;
}

// Every option with a value other than its default, in lpfg's spellings where lpfg has them.
const std::vector<std::string> kEveryOption = {
    "-b", "-out", "a.png", "-out", "b.obj", "--fps", "30", "--record", "rec%04d.png", "-a", "-c", "-d", "-ds",
    "-dtf", "-dtfes", "--output-frames", "-q", "-v", "-rmode", "trig", "-w", "640", "480.5", "-wp", "10", "20",
    "-wpr", "0.25", "0.5", "-wr", "0.5", "0.75", "-wnb", "-wnm", "-cleanEA20", "--environment-timeout", "0.1",
    "-cn", "-tablet", "-timed", "-dll", "lsys.so", "-lp", "/usr/lib", "--stats", "--profile", "p.json", "-O", "2",
    "--tier-after", "100", "--panel", "Parameters", "--panel", "Profile", "--lab", "--sandbox", "--max-cpu", "30",
    "--max-file-size", "2M", "--max-threads", "64", "--sandboxed", "5", "--reply-fd", "6", "--to-step=-2",
    "--plain-errors", "--watch", "--emit-cpp", "--steps", "3", "--run", "grow", "--max-modules", "1000", "--max-memory", "1G", "--time-limit",
    "1.5e-3", "-D", "A=1", "-D", "B=x y", "--seed", "18446744073709551615", "--variation", "ABC", "--frames", "12",
    "--run-record", "r.json", "--debugger", "-I", "inc", "-I", "/abs/inc", "plant.v", "plant.l"};

TEST(Options, EveryOptionIsOnTheTestsCommandLine) {
  std::unique_ptr<CLI::App> app;
  parse(kEveryOption, &app);
  for (const CLI::Option* o : app->get_options()) {
    if (o == app->get_help_ptr() || o == app->get_version_ptr()) continue;
    EXPECT_GT(o->count(), 0u) << o->get_name(true, true) << " is missing from kEveryOption";
  }
}

TEST(Options, ChildParsesWhatTheParentParsed) {
  const Options parent = parse(kEveryOption);
  // What stays with the parent: the window's options, the watcher, the sandbox and its limits,
  // what a sandboxed run refuses, lpfg's options that do nothing, and the child's own options,
  // which the sandbox gives each run. (--profile goes with the child: its table is printed there;
  // the sandbox refuses a profile file before it makes a child.)
  Options expected = parent;
  const Options defaults;
  expected.animate = defaults.animate;
  expected.record = defaults.record;
  expected.rmode = defaults.rmode;
  expected.winPos = defaults.winPos;
  expected.winPosRel = defaults.winPosRel;
  expected.winSizeRel = defaults.winSizeRel;
  expected.noBorder = defaults.noBorder;
  expected.noMessageLog = defaults.noMessageLog;
  expected.panels = defaults.panels;
  expected.cn = defaults.cn;
  expected.tablet = defaults.tablet;
  expected.timer = defaults.timer;
  expected.dll = defaults.dll;
  expected.libPath = defaults.libPath;
  expected.lab = defaults.lab;
  expected.sandbox = defaults.sandbox;
  expected.watch = defaults.watch;
  expected.runRecord = defaults.runRecord;
  expected.debugger = defaults.debugger;
  expected.maxCpuSeconds = defaults.maxCpuSeconds;
  expected.maxFileSize = defaults.maxFileSize;
  expected.maxThreads = defaults.maxThreads;
  expected.reportFd = defaults.reportFd;
  expected.replyFd = defaults.replyFd;
  expected.toStep = defaults.toStep;

  const std::vector<std::string> args = lcjit::app::childArguments(parent);
  const Options child = parse(args);
  EXPECT_EQ(child, expected);
  // The numbers read back as the parent read them, not rounded in writing.
  EXPECT_EQ(child.environmentTimeout, 0.1);
  EXPECT_EQ(child.timeLimit, 1.5e-3);
  EXPECT_EQ(child.winSize, (std::vector<float>{640, 480.5f}));
  EXPECT_EQ(child.seed, 18446744073709551615ull);
  EXPECT_EQ(child.maxMemory, size_t(1) << 30);
  // The inputs come last, in their order.
  ASSERT_GE(args.size(), 2u);
  EXPECT_EQ(args[args.size() - 2], "plant.v");
  EXPECT_EQ(args.back(), "plant.l");
}

TEST(Options, EveryOptionIsWrittenBack) {
  const Options parsed = parse(kEveryOption);
  EXPECT_EQ(parse(lcjit::app::commandLine(parsed)), parsed);
}

TEST(Options, DefaultsGoToTheChildAsTheyAre) {
  const Options parent = parse({"plant.l"});
  EXPECT_EQ(parse(lcjit::app::childArguments(parent)), parent);
  EXPECT_FALSE(parent.optLevel);  // without -O the tiers are lcjit's choice, in the child too
}

TEST(Options, LpfgSpellingsAreLcjits) {
  EXPECT_EQ(parse({"-out", "x.str", "-ds", "-wp", "1", "2", "-timer", "-o", "l.so", "m.l"}),
            parse({"--out", "x.str", "--ds", "--wp", "1", "2", "--timed", "--dll", "l.so", "m.l"}));
}

}  // namespace
