// Refresh modes (manual §1.1.1 -rmode), the §1.2.2 "New …" table, the §1.3 file-monitoring table,
// and the inotify watcher on real files.
#include <gtest/gtest.h>

#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "app/session/FileMonitor.h"
#include "app/session/Languages.h"
#include "frontend/cfdg/ReadDesign.h"
#include "frontend/lc/Rewriter.h"

using namespace lcjit;
using namespace lcjit::app;
namespace fs = std::filesystem;
using FK = FileKind;

// ---- -rmode, file kinds -------------------------------------------------------------------------

TEST(RefreshMode, Parse) {
  EXPECT_EQ(parseRefreshMode("expl"), RefreshMode::Explicit);
  EXPECT_EQ(parseRefreshMode("explicit"), RefreshMode::Explicit);
  EXPECT_EQ(parseRefreshMode("cont"), RefreshMode::Continuous);
  EXPECT_EQ(parseRefreshMode("continuous"), RefreshMode::Continuous);
  EXPECT_EQ(parseRefreshMode("trig"), RefreshMode::Triggered);
  EXPECT_EQ(parseRefreshMode("triggered"), RefreshMode::Triggered);
  EXPECT_EQ(parseRefreshMode("Cont"), std::nullopt);
  EXPECT_EQ(parseRefreshMode(""), std::nullopt);
}

TEST(FileKinds, ByExtension) {
  EXPECT_EQ(fileKindOf("dir/plant.l"), FK::Model);
  EXPECT_EQ(fileKindOf("view.v"), FK::View);
  EXPECT_EQ(fileKindOf("old.dr"), FK::View);
  EXPECT_EQ(fileKindOf("anim.a"), FK::Animation);
  EXPECT_EQ(fileKindOf("colors.map"), FK::Colormap);
  EXPECT_EQ(fileKindOf("m.mat"), FK::Material);
  EXPECT_EQ(fileKindOf("leaf.s"), FK::Surface);
  EXPECT_EQ(fileKindOf("bark.rgb"), FK::Texture);
  EXPECT_EQ(fileKindOf("bark.png"), FK::Texture);
  EXPECT_EQ(fileKindOf("bark.jpg"), FK::Texture);
  EXPECT_EQ(fileKindOf("f.func"), FK::Function);
  EXPECT_EQ(fileKindOf("f.fset"), FK::Function);
  EXPECT_EQ(fileKindOf("t.tset"), FK::Timeline);
  EXPECT_EQ(fileKindOf("c.con"), FK::Contour);
  EXPECT_EQ(fileKindOf("c.cset"), FK::Contour);
  EXPECT_EQ(fileKindOf("p.vset"), FK::Parameters);
  EXPECT_EQ(fileKindOf("env.e"), FK::Environment);
  EXPECT_EQ(fileKindOf("notes.txt"), FK::Other);
  EXPECT_EQ(fileKindOf("a.dir/noext"), FK::Other);
  EXPECT_EQ(fileKindOf(".l"), FK::Other);  // a hidden file, not an extension
  EXPECT_EQ(fileKindOf("plant.L"), FK::Other);
}

// The languages' table (Languages.h) says which files are models, in which language, on which
// engine; the input files' table takes its model rows from it, and no extension is read two ways.
TEST(Languages, ByExtension) {
  const Language* lc = languageOf("dir/plant.l");
  ASSERT_NE(lc, nullptr);
  EXPECT_EQ(lc->name, "L+C");
  EXPECT_EQ(lc->model, "L-system");
  EXPECT_EQ(lc->engine, EngineKind::LSystem);
  EXPECT_EQ(languageOf("view.v"), nullptr);
  EXPECT_EQ(languageOf(".l"), nullptr);  // a hidden file
  EXPECT_EQ(languageOf("plant.L"), nullptr);
  EXPECT_EQ(modelExtensions(*lc), ".l");
  EXPECT_EQ(noModelGiven(),
            "no L-system file (.l) or Context Free design file (.cfdg) or XL model file (.rgg or .xl) given");
  size_t modelRows = 0;
  for (const Language& language : languages())
    for (std::string_view ext : language.extensions) {
      const std::string path = "m." + std::string(ext);
      EXPECT_EQ(languageOf(path), &language) << ext;
      EXPECT_EQ(fileKindOf(path), FK::Model) << ext;
      ++modelRows;
    }
  std::set<std::string_view> seen;
  size_t models = 0;
  for (const auto& row : inputExtensions()) {
    EXPECT_TRUE(seen.insert(row.extension).second) << "." << row.extension << " is in two rows";
    models += row.kind == FK::Model;
  }
  EXPECT_EQ(models, modelRows);
}

