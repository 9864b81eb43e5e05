// The window's Parameters panel (app/window/Parameters.h): .vset values changed in memory and saved back
// with only their values changed (manual §6.7), and vlab panels whose messages edit the model's
// files as awkped does (vlab tools manual §2.3, §11.2). Expected files are written out by hand.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/window/Parameters.h"
#include "app/session/Session.h"
#include "runtime/Functions.h"
#include "runtime/WindowInput.h"

using namespace lcjit;
using namespace lcjit::app;
namespace fs = std::filesystem;

namespace {

struct Folder {
  fs::path dir;
  ModelFiles files;
  runtime::FunctionStore functions;
  runtime::Tunables tunables;
  Folder() {
    dir = fs::temp_directory_path() / ("lcjit-parameters-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    files.lsystem = (dir / "m.l").string();
    files.parameters = (dir / "m.vset").string();
    write("m.l", "#define STEPS 3\n#define c 0.5\n#define GRID 1\nLsystem: 0\nAxiom: A\n");
    write("m.vset", "#define LENGTH 10\n#define ANGLE\t60\n");
  }
  ~Folder() { fs::remove_all(dir); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir / name, std::ios::binary) << text; }
  std::string read(const std::string& name) {
    std::ifstream in(dir / name, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  ParameterPanel load() {
    functions.clear();
    if (auto e = functions.loadParameters(files.parameters)) ADD_FAILURE() << llvm::toString(std::move(e));
    ParameterPanel p(tunables);
    p.load(files, functions);
    return p;
  }
};

size_t indexOf(const viewer::Panel& p, const std::string& label) {
  for (size_t i = 0; i < p.controls.size(); ++i)
    if (p.controls[i].label == label) return i;
  ADD_FAILURE() << "no control " << label;
  return 0;
}

TEST(ParameterPanel, VsetValuesChangeInMemoryAndSaveOnRequest) {
  Folder f;
  ParameterPanel params = f.load();
  viewer::Panel p = params.panel();
  EXPECT_EQ(p.title, "Parameters");
  ASSERT_EQ(p.controls.size(), 2u);
  size_t angle = indexOf(p, "ANGLE");
  EXPECT_EQ(p.controls[angle].value, 60.0f);
  EXPECT_EQ(p.controls[angle].min, p.controls[angle].max);  // no panel gives a range: a drag field
  ASSERT_EQ(p.buttons, std::vector<std::string>{"Save values"});
  p.changed(angle, 45.5f);
  auto values = params.takeParameters();
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values["ANGLE"], 45.5f);
  EXPECT_TRUE(params.takeParameters().empty());
  EXPECT_TRUE(params.takeChangedFiles().empty());  // nothing written before Save
  EXPECT_EQ(f.read("m.vset"), "#define LENGTH 10\n#define ANGLE\t60\n");
  // A reload reads the file again: the value moved in the panel stays and is set once more.
  params.load(f.files, f.functions);
  EXPECT_EQ(params.panel().controls[angle].value, 45.5f);
  EXPECT_EQ(params.takeParameters()["ANGLE"], 45.5f);
  p = params.panel();
  p.pressed(0);
  EXPECT_EQ(f.read("m.vset"), "#define LENGTH 10\n#define ANGLE\t45.5\n");
  EXPECT_NE(params.status().find("saved 2 values to"), std::string::npos) << params.status();
}

TEST(ParameterPanel, VlabPanelItemsEditTheirTargetAsAwkpedDoes) {
  Folder f;
  f.write("specifications", "m.l\npanel.l\nL-system:\n\tpanel:\n\t\tdisplay:\n\t\t\tpanel panel.l | awkped m.l\n");
  f.write("panel.l",
          "target: Lsystem\npanel name: L-system\n\n"
          "type: SLIDER\nname: Steps\nmin/max: 0 10\nvalue: 7\nmessage: d STEPS %d 1\n\n"
          "type: SLIDER\nname: Tile size\nmin/max: 0 101\nvalue: 50\nmessage: d c %d 100\n\n"
          "type: BUTTON\nname: Yes\nvalue: 1\nmessage: d GRID 1 1\n\n"
          "type: BUTTON\nname: No\nvalue: 0\nmessage: d GRID 0 1\n\n"
          "type: GROUP\ncolor: 255,255,255\nYes\nNo\nENDGROUP\n");
  ParameterPanel params = f.load();
  viewer::Panel p = params.panel();
  ASSERT_EQ(p.controls.size(), 6u);  // ANGLE, LENGTH, then the panel's four
  size_t steps = indexOf(p, "Steps"), tile = indexOf(p, "Tile size"), yes = indexOf(p, "Yes"), no = indexOf(p, "No");
  // The file's value, not the panel's `value:` (the file is what the model reads).
  EXPECT_EQ(p.controls[steps].value, 3.0f);
  EXPECT_EQ(p.controls[steps].max, 10.0f);
  EXPECT_EQ(p.controls[steps].step, 1.0f);
  EXPECT_FLOAT_EQ(p.controls[tile].value, 0.5f);
  EXPECT_FLOAT_EQ(p.controls[tile].max, 1.01f);
  EXPECT_FLOAT_EQ(p.controls[tile].step, 0.01f);
  EXPECT_EQ(p.controls[yes].kind, viewer::PanelControl::Kind::Toggle);
  EXPECT_EQ(p.controls[yes].value, 1.0f);
  EXPECT_EQ(p.controls[no].value, 0.0f);
  EXPECT_EQ(p.controls[yes].group, p.controls[no].group);
  EXPECT_GE(p.controls[yes].group, 0);
  p.changed(tile, 0.25f);
  EXPECT_EQ(f.read("m.l"), "#define STEPS 3\n#define c 0.25\n#define GRID 1\nLsystem: 0\nAxiom: A\n");
  p.changed(no, 1.0f);
  EXPECT_EQ(f.read("m.l"), "#define STEPS 3\n#define c 0.25\n#define GRID 0\nLsystem: 0\nAxiom: A\n");
  viewer::Panel now = params.panel();
  EXPECT_EQ(now.controls[yes].value, 0.0f);  // the group's other button went off
  EXPECT_EQ(now.controls[no].value, 1.0f);
  auto changed = params.takeChangedFiles();
  EXPECT_EQ(changed, std::vector<std::string>{f.files.lsystem});
  EXPECT_TRUE(params.takeParameters().empty());  // nothing for the .vset
}

TEST(ParameterPanel, APanelOnTheVsetGivesItsValuesARange) {
  Folder f;
  f.write("angle.pnl", "pver 1 1\nname: angles\nassociate: File m.vset\nitems: 1\n"
                       "type: SLIDER\nname: Branching\nmin/max: 0 900\nvalue: 600\nmessage: d ANGLE %d 10\n");
  ParameterPanel params = f.load();
  viewer::Panel p = params.panel();
  ASSERT_EQ(p.controls.size(), 2u);  // one control for ANGLE, not two
  size_t angle = indexOf(p, "Branching (ANGLE)");
  EXPECT_EQ(p.controls[angle].min, 0.0f);
  EXPECT_EQ(p.controls[angle].max, 90.0f);
  EXPECT_FLOAT_EQ(p.controls[angle].step, 0.1f);
  EXPECT_EQ(p.controls[angle].value, 60.0f);
  p.changed(angle, 30.0f);
  EXPECT_EQ(params.takeParameters()["ANGLE"], 30.0f);  // in memory, as any .vset value
  EXPECT_TRUE(params.takeChangedFiles().empty());
}

}  // namespace

namespace {

// A .tset with one timeline, GROWTH over 0..10, its function the line y = x.
const char* kTimelines =
    "timeEdit 1 2\nitems: 1\nstart: 0\nend: 10\nname: GROWTH\ncolor: 91,115,229\nstartLabel: \nendLabel: \n"
    "timelineFunceditFileStart:\nfver 1 1\nname: GROWTH\nsamples: 20\nflip: off\npoints: 4\n"
    "0.000000 0.000000\n0.333333 0.333333\n0.666667 0.666667\n1.000000 1.000000\ntimelineFunceditFileEnd:\n";

TEST(ParameterPanel, TimelinesRangesMoveTfuncAndSaveToTheTset) {
  Folder f;
  f.write("m.tset", kTimelines);
  f.files.timeline = (f.dir / "m.tset").string();
  f.functions.clear();
  ASSERT_FALSE(bool(f.functions.loadTimeline(f.files.timeline)));
  ASSERT_FALSE(bool(f.functions.loadParameters(f.files.parameters)));
  ParameterPanel params(f.tunables);
  params.load(f.files, f.functions);
  viewer::Panel p = params.panel();
  size_t start = indexOf(p, "GROWTH start"), end = indexOf(p, "GROWTH end");
  EXPECT_EQ(p.controls[start].value, 0.0f);
  EXPECT_EQ(p.controls[end].value, 10.0f);
  // tfunc maps the timeline's range onto the function's 0..1: 10 is its end, then its middle.
  EXPECT_NEAR(f.functions.tfunc("GROWTH", 10), 1.0f, 1e-3);  // tabulated, as lpfg does
  p.changed(end, 20.0f);
  auto timelines = params.takeTimelines();
  ASSERT_EQ(timelines.size(), 1u);
  EXPECT_EQ(timelines["GROWTH"], std::make_pair(0.0f, 20.0f));
  ASSERT_TRUE(f.functions.setTimeline("GROWTH", 0, 20));
  EXPECT_NEAR(f.functions.tfunc("GROWTH", 10), 0.5f, 1e-3);
  EXPECT_EQ(f.read("m.tset"), kTimelines);  // nothing written before Save
  p.pressed(0);
  std::string want = kTimelines;
  want.replace(want.find("end: 10"), 7, "end: 20");
  EXPECT_EQ(f.read("m.tset"), want);
  EXPECT_NE(params.status().find("m.tset"), std::string::npos) << params.status();
}

}  // namespace
