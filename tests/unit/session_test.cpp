// Session reloads: each of lpfg's New … menu items re-reads exactly the files of the manual's
// §1.2.2 table. The test edits every input file after the first load, then checks which edits
// each reload picked up: the L-system (a different production), the view file (line style), the
// colormap (colour 1) and a function file (its value).
#include <gtest/gtest.h>

#include <filesystem>
#include <chrono>
#include <fstream>
#include <functional>
#include <sstream>
#include <atomic>
#include <future>
#include <thread>

#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/common/PlainErrors.h"
#include "app/batch/ProgramPages.h"
#include "app/session/Session.h"
#include "runtime/WindowInput.h"
#include "runtime/include/lcjit/modules.h"

#include <algorithm>
#include <cstring>

using namespace lcjit;
using namespace lcjit::app;
namespace fs = std::filesystem;

namespace {

struct Model {
  fs::path dir;
  ModelFiles files;

  Model() {
    dir = fs::temp_directory_path() / ("lcjit-session-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    files.lsystem = (dir / "m.l").string();
    files.view = (dir / "m.v").string();
    files.colormap = (dir / "m.map").string();
    files.functions = {(dir / "len.func").string()};
    write(1, "pixel", 10, 1.0f);
  }
  ~Model() { fs::remove_all(dir); }

  // Version `v` of the L-system draws v+1 segments of length len(0); the colormap's colour 1 has
  // red = `red`; the function is constant `value`.
  void write(int v, const char* lineStyle, int red, float value) {
    std::ofstream(dir / "m.l") << "#include <lpfgall.h>\nderivation length: 1;\nmodule A;\naxiom: A;\nA : { produce ";
    {
      std::ofstream l(dir / "m.l", std::ios::app);
      for (int i = 0; i <= v; ++i) l << "F(func(len, 0)) ";
      l << "; }\n";
    }
    std::ofstream(dir / "m.v") << "line style: " << lineStyle << "\n";
    std::string map(768, '\0');
    map[3] = (char)red;
    std::ofstream(dir / "m.map", std::ios::binary) << map;
    std::ofstream f(dir / "len.func");
    f << "fver 1 1\nname: len\nsamples: 5\nflip: off\npoints: 4\n";
    for (float x : {0.f, 0.33f, 0.66f, 1.f}) f << x << " " << value << "\n";
  }
};

// A one-file model in a scratch folder, loaded into a new Session at -O1.
struct ScratchModel {
  fs::path dir;
  std::unique_ptr<Session> session;

  ScratchModel(const std::string& name, const std::string& source) {
    dir = fs::temp_directory_path() / ("lcjit-" + name + "-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / (name + ".l")) << source;
    auto s = Session::create();
    if (!s) {
      ADD_FAILURE() << llvm::toString(s.takeError());
      return;
    }
    ModelFiles files;
    files.lsystem = (dir / (name + ".l")).string();
    PhaseTimes t;
    if (auto e = (*s)->load(files, 1, t)) {
      ADD_FAILURE() << llvm::toString(std::move(e));
      return;
    }
    session = std::move(*s);
  }
  ~ScratchModel() { fs::remove_all(dir); }
};

struct Picture {
  size_t segments = 0, triangles = 0;
  float length = 0, red = 0;
  int steps = 0;
};

Picture look(Session& s) {
  runtime::Geometry g;
  if (auto e = s.engine().interpret(g)) ADD_FAILURE() << llvm::toString(std::move(e));
  Picture p;
  p.segments = g.segments.size();
  p.triangles = g.triangleCount();
  if (!g.segments.empty()) p.length = (g.segments[0].to - g.segments[0].from).Length();
  p.red = s.drawing().palette.color(1)[0];
  p.steps = s.engine().stepsDone();
  return p;
}

class SessionReload : public ::testing::Test {
 protected:
  void SetUp() override {
    auto r = Session::create();
    ASSERT_TRUE(bool(r)) << llvm::toString(r.takeError());
    session = std::move(*r);
    load(ReloadParts::all());
    run();
    Picture p = look(*session);
    ASSERT_EQ(p.segments, 2u);
    ASSERT_NEAR(p.length, 1.0f, 1e-5);
    ASSERT_NEAR(p.red, 10 / 255.f, 1e-3);
    // Every file changes: 4 segments, cylinders, red 200, length 2.
    model.write(3, "cylinder", 200, 2.0f);
  }
  void load(ReloadParts what) {
    PhaseTimes t;
    auto e = session->load(model.files, 1, t, what);
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  }
  void run() { ASSERT_FALSE(bool(session->engine().run())); }

