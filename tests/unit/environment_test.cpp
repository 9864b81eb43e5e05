// Environmental programs (lpfg manual §5.10, vlab environment manual §1.4, §2): the .e reader,
// the exchange over each transport with the test program tests/environment/envfixture.cpp, the
// step order, the answers' rules, and a program that fails. Expected values are worked out by
// hand from the manual and lpfg's rules (docs/environment.md), not taken from lcjit's output.
#include <gtest/gtest.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <sys/ipc.h>
#include <sys/sem.h>
#include <unistd.h>

#include "runtime/environment/ChildProgram.h"
#include "runtime/Engine.h"
#include "app/session/Session.h"
#include "runtime/files/CommSpec.h"

using namespace lcjit;
using namespace lcjit::app;
namespace fs = std::filesystem;

namespace {

// ---- the .e reader

TEST(CommSpec, ReadsEveryCommand) {
  std::vector<runtime::ViewFileWarning> w;
  auto s = runtime::parseCommSpec("executable: prog -x 1\ncommunication type: memory\nturtle position: P: %f %f %f\n"
                                  "turtle heading:%g %g %g\nturtle line width: W: %.2f\nfollowing module: on\n"
                                  "verbose: yes\n",
                                  "a.e", w);
  ASSERT_TRUE(bool(s)) << llvm::toString(s.takeError());
  EXPECT_EQ(s->executable, "prog -x 1");
  EXPECT_EQ(s->transport, runtime::CommSpec::Transport::Memory);
  EXPECT_EQ(s->position, " P: %f %f %f");  // verbatim: the program skips up to the first '%'
  EXPECT_EQ(s->heading, "%g %g %g");
  EXPECT_EQ(s->lineWidth, " W: %.2f");
  EXPECT_TRUE(s->left.empty());
  EXPECT_TRUE(s->followingModule);
  EXPECT_TRUE(s->verbose);
  EXPECT_TRUE(w.empty());
  // `-e FILE` goes after the program's name unless the line names one.
  EXPECT_EQ(runtime::environmentArguments(*s), (std::vector<std::string>{"prog", "-e", "a.e", "-x", "1"}));
  s->executable = "prog -e other.e spec";
  EXPECT_EQ(runtime::environmentArguments(*s), (std::vector<std::string>{"prog", "-e", "other.e", "spec"}));
}

TEST(CommSpec, DefaultsToPipesAsTheProgramsLibraryDoes) {
  std::vector<runtime::ViewFileWarning> w;
  auto s = runtime::parseCommSpec("executable: prog\n", "a.e", w);
  ASSERT_TRUE(bool(s));
  EXPECT_EQ(s->transport, runtime::CommSpec::Transport::Pipes);
  EXPECT_TRUE(s->position.empty());
  EXPECT_FALSE(s->followingModule);
}

TEST(CommSpec, ErrorsNameFileLineAndColumn) {
  std::vector<runtime::ViewFileWarning> w;
  auto noProgram = runtime::parseCommSpec("communication type: files\n", "a.e", w);
  ASSERT_FALSE(bool(noProgram));
  EXPECT_NE(llvm::toString(noProgram.takeError()).find("a.e:1:1: error: no 'executable:' line"), std::string::npos);
  auto badType = runtime::parseCommSpec("executable: p\ncommunication type: carrier pigeon\n", "a.e", w);
  ASSERT_FALSE(bool(badType));
  EXPECT_NE(llvm::toString(badType.takeError()).find("a.e:2:21: error: unknown communication type 'carrier'"),
            std::string::npos);
  // A format gets three doubles: %s would read a pointer that is not there.
  auto badFormat = runtime::parseCommSpec("executable: p\nturtle position: P: %f %s\n", "a.e", w);
  ASSERT_FALSE(bool(badFormat));
  EXPECT_NE(llvm::toString(badFormat.takeError()).find("a.e:2:24: error: a turtle format"), std::string::npos);
  auto fourNumbers = runtime::parseCommSpec("executable: p\nturtle up: %f %f %f %f\n", "a.e", w);
  EXPECT_FALSE(bool(fourNumbers));
  llvm::consumeError(fourNumbers.takeError());
  w.clear();
  auto ok = runtime::parseCommSpec("executable: p\n  verbose: on\nnonsense: 1\nverbose: maybe\n", "a.e", w);
  ASSERT_TRUE(bool(ok));
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].line, 2);
  EXPECT_NE(w[1].message.find("unknown command 'nonsense:'"), std::string::npos);
  EXPECT_EQ(w[2].column, 10);
}

