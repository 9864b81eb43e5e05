// The window's file editors (app/window/Editors) with a Session, as the window's mode wires them: a
// function point moved in its panel re-runs the model with the new function before anything is
// saved, Save writes the file, Revert reads it back; a colour changed in the colormap panel is
// redrawn without a re-run; a model without a colour file gets a colormap panel of the colours it
// is drawn with.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/window/Editors.h"
#include "app/session/Session.h"
#include "runtime/Engine.h"
#include "runtime/Functions.h"
#include "runtime/turtle/Drawing.h"

using namespace lcjit;
using namespace lcjit::app;
namespace fs = std::filesystem;

namespace {

const char* kFunc = "fver 1 1\nname: len\nsamples: 10\nflip: off\npoints: 4\n"
                    "0.000000 1.000000 1\n0.333333 1.000000 1\n0.666667 1.000000 1\n1.000000 1.000000 1\n";

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class EditorsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("lcjit-editors-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // One segment of length len(0.5); its colour index 1.
    std::ofstream(dir / "m.l") << "#include <lpfgall.h>\nderivation length: 1;\nmodule A;\naxiom: A;\n"
                                  "A : { produce SetColor(1) F(func(len, 0.5)); }\n";
    std::ofstream(dir / "len.func", std::ios::binary) << kFunc;
    files.lsystem = (dir / "m.l").string();
    files.functions = {(dir / "len.func").string()};
    auto s = Session::create();
    ASSERT_TRUE(bool(s)) << llvm::toString(s.takeError());
    session = std::move(*s);
  }
  void TearDown() override { fs::remove_all(dir); }

  void load(const ModelFiles& f, ReloadParts what = ReloadParts::all()) {
    PhaseTimes t;
    auto e = session->load(f, 1, t, what);
    ASSERT_FALSE(bool(e)) << llvm::toString(std::move(e));
  }
  float length() {
    EXPECT_FALSE(bool(session->engine().run()));
    runtime::Geometry g;
    if (auto e = session->engine().interpret(g)) ADD_FAILURE() << llvm::toString(std::move(e));
    if (g.segments.size() != 1) {
      ADD_FAILURE() << g.segments.size() << " segments";
      return 0;
    }
    return (g.segments[0].to - g.segments[0].from).Length();
  }
  static viewer::Panel* panel(std::vector<viewer::Panel>& panels, const std::string& title) {
    for (viewer::Panel& p : panels)
      if (p.title == title) return &p;
    ADD_FAILURE() << "no panel " << title;
    return nullptr;
  }

  fs::path dir;
  ModelFiles files;
  std::unique_ptr<Session> session;
};

}  // namespace