  Model model;
  std::unique_ptr<Session> session;
};

TEST_F(SessionReload, NewModelRereadsEverything) {
  load(ReloadParts::all());
  run();
  Picture p = look(*session);
  EXPECT_EQ(p.segments, 0u);  // cylinders now
  EXPECT_GT(p.triangles, 0u);
  EXPECT_NEAR(p.red, 200 / 255.f, 1e-3);
}

TEST_F(SessionReload, NewLsystemKeepsTheView) {
  load(ReloadParts::newLsystem());
  run();
  Picture p = look(*session);
  EXPECT_EQ(p.segments, 4u);           // recompiled
  EXPECT_NEAR(p.length, 2.0f, 1e-5);   // functions re-read
  EXPECT_NEAR(p.red, 200 / 255.f, 1e-3);  // colours re-read
}

TEST_F(SessionReload, NewRunKeepsTheCompiledModelAndView) {
  load(ReloadParts::newRun());
  run();
  Picture p = look(*session);
  EXPECT_EQ(p.segments, 2u);  // not recompiled, view not re-read (still pixel lines)
  EXPECT_NEAR(p.length, 2.0f, 1e-5);
  EXPECT_NEAR(p.red, 200 / 255.f, 1e-3);
}

TEST_F(SessionReload, NewViewRedrawsWithoutRerunning) {
  load(ReloadParts::newView());
  Picture p = look(*session);  // no run: the string is the one already derived
  EXPECT_EQ(p.steps, 1);
  EXPECT_EQ(p.segments, 0u);  // the view file's cylinders apply
  EXPECT_GT(p.triangles, 0u);
  EXPECT_NEAR(p.red, 200 / 255.f, 1e-3);
}

TEST_F(SessionReload, ABrokenEditKeepsTheLastGoodModel) {
  std::ofstream(model.dir / "m.l") << "#include <lpfgall.h>\nderivation length: 1;\naxiom: Undeclared;\n";
  PhaseTimes t;
  auto e = session->load(model.files, 1, t, ReloadParts::newLsystem());
  ASSERT_TRUE(bool(e));
  EXPECT_NE(llvm::toString(std::move(e)).find("m.l:3:"), std::string::npos);
  Picture p = look(*session);
  EXPECT_EQ(p.segments, 2u);  // the last good model, its string and files
  EXPECT_NEAR(p.red, 10 / 255.f, 1e-3);
}

}  // namespace

namespace {

TEST(EngineCancel, StopDuringALongStepKeepsTheStringBeforeIt) {
  // Each step rewrites 200 000 modules, each production busy for a while: cancelStep() from
  // another thread ends the step early, leaving the string (and step number) as before it.
  ScratchModel m("long", "#include <lpfgall.h>\nderivation length: 2;\nmodule A(int);\n"
                         "axiom: A(0);\n"
                         "A(n) : { if (n == 0) { for (int i = 0; i < 200000; ++i) nproduce A(1); produce; }\n"
                         "  volatile double x = 0; for (int i = 0; i < 20000; ++i) x += i; produce A(n + 1); }\n");
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  runtime::EngineHooks hooks;
  e.begin(hooks);
  ASSERT_TRUE(e.step());  // step 1: 200 000 × A(1), fast
  size_t before = e.moduleCount();
  std::thread stopper([&e] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    e.cancelStep();
  });
  // Step 2 would take seconds (200 000 × 20 000 additions). Cancelled, it ends with the string
  // of step 1: no A(2), the step number still 1 (no bound on the time: the machine may be busy).
  bool more = e.step();
  stopper.join();
  EXPECT_FALSE(more);
  EXPECT_EQ(e.stepNo(), 1);
  EXPECT_EQ(e.moduleCount(), before);
  EXPECT_NE(e.text(e.string()).find("A(1)"), std::string::npos);
  EXPECT_EQ(e.text(e.string()).find("A(2)"), std::string::npos);
}

// What `write` streams is `whole`, which spans several of the writers' one-megabyte chunks.
void expectStreamedAsWhole(const std::string& whole, const std::function<void(std::ostream&)>& write) {
  ASSERT_GT(whole.size(), size_t(3) << 20);
  std::ostringstream streamed;
  write(streamed);
  EXPECT_EQ(streamed.str(), whole);
}

// `-out x.str` writes the text as it is formatted, a megabyte at a time: the modules one by one,
// in order, across the chunks' edges.
TEST(EngineText, WrittenAsFormattedIsTheWholeText) {
  ScratchModel m("text", "#include <lpfgall.h>\nderivation length: 1;\nmodule A(int, float);\nmodule B;\n"
                         "axiom: B;\n"
                         "B : { for (int i = 0; i < 150000; ++i) nproduce A(i, i * 0.25f) SB() EB(); produce; }\n");
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  ASSERT_FALSE(bool(e.run()));
  std::string whole;  // module by module, as the manual's text form has them
  for (int i = 0; i < 150000; ++i) {
    char a[64];
    std::snprintf(a, sizeof a, "A(%d,%.9g)\nSB\nEB\n", i, double(i * 0.25f));
    whole += a;
  }
  EXPECT_EQ(e.text(e.string()), whole);
  expectStreamedAsWhole(whole, [&](std::ostream& out) { e.writeText(e.string(), out); });
}

// The module count a forward step keeps as it derives (the limit check and --stats use it) is
// the string's: with successors of several modules, empty ones, a Cut and unchanged modules.
TEST(EngineCount, CountedAsDerivedIsTheStringsCount) {
  ScratchModel m("count", "#include <lpfgall.h>\nderivation length: 4;\nmodule A(int);\nmodule B;\nmodule C;\n"
                          "axiom: A(0) B C SB A(1) Cut() C EB C;\n"
                          "production:\nA(n) : { produce A(n+1) SB() B C EB() B; }\nB : { produce; }\n"
                          "int k = 0;\nStartEach: { ++k; }\nC : { if (k % 2) produce C C; }\n");
  ASSERT_TRUE(m.session);
  // A step counts once its predecessor string is larger (in bytes) than the module limit.
  runtime::EngineLimits limits;
  limits.maxModules = 100;
  m.session->setLimits(limits);
  runtime::Engine& e = m.session->engine();
  runtime::EngineHooks hooks;
  e.begin(hooks);
  size_t countedSteps = 0;
  for (int step = 1; e.step(); ++step) {
    size_t walked = 0;
    for (size_t p = 0; p < e.string().size(); p = e.modules().next(e.string().data(), p)) ++walked;
    EXPECT_EQ(e.moduleCount(), walked) << "after step " << step;
    EXPECT_GT(walked, size_t(4));
    countedSteps += e.string().size() > limits.maxModules;
  }
  e.finish();
  EXPECT_FALSE(bool(e.takeFault()));
  EXPECT_EQ(e.stepsDone(), 4);
  EXPECT_GE(countedSteps, size_t(2));  // the counting path was taken
}

// -dtf's turtle text streamed as the turtle goes is the text interpret() gives whole, across
// chunk edges.
TEST(EngineText, TurtleTextWrittenAsInterpretedIsTheWholeText) {
  ScratchModel m("dtf", "#include <lpfgall.h>\nderivation length: 1;\nmodule B;\naxiom: B;\n"
                        "B : { for (int i = 0; i < 60000; ++i) nproduce F(i * 0.5f) SB() Left(30) f(0.25) EB() "
                        "Circle0(); produce; }\n");
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  ASSERT_FALSE(bool(e.run()));
  std::string whole;
  ASSERT_FALSE(bool(e.interpret(nullptr, nullptr, &whole)));
  expectStreamedAsWhole(whole, [&](std::ostream& out) { EXPECT_FALSE(bool(e.writeTurtleText(out))); });
  // lpfg's TextFileTurtle: %f numbers; Circle0 also writes the Circle of half the width.
  const std::string first = "F(0.000000)\nLeft(30.000000)\nf(0.250000)\nCircle0\nCircle(0.500000)\nF(0.500000)\n";
  EXPECT_EQ(whole.substr(0, first.size()), first);
}

// §5.9: a record the host builds (MouseInsPos, inserted where the user clicked) gets the id
// repeated in its last two bytes even where its layout has padding there: the string is also
// scanned backwards (left context), from those bytes.
TEST(EngineInsert, AnInsertedRecordEndsWithItsId) {
  ScratchModel m("ins", "#include <lpfgall.h>\nderivation length: 1;\nmodule A;\naxiom: A A;\n");
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  runtime::EngineHooks hooks;
  e.begin(hooks);
  __lc_R_MouseInsPos r;
  std::memset(&r, 0, sizeof r);
  r.id = r.id2 = __lc_id_MouseInsPos;
  ASSERT_GT(sizeof r, offsetof(__lc_R_MouseInsPos, id2) + sizeof r.id2);  // padding after id2
  size_t recordA = e.string().size() / 2;
  ASSERT_TRUE(e.insertBefore(recordA, reinterpret_cast<const char*>(&r)));
  const char* end = e.string().data() + recordA + sizeof r;
  __lc_ModuleId last;
  std::memcpy(&last, end - sizeof last, sizeof last);
  EXPECT_EQ(last, __lc_id_MouseInsPos);
  EXPECT_NE(e.text(e.string()).find("MouseInsPos"), std::string::npos);
}

}  // namespace

namespace {

// Two tiers: the -O2 build of a running -O0 model is swapped in between steps without
// re-running: the string and the model's globals go on from where the -O0 code left them.
TEST(SessionTiers, BetterTierContinuesTheRunningDerivation) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-tiers-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "count.l") << "#include <lpfgall.h>\n#include <vector>\nderivation length: 6;\nmodule A(int);\n"
                                    "axiom: A(0);\nint calls = 0;\nstatic std::vector<int> seen;\n"
                                    "A(n) : { seen.push_back(n); ++calls; produce A(calls * 100 + (int)seen.size()); }\n";
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  ModelFiles files;
  files.lsystem = (dir / "count.l").string();
  PhaseTimes t;
  ASSERT_FALSE(bool((*session)->load(files, 0, t)));
  EXPECT_EQ((*session)->optLevel(), 0);
  runtime::Engine& e = (*session)->engine();
  runtime::EngineHooks hooks;
  e.begin(hooks);
  ASSERT_TRUE(e.step());
  ASSERT_TRUE(e.step());
  EXPECT_EQ(e.text(e.string()), "A(202)\n");