// ---- runs with the test program

struct Scratch {
  fs::path dir, before;
  Scratch() {
    before = fs::current_path();
    dir = fs::temp_directory_path() / ("lcjit-env-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::current_path(dir);  // the files transport works in the current folder, as lpfg's does
  }
  ~Scratch() {
    fs::current_path(before);
    fs::remove_all(dir);
  }
};

std::string fixture() { return LCJIT_ENV_FIXTURE; }

struct ModelRun {
  std::unique_ptr<Session> session;
  llvm::Error loadError = llvm::Error::success();
  llvm::Error runError = llvm::Error::success();
  std::vector<std::string> warnings;
  ~ModelRun() {
    llvm::consumeError(std::move(loadError));
    llvm::consumeError(std::move(runError));
  }
  std::string load() { return loadError ? llvm::toString(std::move(loadError)) : std::string(); }
  std::string run() { return runError ? llvm::toString(std::move(runError)) : std::string(); }
  // The floats of the n-th module named `name` in the string.
  std::vector<float> values(const char* name, int count, int nth = 0) {
    runtime::Engine& e = session->engine();
    int id = e.modules().find(name);
    const runtime::ModuleBuffer& s = e.string();
    for (size_t p = 0; p < s.size(); p = e.modules().next(s.data(), p)) {
      if (runtime::ModuleTable::idAt(s.data() + p) != id || nth-- > 0) continue;
      std::vector<float> v(count);
      std::memcpy(v.data(), s.data() + p + 4, sizeof(float) * count);  // after the 2-byte id, float-aligned
      return v;
    }
    return {};
  }
};

// Writes m.l and m.e and runs the model to its end in a new session.
void run(ModelRun& r, const std::string& lsystem, const std::string& espec, runtime::ChildProgramOptions options = {},
         bool cleanEA20 = false, double timeLimit = 0) {
  std::ofstream("m.l") << "#include <lpfgall.h>\n" << lsystem;
  std::ofstream("m.e") << espec;
  auto s = Session::create();
  ASSERT_TRUE(bool(s)) << llvm::toString(s.takeError());
  r.session = std::move(*s);
  Session::EnvironmentSettings settings;
  settings.program = options;
  settings.cleanEA20 = cleanEA20;
  r.session->setEnvironmentSettings(settings);
  runtime::EngineLimits limits;
  limits.timeLimit = timeLimit;
  r.session->setLimits(limits);
  ModelFiles files;
  files.lsystem = "m.l";
  files.environment = "m.e";
  PhaseTimes t;
  r.loadError = r.session->load(files, 0, t);
  if (r.loadError) return;
  runtime::EngineHooks hooks;
  hooks.warning = [&r](const std::string& w) { r.warnings.push_back(w); };
  r.runError = r.session->engine().run(hooks);
}

std::string espec(const std::string& transport, const std::string& mode, const std::string& extra = "") {
  return "executable: " + fixture() + " " + mode + "\ncommunication type: " + transport + "\n" + extra;
}

// E1(1) E2(2,3) EA20(5,6,0…): each step's pass sends the values and the program adds one to
// each; there are two passes (steps 1 and 2; none after the last step), so E1 ends at 3, E2 at
// (4,5), EA20 at (7,8,2,2,…).
const char* kThreeModules =
    "derivation length: 2;\nEA20Array ea = {5, 6};\naxiom: E1(1) E2(2,3) EA20(ea);\n";

class Transports : public ::testing::TestWithParam<const char*> {};

TEST_P(Transports, AnswersOverwriteTheModulesBeforeEachStep) {
  Scratch scratch;
  ModelRun r;
  run(r, kThreeModules, espec(GetParam(), "plus1"));
  ASSERT_EQ(r.load(), "");
  ASSERT_EQ(r.run(), "");
  EXPECT_EQ(r.values("E1", 1), std::vector<float>{3});
  EXPECT_EQ(r.values("E2", 2), (std::vector<float>{4, 5}));
  std::vector<float> ea(20, 2);
  ea[0] = 7, ea[1] = 8;
  EXPECT_EQ(r.values("EA20", 20), ea);
  EXPECT_TRUE(r.warnings.empty());
  r.session.reset();  // stops the program: nothing may be left behind
  for (auto& f : fs::directory_iterator("."))
    EXPECT_EQ(f.path().filename().string().rfind(".to_field", 0), std::string::npos) << f.path();
}

// Every turtle field, read back through an EA20: after SetWidth(3) f(2) Left(90) the turtle is
// at (0,2,0), heading (-1,0,0) (the old left), left (0,-1,0), up (0,0,1), width 3, scale 1.
// 14 values answered: elements 14..19 keep their 9s (or become 0 with -cleanEA20).
TEST_P(Transports, EveryTurtleFieldIsSent) {
  const std::string lines =
      "turtle position: P: %f %f %f\nturtle heading: H: %f %f %f\nturtle left: L: %f %f %f\nturtle up: U: %f %f %f\n"
      "turtle line width: W: %f\nturtle scale factor: S: %f\n";
  const char* model =
      "derivation length: 1;\nEA20Array ea = {9,9,9,9,9,9,9,9,9,9,9,9,9,9,9,9,9,9,9,9};\n"
      "axiom: SetWidth(3) f(2) Left(90) EA20(ea);\n";
  std::vector<float> want = {0, 2, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 3, 1, 9, 9, 9, 9, 9, 9};
  for (bool clean : {false, true}) {
    Scratch scratch;
    ModelRun r;
    run(r, model, espec(GetParam(), "turtle", lines), {}, clean);
    ASSERT_EQ(r.load(), "");
    ASSERT_EQ(r.run(), "");
    if (clean) std::fill(want.begin() + 14, want.end(), 0.0f);
    EXPECT_EQ(r.values("EA20", 20), want) << (clean ? "-cleanEA20" : "");
  }
}

INSTANTIATE_TEST_SUITE_P(Environment, Transports, ::testing::Values("files", "memory", "pipes"));

// The pass comes before StartEach and the productions, so a production sees this step's answer:
// 0 → 1 → ×10 = 10 → 11 → 110 → 111 → 1110. NoEnvironment() in StartEach of step 1 skips the
// passes of steps 2 and 3: 0 → 1 → 10 → 100 → 1000.
TEST(Environment, ProductionsSeeTheAnswersOfTheirStep) {
  const std::string body = "derivation length: 3;\naxiom: E1(0);\nE1(x) : { produce E1(x * 10); }\n";
  for (bool quiet : {false, true}) {
    Scratch scratch;
    ModelRun r;
    run(r, (quiet ? "Start: { Environment(); }\nStartEach: { if (StepNo() == 1) NoEnvironment(); }\n" : "") + body,
        espec("files", "plus1"));
    ASSERT_EQ(r.load(), "");
    ASSERT_EQ(r.run(), "");
    EXPECT_EQ(r.values("E1", 1), std::vector<float>{quiet ? 1000.0f : 1110.0f});
  }
}

// Step 1's pass answers E1(-1) with 0; its production then makes E1(0) … E1(3999) E1(0), whose
// 4001 records (about 80 KB) step 2's pass sends: each answered plus one.
const char* kManyModules =
    "derivation length: 2;\nint done = 0;\naxiom: E1(-1);\n"
    "E1(x) : { if (!done) { done = 1; for (int i = 0; i < 4000; ++i) nproduce E1(i); produce E1(x); } }\n";

// Answers split into chunks (`Control: 1`, `0`, `4`) are all read; a request of more than the
// shared memory's 50 000 bytes goes in chunks too (3000 modules of about 20 bytes).
TEST(Environment, LongExchangesGoInChunks) {
  for (const char* transport : {"files", "memory"}) {
    Scratch scratch;
    ModelRun r;
    run(r, "derivation length: 1;\naxiom: E1(1) E1(2) E1(3) E1(4) E1(5);\n", espec(transport, "chunk 2"));
    ASSERT_EQ(r.load(), "") << transport;
    ASSERT_EQ(r.run(), "") << transport;
    for (int i = 0; i < 5; ++i) EXPECT_EQ(r.values("E1", 1, i), std::vector<float>{float(i + 2)}) << transport;
  }
  Scratch scratch;
  ModelRun r;
  run(r, kManyModules, espec("memory", "plus1"));
  ASSERT_EQ(r.load(), "");
  ASSERT_EQ(r.run(), "");
  EXPECT_EQ(r.values("E1", 1, 0), std::vector<float>{1});
  EXPECT_EQ(r.values("E1", 1, 3999), std::vector<float>{4000});
  EXPECT_EQ(r.values("E1", 1, 4000), std::vector<float>{1});
}

// A program that answers each module as it reads it, over pipes: more than a pipe's 64 KB each
// way, so lcjit must read while it writes.
TEST(Environment, ImmediateAnswersOverPipes) {
  Scratch scratch;
  ModelRun r;
  run(r, kManyModules, espec("pipes", "immediate", "turtle position: %f %f %f\n"));
  ASSERT_EQ(r.load(), "");
  ASSERT_EQ(r.run(), "");
  EXPECT_EQ(r.values("E1", 1, 0), std::vector<float>{1});
  EXPECT_EQ(r.values("E1", 1, 3999), std::vector<float>{4000});
  EXPECT_EQ(r.values("E1", 1, 4000), std::vector<float>{1});
}

TEST(Environment, UnusableAnswersAreWarningsAndChangeNothing) {
  Scratch scratch;
  ModelRun r;
  run(r, "derivation length: 1;\naxiom: E1(4);\n", espec("files", "garbage"));
  ASSERT_EQ(r.load(), "");
  ASSERT_EQ(r.run(), "");
  EXPECT_EQ(r.values("E1", 1), std::vector<float>{4});
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("m.e: warning: the environmental program's answer 'hello'"), std::string::npos);
}