// Each row names the front end its engine calls, and only that one (Languages.h): the L-system
// engine's session rewrites with `rewrite`, the shape-expansion engine's runs read with
// `readDesign`. CFDG's reads a design into the unit the Expander runs, with its imports.
TEST(Languages, FrontEndOfItsEngine) {
  for (const Language& language : languages()) {
    EXPECT_EQ(language.rewrite != nullptr, language.engine == EngineKind::LSystem) << language.name;
    EXPECT_EQ(language.readDesign != nullptr, language.engine == EngineKind::ShapeExpansion) << language.name;
  }
  const Language* cfdg = languageNamed("CFDG");
  ASSERT_NE(cfdg, nullptr);
  EXPECT_EQ(languageOf("garden.cfdg"), cfdg);
  auto unit = cfdg->readDesign("startshape A\nshape A { SQUARE [] }\n", "garden.cfdg", {});
  ASSERT_TRUE(bool(unit)) << llvm::toString(unit.takeError());
  EXPECT_NE(unit->translation.cpp.find("__cf_design"), std::string::npos);
  EXPECT_TRUE(unit->imports.empty());
  auto bad = cfdg->readDesign("startshape A\nshape A { SQUARE [x oops] }\n", "garden.cfdg", {});
  ASSERT_FALSE(bool(bad));
  EXPECT_NE(llvm::toString(bad.takeError()).find("garden.cfdg:2:"), std::string::npos);
  EXPECT_EQ(languageNamed("Logo"), nullptr);
  // XL's runs on the L-system engine: its text becomes the L+C the L+C rewriter takes, and its
  // errors name the .rgg.
  const Language* xl = languageNamed("XL");
  ASSERT_NE(xl, nullptr);
  EXPECT_EQ(languageOf("tree.rgg"), xl);
  EXPECT_EQ(languageOf("tree.xl"), xl);
  auto model = xl->rewrite("module X;\nprotected void init() [ Axiom ==> X; ]\npublic void run() [ X ==> F(1) [RU(30) X]; ]\n",
                           "tree.rgg", "");
  ASSERT_TRUE(bool(model)) << llvm::toString(model.takeError());
  ASSERT_EQ(model->userModules.size(), 2u);  // X, and GroIMP's RU
  EXPECT_EQ(model->userModules[0].name, "X");
  EXPECT_EQ(model->ruleCount, 2);  // X's production, RU's interpretation rule
  auto wrong = xl->rewrite("module X;\nprotected void init() [ Axiom ==> X Y; ]\n", "tree.rgg", "");
  ASSERT_FALSE(bool(wrong));
  EXPECT_NE(llvm::toString(wrong.takeError()).find("tree.rgg:2:37: error: no module 'Y'"), std::string::npos);
}

// A design's constant numbers are its variables (the window's Parameters panel): the value as
// Context Free reads it (a trailing % divides by 100, a sign before the number counts), the line
// it is written on; a computed value, a vector or a function is not one.
TEST(Languages, DesignVariablesAsContextFreeReadsThem) {
  const Language* cfdg = languageNamed("CFDG");
  ASSERT_NE(cfdg, nullptr);
  auto unit = cfdg->readDesign("startshape A\nshare = 50%\nturn = -12.5\ntwice = 2 * share\npair = (1, 2)\n"
                               "shape A { SQUARE [s share r turn] }\n",
                               "garden.cfdg", {});
  ASSERT_TRUE(bool(unit)) << llvm::toString(unit.takeError());
  ASSERT_EQ(unit->variables.size(), 2u);
  EXPECT_EQ(unit->variables[0].name, "share");
  EXPECT_EQ(unit->variables[0].value, 0.5);
  EXPECT_EQ(unit->variables[0].line, 2);
  EXPECT_EQ(unit->variables[1].name, "turn");
  EXPECT_EQ(unit->variables[1].value, -12.5);
  EXPECT_EQ(unit->variables[1].line, 3);
}