  auto job = (*session)->betterTierJob(2);
  BetterTier tier = std::async(std::launch::async, job).get();  // as the watcher does
  ASSERT_TRUE(tier.code) << tier.error;
  EXPECT_TRUE((*session)->installTier(std::move(tier)));
  EXPECT_EQ((*session)->optLevel(), 2);
  while (e.step()) {
  }
  EXPECT_EQ(e.stepNo(), 6);
  EXPECT_EQ(e.text(e.string()), "A(606)\n");  // calls and seen went on: no restart, no re-init

  // A tier compiled for a model that was reloaded meanwhile is not installed.
  auto stale = (*session)->betterTierJob(2);
  ASSERT_FALSE(bool((*session)->load(files, 0, t)));
  BetterTier late = stale();
  ASSERT_TRUE(late.code) << late.error;
  EXPECT_FALSE((*session)->installTier(std::move(late)));
  EXPECT_EQ((*session)->optLevel(), 0);
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(Diagnostics, ErrorsShowTheirSourceLineAndColumn) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-diag-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string file = (dir / "m.l").string();
  std::ofstream(file) << "axiom: A;\n\tX(1) : { produce Oops; }\n";
  std::string shown = withSourceLines(file + ":2:19: error: unknown module 'Oops'\n"
                                      "<lcjit: generated model tables>:1:5: error: cascade\n" +
                                      file + ":9:1: error: past the end\n");
  EXPECT_EQ(shown, file + ":2:19: error: unknown module 'Oops'\n"
                          "    2 | \tX(1) : { produce Oops; }\n"
                          "      | \t                 ^\n"
                          "<lcjit: generated model tables>:1:5: error: cascade\n" +
                       file + ":9:1: error: past the end\n");
  fs::remove_all(dir);
}

}  // namespace