// ---- a program that fails

TEST(EnvironmentFailures, MissingProgram) {
  Scratch scratch;
  ModelRun r;
  run(r, kThreeModules, "executable: /nonexistent/envprog\ncommunication type: files\n");
  std::string e = r.load();
  EXPECT_NE(e.find("m.e: error: cannot start the environmental program '/nonexistent/envprog' (line 1): not found"),
            std::string::npos)
      << e;
}

TEST(EnvironmentFailures, CrashExitHangAndSilence) {
  struct Case {
    const char* mode;
    const char* message;
  } cases[] = {{"crash", "was killed by signal"}, {"exit", "exited with status 3 without answering"},
               {"hang", "did not answer within 0.3 s"}, {"silent", "was not ready after 0.3 s"}};
  for (const Case& c : cases) {
    for (const char* transport : {"files", "pipes"}) {
      Scratch scratch;
      ModelRun r;
      runtime::ChildProgramOptions o;
      o.startSeconds = o.answerSeconds = 0.3;
      run(r, kThreeModules, espec(transport, c.mode), o);
      std::string e = r.load() + r.run();
      EXPECT_NE(e.find("m.e: error: the environmental program " + fixture()), std::string::npos) << c.mode << " " << e;
      EXPECT_NE(e.find(c.message), std::string::npos) << c.mode << " " << transport << ": " << e;
    }
  }
}