TEST_F(EditorsTest, AMovedFunctionPointRerunsTheModelAndSaveWritesIt) {
  load(files);
  EXPECT_NEAR(length(), 1.0f, 1e-5);
  Editors editors(files, runtime::Palette::lcjitDefault());
  std::vector<viewer::Panel> panels = editors.panels();
  viewer::Panel* p = panel(panels, "Function len");
  ASSERT_NE(p, nullptr);
  ASSERT_EQ(p->controls.size(), 3u);  // the file, the curve, a line of help
  const viewer::PanelControl& curve = p->controls[1];
  ASSERT_EQ(curve.kind, viewer::PanelControl::Kind::Curve);
  EXPECT_TRUE(curve.function);
  ASSERT_EQ(curve.points.size(), 4u);
  ASSERT_FALSE(curve.curve.empty());
  EXPECT_NEAR(curve.curve[50][1], 1.0f, 1e-5);  // drawn as the model sees it
  EXPECT_EQ(editors.takeAction(), Action::None);
  // Every point up to y = 2.5, as drags in the window report them.
  for (size_t k = 0; k < 4; ++k) p->edited(1, k, {curve.points[k][0], 2.5f, 0, 0});
  EXPECT_EQ(editors.takeAction(), Action::NewRun);
  EXPECT_EQ(editors.takeAction(), Action::None);
  EXPECT_EQ(readText(dir / "len.func"), kFunc);  // nothing saved yet
  ModelFiles edited = editors.files(files);
  ASSERT_EQ(edited.functions.size(), 1u);
  EXPECT_NE(edited.functions[0], files.functions[0]);
  EXPECT_EQ(fs::path(edited.functions[0]).filename(), "len.func");  // the model sees its own names
  load(edited, ReloadParts::newRun());
  EXPECT_NEAR(length(), 2.5f, 1e-5);
  panels = editors.panels();
  p = panel(panels, "Function len");
  ASSERT_NE(p, nullptr);
  EXPECT_NEAR(p->controls[1].curve[50][1], 2.5f, 1e-5);
  EXPECT_EQ(p->status, "edited, not saved");
  // Save: the file holds the new points, in funcedit's format; the model reads the file again.
  p->pressed(0);
  EXPECT_EQ(readText(dir / "len.func"), "fver 1 1\nname: len\nsamples: 10\nflip: off\npoints: 4\n"
                                        "0.000000 2.500000 1\n0.333333 2.500000 1\n0.666667 2.500000 1\n1.000000 2.500000 1\n");
  EXPECT_EQ(editors.files(files).functions, files.functions);
  load(editors.files(files), ReloadParts::newRun());
  EXPECT_NEAR(length(), 2.5f, 1e-5);
  // Ctrl+click's new point re-runs too and is counted in the file; a removal back to 4 points
  // is allowed, below 4 not.
  panels = editors.panels();
  p = panel(panels, "Function len");
  p->added(1, 2, {0.5f, 5.0f});
  EXPECT_EQ(editors.takeAction(), Action::NewRun);
  load(editors.files(files), ReloadParts::newRun());
  EXPECT_GT(length(), 3.0f);
  panels = editors.panels();
  p = panel(panels, "Function len");
  EXPECT_EQ(p->controls[1].points.size(), 5u);
  p->pressed(0);
  EXPECT_NE(readText(dir / "len.func").find("points: 5\n"), std::string::npos);
  p->removed(1, 2);
  p->removed(1, 1);
  panels = editors.panels();
  p = panel(panels, "Function len");
  EXPECT_EQ(p->controls[1].points.size(), 4u);
  EXPECT_EQ(p->status, "a curve needs at least 4 points");
  p->pressed(0);
  // Revert after a change on disk reads the file again, and asks for a re-run.
  std::ofstream(dir / "len.func", std::ios::binary) << kFunc;
  panels = editors.panels();
  panel(panels, "Function len")->pressed(1);
  EXPECT_EQ(editors.takeAction(), Action::NewRun);
  panels = editors.panels();
  EXPECT_FLOAT_EQ(panel(panels, "Function len")->controls[1].points[1][1], 1.0f);
}

TEST_F(EditorsTest, AColourChangeRedrawsWithoutARerun) {
  std::string map(768, '\0');
  map[3] = char(10);  // colour 1: (10, 0, 0)
  std::ofstream(dir / "m.map", std::ios::binary) << map;
  files.colormap = (dir / "m.map").string();
  load(files);
  length();
  const int steps = session->engine().stepsDone();
  Editors editors(files, runtime::Palette::lcjitDefault());
  std::vector<viewer::Panel> panels = editors.panels();
  viewer::Panel* p = panel(panels, "Colormap");
  ASSERT_NE(p, nullptr);
  ASSERT_GE(p->controls.size(), 3u);
  EXPECT_EQ(p->controls[1].kind, viewer::PanelControl::Kind::Swatches);
  ASSERT_EQ(p->controls[1].colors.size(), 256u);
  EXPECT_FLOAT_EQ(p->controls[1].colors[1][0], 10 / 255.0f);
  p->changed(1, 1);  // select colour 1
  panels = editors.panels();
  p = panel(panels, "Colormap");
  EXPECT_EQ(p->controls[2].label, "Colour 1");
  p->edited(2, 0, {0, 1, 0, 1});
  EXPECT_EQ(editors.takeAction(), Action::NewRendering);
  load(editors.files(files), *reloadPartsFor(Action::NewRendering));
  EXPECT_EQ(session->engine().stepsDone(), steps);  // not re-run
  auto c = session->drawing().palette.color(1);
  EXPECT_FLOAT_EQ(c[0], 0);
  EXPECT_FLOAT_EQ(c[1], 1);
  EXPECT_EQ(readText(dir / "m.map"), map);  // until saved
  p->pressed(0);
  std::string saved = map;
  saved[3] = 0, saved[4] = char(255);
  EXPECT_EQ(readText(dir / "m.map"), saved);
}