namespace {

// C++ typed at the REPL runs in the model's context: expressions print, statements
// change the model's globals, declarations (functions, productions) stay until the next load.
TEST(SessionRepl, EvaluatesInTheModelsContext) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-repl-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "r.l") << "#include <lpfgall.h>\n#include <vector>\n#define START 3\nderivation length: 2;\n"
                                "module A(int);\nmodule B(float);\naxiom: A(START) B(0.5);\n"
                                "float total = 0;\nstatic std::vector<int> seen;\n"
                                "A(n) : { total += n; seen.push_back(n); produce A(n + 1); }\n"
                                // The file ends in another section: rules typed at the prompt
                                // are productions all the same.
                                "interpretation:\nA(n) : { produce F(1); }\n";
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  Session& s = **session;
  ModelFiles files;
  files.lsystem = (dir / "r.l").string();
  PhaseTimes t;
  ASSERT_FALSE(bool(s.load(files, 0, t)));
  auto eval = [&](const std::string& in) {
    auto r = s.evaluate(in);
    return r ? *r : "ERROR: " + llvm::toString(r.takeError());
  };
  EXPECT_EQ(eval("total"), "0");
  ASSERT_FALSE(bool(s.engine().run()));
  EXPECT_EQ(eval("total"), "7");                       // 3 + 4: the running model's global
  EXPECT_EQ(eval("seen.size()"), "2");                 // a static one too
  EXPECT_EQ(eval("START * 2"), "6");                   // the model's macros
  EXPECT_EQ(eval("total = 100;"), "");                 // a statement
  EXPECT_EQ(eval("total"), "100");
  EXPECT_EQ(eval("float twice(float v) { return 2 * v; }"), "");  // a declaration stays
  EXPECT_EQ(eval("twice(total) + 1"), "201");
  // Without its ';' a declaration is one still: a global the next input sees (not
  // a local variable of a statement, dropped at once).
  EXPECT_EQ(eval("int count = 5"), "");
  EXPECT_EQ(eval("count + 1"), "6");
  EXPECT_EQ(eval("V3f(1, 2, 3)"), "(1, 2, 3)");
  EXPECT_EQ(eval("Printf(\"hello\\n\")"), "");         // void: run, nothing printed here

  // Model code typed at the prompt that crashes is stopped and reported; the session goes on.
  std::string crashed = eval("*(volatile int*)nullptr = 1;");
  EXPECT_NE(crashed.find("segmentation fault"), std::string::npos) << crashed;
  EXPECT_EQ(eval("total"), "100");

  // C++ that does not return stops when the engine is interrupted (the REPL's Ctrl-C).
  std::atomic<bool> returned{false};
  std::thread stopper([&] {  // until it returns: an interrupt while it still compiles is lost
    while (!returned) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      s.engine().interrupt();
    }
  });
  std::string looped = eval("for (;;) total += 1;");
  returned = true;
  stopper.join();
  EXPECT_NE(looped.find("interrupted"), std::string::npos) << looped;
  EXPECT_EQ(eval("total = 100;"), "");

  std::string bad = eval("total +");
  EXPECT_NE(bad.find("<repl>:1:"), std::string::npos) << bad;
  EXPECT_EQ(eval("total"), "100");  // nothing broke

  // A production for B, which the model leaves alone, takes part in the next steps.
  EXPECT_EQ(eval("B(x) : { produce B(x * 2); }"), "");
  ASSERT_FALSE(bool(s.engine().run()));
  EXPECT_EQ(s.engine().text(s.engine().string()), "A(5)\nB(2)\n");
  EXPECT_EQ(eval("total"), "107");  // Start did not reset it; the new code kept the state

  // A reload replaces what was typed.
  ASSERT_FALSE(bool(s.load(files, 0, t)));
  EXPECT_NE(eval("twice(1)").find("ERROR"), std::string::npos);
  EXPECT_EQ(eval("total"), "0");
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(Diagnostics, PlainLanguageComesFirstForUserFiles) {
  std::string compiler = "/home/s/plant.l:12:9: error: use of undeclared identifier 'Apx'\n"
                         "<lcjit: generated model tables>:3:1: error: cascade\n"
                         "/home/s/plant.l:20:3: error: expected ';' after expression\n"
                         "/home/s/plant.l:12:9: error: use of undeclared identifier 'Apx'\n";
  std::string shown = inPlainLanguage(compiler);
  EXPECT_EQ(shown.find("plant.l, line 12: 'Apx' is not defined."), 0u) << shown;
  EXPECT_NE(shown.find("module Apx(...);"), std::string::npos);
  EXPECT_NE(shown.find("plant.l, line 20: A ';' is missing"), std::string::npos);
  EXPECT_EQ(shown.find("cascade"), shown.rfind("cascade"));  // only in the compiler's text
  EXPECT_EQ(shown.find("line 12"), shown.rfind("line 12"));  // said once
  EXPECT_NE(shown.find("(what the compiler said:)\n" + compiler), std::string::npos);
  EXPECT_EQ(inPlainLanguage("warning: nothing\n"), "warning: nothing\n");
}

}  // namespace