// The program of a model is stopped when the model is reloaded (the new one starts) and when the
// session ends; a step stopped by the time limit while the program computes leaves the session
// usable: the next run starts the program again.
TEST(EnvironmentFailures, ReloadAndStopLeaveNothingBehind) {
  Scratch scratch;
  fs::path log = fs::current_path() / "fixture.log";
  setenv("LCJIT_ENV_FIXTURE_LOG", log.c_str(), 1);
  auto pids = [&] {
    std::vector<std::pair<int, int>> out;  // pid, semaphore key
    std::ifstream f(log);
    std::string word;
    int pid, key;
    while (f >> word) {
      if (word == "pid" && f >> pid >> key) out.push_back({pid, key});
      else if (word == "step") f >> pid;
    }
    return out;
  };
  {
    ModelRun r;
    run(r, kThreeModules, espec("files", "hang"), {}, false, /*timeLimit=*/0.5);
    ASSERT_EQ(r.load(), "");
    std::string e = r.run();
    EXPECT_NE(e.find("stopped"), std::string::npos) << e;
    // Edit the .e file and reload: the hung program goes, the new one answers.
    std::ofstream("m.e") << espec("files", "plus1");
    ModelFiles files;
    files.lsystem = "m.l";
    files.environment = "m.e";
    PhaseTimes t;
    llvm::Error reload = r.session->load(files, 0, t);
    ASSERT_FALSE(bool(reload)) << llvm::toString(std::move(reload));
    llvm::Error rerun = r.session->engine().run();
    ASSERT_FALSE(bool(rerun)) << llvm::toString(std::move(rerun));
    EXPECT_EQ(r.values("E1", 1), std::vector<float>{3});
    auto started = pids();
    ASSERT_EQ(started.size(), 2u);
    EXPECT_NE(kill(started[0].first, 0), 0) << "the first program is still running";
    EXPECT_EQ(kill(started[1].first, 0), 0);
  }
  unsetenv("LCJIT_ENV_FIXTURE_LOG");
  for (auto [pid, key] : pids()) {
    EXPECT_NE(kill(pid, 0), 0) << "program " << pid << " outlived its session";
    EXPECT_LT(semget(key, 0, 0), 0) << "semaphores " << key << " left behind";
  }
  for (auto& f : fs::directory_iterator("."))
    EXPECT_EQ(f.path().filename().string().find("_field"), std::string::npos) << f.path();
}