// The same table says which files name others (a set) and which the command line takes: lpfg's
// command line takes a .fset or .cset as a set, and no texture (the view file names those).
TEST(FileKinds, SetsAndTheCommandLine) {
  EXPECT_TRUE(inputExtensionOf("f.fset")->set);
  EXPECT_TRUE(inputExtensionOf("c.cset")->set);
  EXPECT_FALSE(inputExtensionOf("f.func")->set);
  EXPECT_TRUE(inputExtensionOf("leaf.s")->commandLine);
  EXPECT_FALSE(inputExtensionOf("bark.png")->commandLine);
  EXPECT_EQ(inputExtensionOf("notes.txt"), nullptr);
  const std::string list = commandLineExtensions();
  EXPECT_EQ(list.rfind(".l, .cfdg, .rgg, .xl, .a, .v, ", 0), 0u) << list;  // every language's model files first
  EXPECT_NE(list.find(", .fset, .tset or .vset"), std::string::npos) << list;
  EXPECT_EQ(list.find(".png"), std::string::npos) << list;
}

// ---- §1.3: file changed → action (one assertion per row, for each monitoring mode) --------------

class ChangeTable : public ::testing::TestWithParam<RefreshMode> {};

TEST_P(ChangeTable, Rows) {
  RefreshMode m = GetParam();
  EXPECT_EQ(actionForChange(FK::Model, m), Action::NewLsystem);      // L-system → New L-system
  EXPECT_EQ(actionForChange(FK::View, m), Action::NewView);            // View → New view
  EXPECT_EQ(actionForChange(FK::Animation, m), Action::NewAnimate);    // Animate → rereads file only
  EXPECT_EQ(actionForChange(FK::Colormap, m), Action::NewRendering);   // Colormap → New rendering
  EXPECT_EQ(actionForChange(FK::Material, m), Action::NewRendering);   // Material → New rendering
  EXPECT_EQ(actionForChange(FK::Surface, m), Action::NewRendering);    // Surface → New rendering
  EXPECT_EQ(actionForChange(FK::Texture, m), Action::NewRendering);    // Texture → New rendering
  EXPECT_EQ(actionForChange(FK::Function, m), Action::NewRun);         // Function → New run
  EXPECT_EQ(actionForChange(FK::Contour, m), Action::NewRun);          // Contour → New run
  EXPECT_EQ(actionForChange(FK::Timeline, m), Action::NewRun);         // Timeline → New run
  EXPECT_EQ(actionForChange(FK::Parameters, m), Action::NewRun);       // Parameters → New run
  EXPECT_EQ(actionForChange(FK::Environment, m), Action::NewLsystem);  // lcjit: restarts the program
  EXPECT_EQ(actionForChange(FK::Other, m), Action::None);
}
INSTANTIATE_TEST_SUITE_P(Monitoring, ChangeTable,
                         ::testing::Values(RefreshMode::Continuous, RefreshMode::Triggered));

TEST(ChangeTable, ExplicitRereadsNothing) {
  for (FK k : {FK::Model, FK::View, FK::Animation, FK::Colormap, FK::Material, FK::Surface, FK::Texture,
               FK::Function, FK::Contour, FK::Timeline, FK::Parameters, FK::Environment, FK::Other})
    EXPECT_EQ(actionForChange(k, RefreshMode::Explicit), Action::None) << toString(k);
}

// ---- §1.2.2 summary table (one assertion per row) ------------------------------------------------

namespace {
const std::set<FK> kColours = {FK::Colormap, FK::Material, FK::Surface, FK::Texture};
const std::set<FK> kData = {FK::Function, FK::Contour, FK::Timeline, FK::Parameters};
std::set<FK> unite(std::initializer_list<std::set<FK>> parts) {
  std::set<FK> out;
  for (const auto& p : parts) out.insert(p.begin(), p.end());
  return out;
}
}  // namespace