namespace {

// Incremental recompiles: an edit inside production bodies compiles only those
// productions and links them with the running code's others; the run then starts as fresh as
// after a full load (globals reset). An edit elsewhere compiles everything.
TEST(SessionIncremental, OnlyChangedProductionsCompileAndStateStartsFresh) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-incr-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string path = (dir / "inc.l").string();
  auto write = [&](int a, int b, int c, const std::string& extraLine = "") {
    std::ofstream(path) << "#include <lpfgall.h>\n#include <vector>\nderivation length: 2;\nmodule A(int);\nmodule B(int);\nmodule C(int);\n"
                           "int calls = 0;\nstatic std::vector<int> history;\naxiom: A(0) B(0) C(0);\n"
                           "A(n) : { ++calls; history.push_back(n); produce A(n + " << a << " + calls * 100 + (int)history.size() * 1000); }\n"
                           "B(n) : {\n" << extraLine << "  produce B(n + " << b << ");\n}\n"
                           "C(n) : { produce C(n + " << c << "); }\n";
  };
  write(1, 2, 3);
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  Session& s = **session;
  ModelFiles files;
  files.lsystem = path;
  auto reload = [&](PhaseTimes& t) {
    auto e = s.load(files, 0, t, ReloadParts::newLsystem());
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
    ASSERT_FALSE(bool(s.engine().run()));
  };
  auto text = [&] { return s.engine().text(s.engine().string()); };
  PhaseTimes t;
  {
    auto e = s.load(files, 0, t);
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  }
  ASSERT_FALSE(bool(s.engine().run()));
  EXPECT_EQ(t.productionsCompiled, -1);
  EXPECT_EQ(text(), "A(3302)\nB(4)\nC(6)\n");  // A: 0+1+100+1000, then +1+200+2000

  write(1, 5, 3);  // B's body
  reload(t);
  EXPECT_EQ(t.productionsCompiled, 1);
  EXPECT_EQ(text(), "A(3302)\nB(10)\nC(6)\n");  // calls and history started over: the same A

  write(1, 5, 7);  // C's: links with the first build's A and the last one's B
  reload(t);
  EXPECT_EQ(t.productionsCompiled, 1);
  EXPECT_EQ(text(), "A(3302)\nB(10)\nC(14)\n");

  write(1, 6, 7, "  int unused = 0; (void)unused;\n");  // B again, a line longer
  reload(t);
  EXPECT_EQ(t.productionsCompiled, 1);
  EXPECT_EQ(text(), "A(3302)\nB(12)\nC(14)\n");

  write(2, 6, 7, "  int unused = 0; (void)unused;\n");  // A, which uses the globals
  reload(t);
  EXPECT_EQ(t.productionsCompiled, 1);
  EXPECT_EQ(text(), "A(3304)\nB(12)\nC(14)\n");

  // A mistake in a production is reported where it is, and the model stays.
  write(2, 6, 7, "  int broken = ;\n");
  PhaseTimes bad;
  auto e = s.load(files, 0, bad, ReloadParts::newLsystem());
  ASSERT_TRUE(bool(e));
  std::string message = llvm::toString(std::move(e));
  EXPECT_NE(message.find("inc.l:12:16: error: expected expression"), std::string::npos) << message;
  EXPECT_EQ(text(), "A(3304)\nB(12)\nC(14)\n");

  // Outside the productions: everything is compiled.
  write(2, 6, 7, "  int unused = 0; (void)unused;\n");
  std::ofstream(path, std::ios::app) << "int another = 0;\n";
  reload(t);
  EXPECT_EQ(t.productionsCompiled, -1);
  EXPECT_EQ(text(), "A(3304)\nB(12)\nC(14)\n");

  // The -O2 tier of an incremental build has all the productions.
  write(2, 6, 9, "  int unused = 0; (void)unused;\n");
  std::ofstream(path, std::ios::app) << "int another = 0;\n";
  {
    auto e = s.load(files, 0, t, ReloadParts::newLsystem());
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  }
  EXPECT_EQ(t.productionsCompiled, 1);
  runtime::EngineHooks hooks;
  s.engine().begin(hooks);
  ASSERT_TRUE(s.engine().step());
  BetterTier tier = s.betterTierJob(2)();
  ASSERT_TRUE(tier.code) << tier.error;
  EXPECT_TRUE(s.installTier(std::move(tier)));
  ASSERT_FALSE(s.engine().step());
  EXPECT_EQ(text(), "A(3304)\nB(12)\nC(18)\n");
  fs::remove_all(dir);
}