// A program that does not leave when asked is killed with its process group: what it started (a
// script's background command) goes with it, not only the program.
TEST(EnvironmentFailures, AKilledProgramTakesWhatItStartedWithIt) {
  Scratch scratch;
  const fs::path childPid = fs::current_path() / "child.pid";
  std::ofstream("prog.sh") << "#!/bin/sh\nsleep 86400 </dev/null >/dev/null 2>&1 &\necho $! > " << childPid.string()
                           << "\nexec " << fixture() << " \"$@\"\n";
  fs::permissions("prog.sh", fs::perms::owner_all);
  {
    ModelRun r;
    run(r, kThreeModules, "executable: ./prog.sh hang\ncommunication type: pipes\n", {}, false, /*timeLimit=*/0.5);
    ASSERT_EQ(r.load(), "");
    std::string e = r.run();
    EXPECT_NE(e.find("stopped"), std::string::npos) << e;
  }  // the session ends: the hung program is asked to leave, then killed
  int pid = 0;
  std::ifstream(childPid) >> pid;
  ASSERT_GT(pid, 0);
  // SIGKILL is delivered at once but the process ends a moment later: a bound only a broken
  // machine reaches. A zombie's command line is empty.
  auto running = [pid] {
    std::ifstream cmdline("/proc/" + std::to_string(pid) + "/cmdline");
    std::string text((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    return text.find("86400") != std::string::npos;
  };
  for (int i = 0; i < 6000 && running(); ++i) usleep(10000);
  EXPECT_FALSE(running()) << "the program's child " << pid << " outlived it";
  if (running()) kill(pid, SIGKILL);
}

}  // namespace

// ---- the built-in honda81 (vlab environment manual §3.1.1, and vlab's build's rules)

namespace {

runtime::CommSpec hondaSpec(const std::string& specText, const std::string& position = " P: %f %f %f") {
  std::ofstream("density.spec") << specText;
  runtime::CommSpec spec;
  spec.file = "m.e";
  spec.executable = "honda81 -e m.e density.spec";
  spec.transport = runtime::CommSpec::Transport::Files;
  spec.position = position;
  return spec;
}

std::string ask(runtime::EnvironmentLink& link, const std::vector<std::string>& records) {
  auto a = link.exchange(records, 1, [] {});
  return a ? *a : llvm::toString(a.takeError());
}

}  // namespace

TEST(BuiltinHonda81, VigorGroupsAndRadius) {
  Scratch scratch;
  auto link = runtime::startBuiltinProgram("honda81", hondaSpec("radius: 1\n3d case: on\n"));
  ASSERT_TRUE(bool(link)) << llvm::toString(link.takeError());
  // 10 (vigor 0.5) lies within 1 of 20 (0.7): 10 stops, 20 does not. 30 and 40 have equal vigor
  // and are 0.5 apart: both stop. 50 is in group 1 alone: it goes on. 60 is 1 away from 20 on
  // the boundary (distance² = 1 ≤ 1): it stops.
  EXPECT_EQ(ask(**link, {"10 E(0.500000)\n P: 0.000000 0.000000 0.000000\n",
                         "20 E(0.700000)\n P: 0.500000 0.000000 0.000000\n",
                         "30 E(1.000000)\n P: 5.000000 0.000000 0.000000\n",
                         "40 E(1.000000)\n P: 5.000000 0.500000 0.000000\n",
                         "50 E(0.200000,1.000000)\n P: 0.000000 0.000000 0.000000\n",
                         "60 E(0.100000)\n P: 0.500000 1.000000 0.000000\n"}),
            "10 E(0)\n20 E(1)\n30 E(0)\n40 E(0)\n50 E(1)\n60 E(0)\n");
}

TEST(BuiltinHonda81, FloatArithmeticAndTwoDimensions) {
  Scratch scratch;
  // radius 0.1: r² = fl(0.1f·0.1f) = 0.010000001; 0.3f − 0.2f = 0.10000001, squared 0.010000002:
  // just outside, so no collision, as in vlab's float build (a double computation would collide).
  auto link = runtime::startBuiltinProgram("honda81", hondaSpec("radius:  0.1\n"));
  ASSERT_TRUE(bool(link));
  EXPECT_EQ(ask(**link, {"1 E(0.5)\n P: 0.3 0 0\n", "2 E(0.6)\n P: 0.2 0 0\n"}), "1 E(1)\n2 E(1)\n");
  // Without `3d case: on` the discs lie in x and z: y does not count.
  EXPECT_EQ(ask(**link, {"1 E(0.5)\n P: 0 0 0\n", "2 E(0.6)\n P: 0 7 0.05\n"}), "1 E(0)\n2 E(1)\n");
  // A query without three position numbers gets no answer.
  auto noPosition = runtime::startBuiltinProgram("honda81", hondaSpec("radius: 1\n", " P: %f %f"));
  ASSERT_TRUE(bool(noPosition));
  EXPECT_EQ(ask(**noPosition, {"1 E(0.5)\n P: 0 0\n"}), "");
}

TEST(BuiltinHonda81, TakesOverWhenNoHonda81IsOnPath) {
  Scratch scratch;
  std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (fs::current_path() / "empty").c_str(), 1);
  std::ofstream("density.spec") << "radius: 0.5\n3d case: on\n";
  // Two apices 0.3 apart with vigors 0.4 and 0.9: after step 1's exchange the first is 0, the
  // second 1; step 2 asks again with those vigors: 0 stays dominated by 1 (0 → 0), 1 stays 1.
  ModelRun r;
  std::vector<std::string> log;
  runtime::ChildProgramOptions o;
  o.log = [&](const std::string& l) { log.push_back(l); };
  run(r, "derivation length: 2;\naxiom: E1(0.4) f(0.3) E1(0.9);\n",
      "executable: honda81 -e m.e density.spec\ncommunication type: files\nturtle position: P: %f %f %f\n", o);
  setenv("PATH", path.c_str(), 1);
  ASSERT_EQ(r.load(), "");
  ASSERT_EQ(r.run(), "");
  EXPECT_EQ(r.values("E1", 1, 0), std::vector<float>{0});
  EXPECT_EQ(r.values("E1", 1, 1), std::vector<float>{1});
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log[0], "honda81 is not on PATH: lcjit's built-in honda81 answers");
}