TEST(MenuTable, FilesReadBy) {
  // New model: L-system, view, colours/surfaces/textures, functions/contours/timeline/parameters
  // (+ the animation and environment files: "re-read all input files").
  EXPECT_EQ(filesReadBy(Action::NewModel),
            unite({{FK::Model, FK::View, FK::Animation, FK::Environment}, kColours, kData}));
  // New L-system: all but the view and animation files (and, in lcjit, the .e file: the
  // environmental program restarts with it).
  EXPECT_EQ(filesReadBy(Action::NewLsystem), unite({{FK::Model, FK::Environment}, kColours, kData}));
  // New run: colours… and functions…, not the L-system, view or animation files.
  EXPECT_EQ(filesReadBy(Action::NewRun), unite({kColours, kData}));
  // New view: view + colours/surfaces/textures.
  EXPECT_EQ(filesReadBy(Action::NewView), unite({{FK::View}, kColours}));
  // New rendering: the same files as New view.
  EXPECT_EQ(filesReadBy(Action::NewRendering), unite({{FK::View}, kColours}));
  // New animate (§1.2.3): the animation file.
  EXPECT_EQ(filesReadBy(Action::NewAnimate), std::set<FK>{FK::Animation});
  EXPECT_TRUE(filesReadBy(Action::None).empty());
}

TEST(MenuTable, ResetColumns) {
  // Reset view: New model, New view.      Reset rendering: New model, New view, New rendering.
  // Re-run: New model, New L-system, New run.
  struct Row { Action a; bool view, rendering, rerun; };
  for (Row r : {Row{Action::NewModel, true, true, true}, Row{Action::NewLsystem, false, false, true},
                Row{Action::NewRun, false, false, true}, Row{Action::NewView, true, true, false},
                Row{Action::NewRendering, false, true, false}, Row{Action::NewAnimate, false, false, false}}) {
    EXPECT_EQ(resetsView(r.a), r.view) << toString(r.a);
    EXPECT_EQ(resetsRendering(r.a), r.rendering) << toString(r.a);
    EXPECT_EQ(rerunsSimulation(r.a), r.rerun) << toString(r.a);
  }
}

TEST(MenuTable, ActionsForABatch) {
  using V = std::vector<Action>;
  auto m = RefreshMode::Continuous;
  EXPECT_EQ(actionsForChanges({"a.l", "b.func", "c.map"}, m), (V{Action::NewLsystem}));
  EXPECT_EQ(actionsForChanges({"a.l", "v.v"}, m), (V{Action::NewLsystem, Action::NewView}));
  EXPECT_EQ(actionsForChanges({"b.func", "v.v", "c.map"}, m), (V{Action::NewRun, Action::NewView}));
  EXPECT_EQ(actionsForChanges({"c.map", "t.png"}, m), (V{Action::NewRendering}));
  EXPECT_EQ(actionsForChanges({"c.map", "v.v"}, m), (V{Action::NewView}));
  EXPECT_EQ(actionsForChanges({"c.map", "p.vset"}, m), (V{Action::NewRun}));
  EXPECT_EQ(actionsForChanges({"x.a", "a.l"}, m), (V{Action::NewAnimate, Action::NewLsystem}));
  EXPECT_EQ(actionsForChanges({"env.e", "notes.txt"}, m), V{Action::NewLsystem});
  EXPECT_EQ(actionsForChanges({"notes.txt"}, m), V{});
  EXPECT_EQ(actionsForChanges({"a.l"}, RefreshMode::Explicit), V{});
}

// ---- the watcher ---------------------------------------------------------------------------------

namespace {

class Watcher : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    std::string tmpl = (fs::temp_directory_path() / "lcjit_refresh_XXXXXX").string();
    ASSERT_NE(::mkdtemp(tmpl.data()), nullptr);
    dir = tmpl;
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  void write(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::trunc) << text;
  }
  std::string path(const char* name) { return (dir / name).string(); }
};

}  // namespace

TEST_F(Watcher, WriteIsSeen) {
  write(dir / "plant.l", "a");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("plant.l"), path("view.v")})) << mon.error();
  EXPECT_TRUE(mon.poll(0).empty());
  write(dir / "plant.l", "b");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("plant.l")});
  EXPECT_TRUE(mon.poll(200).empty());  // reported once
}

// A save that closed the file does not wait for the quiet period (100 ms here: a reload would
// otherwise always come that late); a file still open for writing does.
TEST_F(Watcher, FinishedSaveIsReportedWithoutTheQuietPeriod) {
  write(dir / "plant.l", "a");
  FileMonitor mon(std::chrono::milliseconds(2000));
  ASSERT_TRUE(mon.watch({path("plant.l")}));
  {
    std::ofstream open(dir / "plant.l", std::ios::trunc);
    open << "b" << std::flush;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_TRUE(mon.poll(0).empty());  // being written: within the 2 s quiet period
  }
  // Closed: a finished save, reported long before the 2 s quiet period would end.
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(mon.poll(1500), std::vector<std::string>{path("plant.l")});
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(1500));
}