// A model with a C++ unit of its own: a reload gives the first run's string again (the unit's
// globals start over, as a new lpfg library's do), whichever productions the edit changed. The
// productions an edit leaves alone must not keep calling the previous copy of the unit.
TEST(SessionIncremental, AModelsOwnUnitStartsOverWithEveryReload) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-incr-unit-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string path = (dir / "u.l").string(), unit = (dir / "counter.cpp").string();
  std::ofstream(unit) << "int counted = 0;\nint next() { return ++counted; }\n";
  auto write = [&](int c) {
    std::ofstream(path) << "#include <lpfgall.h>\nint next();\nderivation length: 2;\nmodule A(int);\nmodule B(int);\n"
                           "module C(int);\naxiom: A(0) B(0) C(0);\n"
                           "A(n) : { produce A(n * 10 + next()); }\nB(n) : { produce B(n + 1); }\n"
                           "C(n) : { produce C(n + " << c << "); }\n";
  };
  write(1);
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  Session& s = **session;
  ModelFiles files;
  files.lsystem = path;
  files.sources = {unit};
  PhaseTimes t;
  {
    auto e = s.load(files, 0, t);
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  }
  ASSERT_FALSE(bool(s.engine().run()));
  auto text = [&] { return s.engine().text(s.engine().string()); };
  EXPECT_EQ(text(), "A(12)\nB(2)\nC(2)\n");  // next() gives 1, then 2: 0*10+1, 1*10+2
  for (int c : {2, 3}) {  // C's body only: A's code is kept
    write(c);
    auto e = s.load(files, 0, t, ReloadParts::newLsystem());
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
    ASSERT_FALSE(bool(s.engine().run()));
    EXPECT_EQ(text(), "A(12)\nB(2)\nC(" + std::to_string(2 * c) + ")\n") << "after the edit to C(n + " << c << ")";
  }
  fs::remove_all(dir);
}

}  // namespace

namespace {

// Hot swap: the next version compiles while the running one derives on another thread
// (as the window does), and takes over only when installed.
TEST(SessionHotSwap, PrepareRunsBesideARunningDerivation) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-swap-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto write = [&](int add) {
    std::ofstream(dir / "swap.l") << "#include <lpfgall.h>\nderivation length: 2;\nmodule A(int);\naxiom: A(0);\n"
                                     "A(n) : { volatile double x = 0; for (int i = 0; i < 40000000; ++i) x += i; "
                                     "produce A(n + " << add << "); }\n";
  };
  write(1);
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  Session& s = **session;
  ModelFiles files;
  files.lsystem = (dir / "swap.l").string();
  PhaseTimes t;
  ASSERT_FALSE(bool(s.load(files, 0, t)));
  runtime::EngineHooks hooks;
  s.engine().begin(hooks);
  std::atomic<bool> deriving{true};
  std::thread worker([&] {
    while (s.engine().step()) {
    }
    deriving = false;
  });
  write(10);
  PhaseTimes pt;
  auto prepared = s.prepare(files, 0, pt, ReloadParts::newLsystem());
  bool preparedWhileDeriving = deriving;
  worker.join();
  ASSERT_TRUE(bool(prepared)) << llvm::toString(prepared.takeError());
  EXPECT_TRUE(preparedWhileDeriving);  // two steps of 40 M additions at -O0 outlast a compile
  EXPECT_EQ(s.engine().text(s.engine().string()), "A(2)\n");  // the old version's, undisturbed
  ASSERT_FALSE(bool(s.install(std::move(*prepared))));
  ASSERT_FALSE(bool(s.engine().run()));
  EXPECT_EQ(s.engine().text(s.engine().string()), "A(20)\n");
  fs::remove_all(dir);
}

}  // namespace

// §10.2 with no tablet driver: GetTabletStatus() is the mouse as a pen — not connected until a
// window feeds the mouse, then its position, and pressure 1 while the left button is down.
TEST(SessionTablet, TheTabletFollowsTheMouse) {
  ScratchModel m("tablet", "#include <lpfgall.h>\nderivation length: 1;\nmodule T(int, int, double);\naxiom: T(0, 0, 0);\n"
                           "T(c, x, p) : { TabletStatus t = GetTabletStatus(); produce T(t.connected, t.viewX, t.pressure); }\n");
  ASSERT_TRUE(m.session);
  ASSERT_FALSE(bool(m.session->engine().run()));
  EXPECT_EQ(m.session->engine().text(m.session->engine().string()), "T(0,0,0)\n");
  MouseStatus pointer;
  pointer.viewX = 120;
  pointer.viewY = 30;
  pointer.lbDown = true;
  m.session->windowInput().mouse.update(pointer);
  ASSERT_FALSE(bool(m.session->engine().run()));
  EXPECT_EQ(m.session->engine().text(m.session->engine().string()), "T(1,120,1)\n");
}

// The program's read-only pages released from the process (ProgramPages.h): its resident file
// pages go down, and its code, the compiler's included, still runs (from the page cache).
long rssFileKiB() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("RssFile:", 0) == 0)
      return std::stol(line.substr(8));
  return -1;
}

TEST(ProgramPages, ReleasedAndTheCodeStillRuns) {
  ScratchModel before("pages", "#include <lpfgall.h>\nderivation length: 3;\nmodule A(int);\n"
                               "axiom: A(0);\nproduction:\nA(n) : { produce A(n+1) A(n+2); }\n");
  ASSERT_TRUE(before.session);
  const long resident = rssFileKiB();
  ASSERT_GT(resident, 0);
  const size_t released = app::releaseProgramPages();
  EXPECT_GT(released, size_t(1) << 20);  // the test program's code and constants
  EXPECT_LT(rssFileKiB(), resident);
  // A new session compiles (front end, code generation, JIT link) and derives after it.
  ScratchModel after("pages2", "#include <lpfgall.h>\nderivation length: 3;\nmodule A(int);\n"
                               "axiom: A(0);\nproduction:\nA(n) : { produce A(n+1) A(n+2); }\n");
  ASSERT_TRUE(after.session);
  runtime::Engine& e = after.session->engine();
  ASSERT_FALSE(bool(e.run()));
  EXPECT_EQ(e.moduleCount(), 8u);  // A(0) doubles each of 3 steps
  EXPECT_EQ(e.text(e.string()).rfind("A(3)\nA(4)\nA(4)\nA(5)\n", 0), 0u) << e.text(e.string());
}

