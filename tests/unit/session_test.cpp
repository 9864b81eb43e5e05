// Session reloads: each of lpfg's New … menu items re-reads exactly the files of the manual's
// §1.2.2 table. The test edits every input file after the first load, then checks which edits
// each reload picked up: the L-system (a different production), the view file (line style), the
// colormap (colour 1) and a function file (its value).
#include <gtest/gtest.h>

#include <filesystem>
#include <chrono>
#include <fstream>
#include <thread>

#include "Drawing.h"
#include "Engine.h"
#include "Session.h"

using namespace lcjit;
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
  fs::path dir = fs::temp_directory_path() / ("lcjit-cancel-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "long.l") << "#include <lpfgall.h>\nderivation length: 2;\nmodule A(int);\n"
                                   "axiom: A(0);\n"
                                   "A(n) : { if (n == 0) { for (int i = 0; i < 200000; ++i) nproduce A(1); produce; }\n"
                                   "  volatile double x = 0; for (int i = 0; i < 20000; ++i) x += i; produce A(n + 1); }\n";
  auto session = Session::create();
  ASSERT_TRUE(bool(session));
  ModelFiles files;
  files.lsystem = (dir / "long.l").string();
  PhaseTimes t;
  ASSERT_FALSE(bool((*session)->load(files, 1, t)));
  runtime::Engine& e = (*session)->engine();
  runtime::EngineHooks hooks;
  e.begin(hooks);
  ASSERT_TRUE(e.step());  // step 1: 200 000 × A(1), fast
  size_t before = e.moduleCount();
  std::thread stopper([&e] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    e.cancelStep();
  });
  auto t0 = std::chrono::steady_clock::now();
  bool more = e.step();  // step 2 would take seconds (200 000 × 20 000 additions)
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  stopper.join();
  EXPECT_FALSE(more);
  EXPECT_LT(seconds, 1.5);
  EXPECT_EQ(e.stepNo(), 1);
  EXPECT_EQ(e.moduleCount(), before);
  EXPECT_NE(e.text(e.string()).find("A(1)"), std::string::npos);
  EXPECT_EQ(e.text(e.string()).find("A(2)"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