TEST_F(Watcher, RenameOverIsSeen) {
  write(dir / "view.v", "scale: 1\n");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("view.v")}));
  write(dir / ".view.v.swp", "scale: 2\n");
  fs::rename(dir / ".view.v.swp", dir / "view.v");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("view.v")});
  // Watching survives the inode change: a second rename-over is seen too.
  write(dir / "view.v.tmp", "scale: 3\n");
  fs::rename(dir / "view.v.tmp", dir / "view.v");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("view.v")});
}

TEST_F(Watcher, FileCreatedLaterIsSeen) {
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("anim.a")}));
  write(dir / "anim.a", "step: 2\n");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("anim.a")});
}

TEST_F(Watcher, BurstIsOneChange) {
  write(dir / "f.func", "0");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("f.func")}));
  for (int i = 0; i < 5; ++i) write(dir / "f.func", std::to_string(i));
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("f.func")});
  EXPECT_TRUE(mon.poll(300).empty());
}

// A poll(0) that waited would return the change once its 1 s quiet period ended, not nothing.
TEST_F(Watcher, NonBlockingPollKeepsPendingChange) {
  write(dir / "c.map", "x");
  FileMonitor mon(std::chrono::milliseconds(1000));
  ASSERT_TRUE(mon.watch({path("c.map")}));
  std::ofstream open(dir / "c.map", std::ios::trunc);
  open << "y" << std::flush;  // still open: waits for the quiet period
  EXPECT_TRUE(mon.poll(0).empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_EQ(mon.poll(0), std::vector<std::string>{path("c.map")});
}

TEST_F(Watcher, UnrelatedFileNotReported) {
  write(dir / "plant.l", "a");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("plant.l")}));
  write(dir / "notes.txt", "hello");
  write(dir / "plant.l.tmp", "x");
  write(dir / "lsys.ii", "x");
  fs::create_directory(dir / "sub");
  EXPECT_TRUE(mon.poll(400).empty());
}

TEST_F(Watcher, SeveralFilesEachOnceInWatchOrder) {
  write(dir / "a.l", "1");
  write(dir / "b.v", "1");
  fs::create_directory(dir / "sub");
  write(dir / "sub" / "c.map", "1");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("a.l"), path("b.v"), (dir / "sub" / "c.map").string()}));
  write(dir / "sub" / "c.map", "2");
  write(dir / "a.l", "2");
  write(dir / "a.l", "3");
  auto changed = mon.poll(3000);
  EXPECT_EQ(changed, (std::vector<std::string>{path("a.l"), (dir / "sub" / "c.map").string()}));
}

TEST_F(Watcher, MissingDirectoryIsAnErrorOthersStillWatched) {
  write(dir / "a.l", "1");
  FileMonitor mon;
  EXPECT_FALSE(mon.watch({(dir / "nodir" / "x.v").string(), path("a.l")}));
  EXPECT_FALSE(mon.error().empty());
  write(dir / "a.l", "2");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("a.l")});
}

// After a reload the watched set is replaced (the view file may name new surfaces): a save that
// came just before must still be reported.
TEST_F(Watcher, RewatchKeepsChangesNotYetReported) {
  write(dir / "a.l", "1");
  write(dir / "b.s", "1");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("a.l")}));
  write(dir / "a.l", "2");
  ASSERT_TRUE(mon.watch({path("a.l"), path("b.s")}));
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("a.l")});
  write(dir / "b.s", "2");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("b.s")});
}

TEST_F(Watcher, RewatchAndClear) {
  write(dir / "a.l", "1");
  write(dir / "b.l", "1");
  FileMonitor mon;
  ASSERT_TRUE(mon.watch({path("a.l")}));
  ASSERT_TRUE(mon.watch({path("b.l")}));
  write(dir / "a.l", "2");
  EXPECT_TRUE(mon.poll(300).empty());
  write(dir / "b.l", "2");
  EXPECT_EQ(mon.poll(3000), std::vector<std::string>{path("b.l")});
  mon.clear();
  write(dir / "b.l", "3");
  EXPECT_TRUE(mon.poll(100).empty());
  EXPECT_TRUE(mon.poll(-1).empty());  // nothing watched: returns at once
}