// The profile counts what the rules did, counted here by hand: A(n) applies once a step; the
// first B rule runs on every B and never produces; the second then applies (B doubles: 0, 1, 3 Bs
// before steps 1, 2, 3); the interpretation rule runs on each of the 7 Bs at the end.
TEST(EngineProfile, CountsEachRulesApplicationsPerStep) {
  ScratchModel m("profile", "#include <lpfgall.h>\nderivation length: 3;\nmodule A(int);\nmodule B;\n"
                            "int never = 0;\naxiom: A(0);\n"
                            "A(n) : { produce A(n+1) B; }\n"        // line 7
                            "B : { if (never) produce; }\n"         // line 8
                            "B : { produce B B; }\n"                // line 9
                            "interpretation:\nB : { produce F(1); }\n");  // line 11
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  EXPECT_EQ(e.profile(), nullptr);
  e.setProfiling(true);
  ASSERT_FALSE(bool(e.run()));
  runtime::Geometry g;
  ASSERT_FALSE(bool(e.interpret(g)));
  const runtime::Profile* p = e.profile();
  ASSERT_NE(p, nullptr);
  std::vector<runtime::RuleSource> src = runtime::ruleSources(e.model());
  auto rule = [&](int line) {
    for (size_t i = 0; i < src.size(); ++i)
      if (src[i].line == line) return i;
    ADD_FAILURE() << "no rule on line " << line;
    return size_t(0);
  };
  const size_t a = rule(7), never = rule(8), doubles = rule(9), draw = rule(11);
  EXPECT_EQ(src[a].predecessor, "A(n)");
  EXPECT_EQ(src[a].kind, "production");
  EXPECT_EQ(src[draw].kind, "interpretation");
  EXPECT_EQ(fs::path(src[a].file).filename(), "profile.l");
  const auto& t = p->total();
  EXPECT_EQ(t[a].produced, 3u);
  EXPECT_EQ(t[a].ran, 3u);
  EXPECT_EQ(t[never].ran, 4u);
  EXPECT_EQ(t[never].produced, 0u);
  EXPECT_EQ(t[doubles].produced, 4u);
  EXPECT_EQ(t[draw].produced, 7u);
  EXPECT_EQ(p->interpretation()[draw].produced, 7u);
  EXPECT_EQ(p->interpretation()[a].ran, 0u);
  // Per step: 1, then 1 + 1, then 1 + 3 (step 0, the axiom, ran no rule).
  ASSERT_EQ(p->steps().size(), 3u);
  std::vector<std::vector<uint64_t>> perStep;
  for (const auto& s : p->steps()) {
    std::vector<uint64_t> produced(src.size(), 0);
    for (const auto& [i, c] : s.rules) produced[i] = c.produced;
    perStep.push_back({uint64_t(s.step), produced[a], produced[doubles]});
  }
  EXPECT_EQ(perStep, (std::vector<std::vector<uint64_t>>{{1, 1, 0}, {2, 1, 1}, {3, 1, 3}}));
  // Hottest first leaves out what never ran; a second run starts counting afresh.
  std::vector<size_t> hot = runtime::hottestRules(t);
  EXPECT_EQ(hot.size(), 4u);
  ASSERT_FALSE(bool(e.run()));
  EXPECT_EQ(e.profile()->total()[a].produced, 3u);
  e.setProfiling(false);
  EXPECT_EQ(e.profile(), nullptr);
}

// Provenance: a history worked out by hand. Step 1: A(0) → A(1) B (line 9); C is the axiom's.
// Step 2: A(1) → A(2) B (line 9), B → E (line 10), and E decomposes into D D (line 12).
void checkOrigins(const std::string& name, const std::string& startEach) {
  ScratchModel m(name, "#include <lpfgall.h>\nderivation length: 2;\nmodule A(int);\nmodule B;\nmodule C;\n"
                            "module E;\nmodule D;\naxiom: A(0) C;\n"
                            "A(n) : { produce A(n+1) B; }\n"   // line 9
                            "B : { produce E; }\n"             // line 10
                            "decomposition:\n"
                            "E : { produce D D; }\n" + startEach);  // line 12
  ASSERT_TRUE(m.session);
  runtime::Engine& e = m.session->engine();
  std::vector<runtime::RuleSource> src = runtime::ruleSources(e.model());
  auto lineOf = [&](runtime::Engine::Origin o) {
    return o.rule == runtime::Engine::Origin::kAxiom ? 0 : o.rule < 0 ? -1 : src[size_t(o.rule)].line;
  };
  auto history = [&] {
    std::vector<std::pair<int, int>> h;  // (line, step) per module; line 0: the axiom, -1 unknown
    for (size_t i = 0; i < e.moduleCount(); ++i) h.emplace_back(lineOf(e.originOf(i)), e.originOf(i).step);
    return h;
  };
  e.setProvenance(true);
  e.breakOn(int(std::find_if(src.begin(), src.end(), [](auto& r) { return r.line == 10; }) - src.begin()));
  runtime::EngineHooks hooks;
  e.begin(hooks);
  EXPECT_EQ(history(), (std::vector<std::pair<int, int>>{{0, 0}, {0, 0}}));
  ASSERT_TRUE(e.step());
  EXPECT_FALSE(e.takeBreak());  // no B yet
  EXPECT_EQ(history(), (std::vector<std::pair<int, int>>{{9, 1}, {9, 1}, {0, 0}}));
  e.step();
  EXPECT_TRUE(e.takeBreak());
  EXPECT_FALSE(e.takeBreak());
  EXPECT_EQ(e.text(e.string()), "A(2)\nB\nD\nD\nC\n");
  EXPECT_EQ(history(), (std::vector<std::pair<int, int>>{{9, 2}, {9, 2}, {12, 2}, {12, 2}, {0, 0}}));
  // An insertion (MouseIns) comes from no rule; the others keep theirs.
  size_t offsetOfC = 0;
  for (int k = 0; k < 4; ++k) offsetOfC = e.modules().next(e.string().data(), offsetOfC);
  __lc_R_MouseIns r;
  std::memset(&r, 0, sizeof r);
  r.id = r.id2 = __lc_id_MouseIns;
  ASSERT_TRUE(e.insertBefore(offsetOfC, reinterpret_cast<const char*>(&r)));
  EXPECT_EQ(history(), (std::vector<std::pair<int, int>>{{9, 2}, {9, 2}, {12, 2}, {12, 2}, {-1, 0}, {0, 0}}));
  e.setProvenance(false);
  EXPECT_EQ(e.originOf(0).rule, runtime::Engine::Origin::kUnknown);
}