TEST_F(EditorsTest, AModelWithoutAColourFileGetsAColormapPanel) {
  session->setLcjitColours(true);
  load(files);
  const runtime::Palette lcjit = runtime::Palette::lcjitDefault();
  EXPECT_EQ(session->drawing().palette.color(1), lcjit.color(1));
  EXPECT_NE(session->drawing().palette.color(1), runtime::Palette().color(1));  // not lpfg's white
  Editors editors(files, lcjit);
  std::vector<viewer::Panel> panels = editors.panels();
  viewer::Panel* p = panel(panels, "Colormap");
  ASSERT_NE(p, nullptr);
  EXPECT_NE(p->controls[0].label.find("no colour file"), std::string::npos);
  EXPECT_EQ(p->controls[1].colors[2], lcjit.color(2));
  p->changed(1, 2);
  panels = editors.panels();
  p = panel(panels, "Colormap");
  p->edited(2, 0, {1, 0, 1, 1});
  EXPECT_EQ(editors.takeAction(), Action::NewRendering);
  ModelFiles edited = editors.files(files);
  EXPECT_FALSE(edited.colormap.empty());
  load(edited, *reloadPartsFor(Action::NewRendering));
  EXPECT_EQ(session->drawing().palette.color(2), (std::array<float, 4>{1, 0, 1, 1}));
  EXPECT_EQ(session->drawing().palette.color(1), lcjit.color(1));  // the others as they were
  // Save writes m.map beside the model, with the edit.
  p->pressed(0);
  ASSERT_TRUE(fs::exists(dir / "m.map"));
  const std::string map = readText(dir / "m.map");
  ASSERT_EQ(map.size(), 768u);
  EXPECT_EQ(map.substr(6, 3), std::string("\xff\x00\xff", 3));
  panels = editors.panels();
  EXPECT_EQ(panel(panels, "Colormap")->status.rfind("saved m.map", 0), 0u);
}

TEST_F(EditorsTest, AMovedContourPointRerunsTheModel) {
  // An open contour from (0,0) to (2,0) in a gallery; the segment is as long as the curve's end's x.
  std::ofstream(dir / "m.l") << "#include <lpfgall.h>\nderivation length: 1;\nmodule A;\naxiom: A;\n"
                                "A : { produce F(curveX(edge, 1)); }\n";
  const std::string set = "contourgalleryver 1 1\nitems: 1\ncver 1 3\nname: edge\npoints: 4 8\ntype: or\nsamples: 8\n"
                          "0.000000 0.000000 0.000000 3\n0.500000 1.000000 0.000000 1\n"
                          "1.500000 1.000000 0.000000 1\n2.000000 0.000000 0.000000 3\n";
  std::ofstream(dir / "shapes.cset", std::ios::binary) << set;
  files.functions.clear();
  files.contours = {(dir / "shapes.cset").string()};
  load(files);
  EXPECT_NEAR(length(), 2.0f, 1e-4);
  Editors editors(files, runtime::Palette::lcjitDefault());
  std::vector<viewer::Panel> panels = editors.panels();
  viewer::Panel* p = panel(panels, "Contour edge");
  ASSERT_NE(p, nullptr);
  const viewer::PanelControl& curve = p->controls[1];
  EXPECT_FALSE(curve.function);
  EXPECT_FALSE(curve.closed);
  ASSERT_EQ(curve.points.size(), 4u);
  ASSERT_FALSE(curve.curve.empty());
  EXPECT_NEAR(curve.curve.back()[0], 2.0f, 1e-4);  // the contour as the model samples it
  p->edited(1, 3, {3, 0, 0, 0});  // the end point (multiplicity 3) moves to x = 3
  EXPECT_EQ(editors.takeAction(), Action::NewRun);
  load(editors.files(files), ReloadParts::newRun());
  EXPECT_NEAR(length(), 3.0f, 1e-4);
  EXPECT_EQ(readText(dir / "shapes.cset"), set);  // until saved
  p->pressed(0);
  std::string saved = set;
  saved.replace(saved.find("2.000000 0.000000 0.000000 3"), 28, "3.000000 0.000000 0.000000 3");
  EXPECT_EQ(readText(dir / "shapes.cset"), saved);
}