TEST(EngineProvenance, EachModuleNamesTheRuleAndStepThatMadeIt) { checkOrigins("origins", ""); }
// The same history derived right to left (Backward(), as vlab's Lychnis does every step).
TEST(EngineProvenance, BackwardStepsKeepTheOriginsToo) { checkOrigins("backorigins", "StartEach: { Backward(); }\n"); }

// tunable(NAME, value, min, max): the code's value (clamped) until the panel moves it; then the
// moved value from the next run on, with no recompile; the code's range and default follow edits.
TEST(Tunables, TheCodesValueUntilMovedThenTheMovedOne) {
  ScratchModel m("tunable", "#include <lpfgall.h>\nderivation length: 1;\nmodule A(float);\naxiom: A(0);\n"
                            "A(x) : { produce A(tunable(\"height\", 2, 0, 5)) A(tunable(\"wide\", 9, 0, 5)); }\n");
  ASSERT_TRUE(m.session);
  runtime::Tunables& t = m.session->windowInput().tunables;
  runtime::Engine& e = m.session->engine();
  ASSERT_FALSE(bool(e.run()));
  EXPECT_EQ(e.text(e.string()), "A(2)\nA(5)\n");  // 9 clamped to the range
  std::vector<runtime::Tunables::Entry> entries = t.entries();
  auto height = std::find_if(entries.begin(), entries.end(), [](auto& x) { return x.name == "height"; });
  ASSERT_NE(height, entries.end());
  EXPECT_EQ(height->value, 2.0f);
  EXPECT_EQ(height->max, 5.0f);
  EXPECT_FALSE(height->moved);
  t.move("height", 3.5f);
  ASSERT_FALSE(bool(e.run()));
  EXPECT_EQ(e.text(e.string()), "A(3.5)\nA(5)\n");
  t.reset();
  ASSERT_FALSE(bool(e.run()));
  EXPECT_EQ(e.text(e.string()), "A(2)\nA(5)\n");
}

// The window state model code reads (runtime/WindowInput.h) is its session's: in one process, a
// tunable moved, a menu item added and chosen, a pointer fed for one session are not another's.
// Each model adds "Grow" to its menu only when its .l file says so (the second's does not).
TEST(SessionWindowInput, TwoSessionsDoNotShareMenuTunablesOrMouse) {
  auto source = [](bool menu) {
    return std::string("#include <lpfgall.h>\nderivation length: 1;\nmodule A(float, int, int);\naxiom: A(0, 0, 0);\n") +
           (menu ? "Start: { UserMenuItem(\"Grow\", 7); }\n" : "") +
           "A(x, p, c) : { MouseStatus m = GetMouseStatus();\n"
           "  produce A(tunable(\"height\", 2, 0, 5), m.viewX, UserMenuChoice()); }\n";
  };
  ScratchModel one("windowone", source(true)), two("windowtwo", source(false));
  ASSERT_TRUE(one.session && two.session);
  runtime::Engine &a = one.session->engine(), &b = two.session->engine();
  ASSERT_FALSE(bool(a.run()));
  ASSERT_FALSE(bool(b.run()));
  EXPECT_EQ(a.text(a.string()), "A(2,0,-1)\n");
  EXPECT_EQ(b.text(b.string()), "A(2,0,-1)\n");
  // The first session's window moves the tunable, feeds the pointer and picks the menu item.
  runtime::WindowInput& first = one.session->windowInput();
  first.tunables.move("height", 3.5f);
  MouseStatus pointer;
  pointer.viewX = 120;
  first.mouse.update(pointer);
  ASSERT_EQ(first.menu.items(), (std::vector<std::pair<std::string, int>>{{"Grow", 7}}));
  first.menu.choose(7);
  ASSERT_FALSE(bool(a.run()));
  ASSERT_FALSE(bool(b.run()));
  EXPECT_EQ(a.text(a.string()), "A(3.5,120,7)\n");
  EXPECT_EQ(b.text(b.string()), "A(2,0,-1)\n");  // the second session saw none of it
  runtime::WindowInput& second = two.session->windowInput();
  EXPECT_TRUE(second.menu.items().empty());
  std::vector<runtime::Tunables::Entry> entries = second.tunables.entries();
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_FALSE(entries[0].moved);
}
