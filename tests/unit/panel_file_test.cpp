// vlab panel files and awkped's edits (runtime/files/PanelFile.h), against the vlab tools
// manual's §2.4 (panel specification) and §11.2 (awkped's message formats).
#include "runtime/files/PanelFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace lcjit::runtime {
namespace {

std::string ok(llvm::Expected<std::string> e) {
  if (!e) {
    ADD_FAILURE() << llvm::toString(e.takeError());
    return "";
  }
  return *e;
}

TEST(Awkped, DefineMessageScalesTheSlidersValue) {
  // §11.2.1: "d SIZE 46 10" sets SIZE to 46/10; the panel's %d is the slider's value.
  auto e = awkpedEdit("d SIZE %d 10", 46);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->kind, AwkpedEdit::Kind::Define);
  EXPECT_EQ(e->name, "SIZE");
  EXPECT_DOUBLE_EQ(e->value, 4.6);
  // Without a scale the value is written as it is.
  auto whole = awkpedEdit("d STEPS %d", 7);
  ASSERT_TRUE(whole);
  EXPECT_DOUBLE_EQ(whole->value, 7);
  EXPECT_FALSE(awkpedEdit("x SIZE %d 10", 1));
  EXPECT_FALSE(awkpedEdit("d SIZE %d 0", 1));  // a zero scale makes no number
}

TEST(Awkped, DefineEditChangesOnlyTheValue) {
  const std::string text = "#define LEFT 1\n#define  c\t0.5   // tile\nStart: {}\n#define c 0.5\n";
  auto e = awkpedEdit("d c %d 100", 25);
  ASSERT_TRUE(e);
  // Every `#define c` line changes (awkped's awk program edits each), blanks and comments stay.
  EXPECT_EQ(ok(applyAwkped(text, *e, "m.l")), "#define LEFT 1\n#define  c\t0.25   // tile\nStart: {}\n#define c 0.25\n");
  auto whole = awkpedEdit("d LEFT %d 1", 0);
  EXPECT_EQ(ok(applyAwkped(text, *whole, "m.l")).substr(0, 15), "#define LEFT 0\n");
  // A name that is only a prefix of another does not match.
  auto none = applyAwkped("#define cc 3\n", *e, "m.l");
  ASSERT_FALSE(none);
  EXPECT_NE(llvm::toString(none.takeError()).find("m.l: error: a panel sets '#define c'"), std::string::npos);
}

TEST(Awkped, LineWordEditUsesTheExponent) {
  // §11.2.1's example: "n 2 2 -1 48" makes line 2's second word 48×10^-1 = 4.8.
  const std::string text = "initial line width: 7 pixels\nsize: 4.2\n";
  auto e = awkpedEdit("n 2 2 -1 %d", 48);
  ASSERT_TRUE(e);
  EXPECT_EQ(ok(applyAwkped(text, *e, "v.v")), "initial line width: 7 pixels\nsize: 4.8\n");
  auto width = awkpedEdit("n 1 4 0 %d", 5);
  EXPECT_EQ(ok(applyAwkped(text, *width, "v.v")), "initial line width: 5 pixels\nsize: 4.2\n");
  auto past = awkpedEdit("n 9 1 0 %d", 5);
  auto err = applyAwkped(text, *past, "v.v");
  ASSERT_FALSE(err);
  EXPECT_NE(llvm::toString(err.takeError()).find("past the file's end"), std::string::npos);
}

TEST(Awkped, NumbersAsAwkPrintsThem) {
  EXPECT_EQ(awkNumber(5), "5");
  EXPECT_EQ(awkNumber(0.5), "0.5");
  EXPECT_EQ(awkNumber(1.0 / 3), "0.333333");
  EXPECT_EQ(awkNumber(-0.0), "0");
  EXPECT_EQ(definedValue("#define A 1\n#define B x\n#define A 2.5\n", "A"), 2.5);
  EXPECT_FALSE(definedValue("#define B x\n", "B"));
}

TEST(PanelFile, ReadsSlidersButtonsAndGroups) {
  const std::string text =
      "target: Lsystem\npanel name: Growth\nbackground: 0,0,0\nsize: 178 294\n\n"
      "type: SLIDER\nname: Steps\ncolors: 255,255,255 255,0,0\norigin: 16 27\nmin/max: 0 10\nvalue: 3\n"
      "message: d STEPS %d 1\n\n"
      "type: BUTTON\nname: On\ntricolor: 1,1,1 0,0,255 0,0,0\norigin: 1 2\nvalue: 1\nmessage: d GRID 1 1\n\n"
      "type: BUTTON\nname: Off\ntricolor: 1,1,1 0,0,255 0,0,0\norigin: 1 3\nvalue: 0\nmessage: d GRID 0 1\n\n"
      "type: GROUP\ncolor: 255,255,255\nOn\nOff\nENDGROUP\n\n"
      "type: LABEL\nname: Grid\ncolor: 1,1,1\norigin: 5 5\n";
  auto p = parsePanel(text, "panel.l");
  ASSERT_TRUE(bool(p)) << llvm::toString(p.takeError());
  EXPECT_EQ(p->name, "Growth");
  ASSERT_EQ(p->items.size(), 4u);
  EXPECT_EQ(p->items[0].kind, PanelItem::Kind::Slider);
  EXPECT_EQ(p->items[0].name, "Steps");
  EXPECT_EQ(p->items[0].min, 0);
  EXPECT_EQ(p->items[0].max, 10);
  EXPECT_EQ(p->items[0].value, 3);
  EXPECT_EQ(p->items[0].message, "d STEPS %d 1");
  EXPECT_EQ(p->items[1].kind, PanelItem::Kind::Button);
  EXPECT_EQ(p->items[1].group, 0);
  EXPECT_EQ(p->items[2].group, 0);
  EXPECT_EQ(p->items[2].value, 0);
  EXPECT_EQ(p->items[3].kind, PanelItem::Kind::Label);
  auto bad = parsePanel("panel name: x\ntype: SLIDER\nmin/max: 3\n", "p.pnl");
  ASSERT_FALSE(bad);
  EXPECT_NE(llvm::toString(bad.takeError()).find("p.pnl:3: error: 'min/max:' needs two numbers"), std::string::npos);
}

TEST(PanelFile, LStudioHeaderNamesItsTarget) {
  auto p = parsePanel("pver 1 1\nname: simple\nassociate: File parameters.inc\ntrigger: newlsystem\nitems: 1\n"
                      "type: SLIDER\nname: DELAY\nmin/max: 0 20\nvalue: 5\nmessage: d DELAY %d 1\n",
                      "simple.pnl");
  ASSERT_TRUE(bool(p)) << llvm::toString(p.takeError());
  EXPECT_EQ(p->name, "simple");
  EXPECT_EQ(p->target, "parameters.inc");
  EXPECT_EQ(p->trigger, "newlsystem");
  ASSERT_EQ(p->items.size(), 1u);
  EXPECT_EQ(p->items[0].max, 20);
}

TEST(PanelFile, FoundThroughSpecificationsAndPnlFiles) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("lcjit-panels-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  auto write = [&](const char* name, const std::string& text) { std::ofstream(dir / name) << text; };
  write("specifications", "fractal.l\npanel.l\nL-system:\n\tpanel:\n\t\tdisplay:\n\t\t\tpanel panel.l | awkped fractal.l\n"
                          "\tpanel:\n\t\tdisplay:\n\t\t\tpanel -rmode cont missing.l | awkped fractal.l\n");
  write("panel.l", "panel name: L\n");
  write("b.pnl", "name: b\nassociate: File params.inc\n");
  write("c.pnl", "name: c\n");  // no target: not a panel lcjit can apply
  std::vector<PanelAndTarget> found = findPanels(dir.string());
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].panel, (dir / "b.pnl").string());
  EXPECT_EQ(found[0].target, (dir / "params.inc").string());
  EXPECT_EQ(found[1].panel, (dir / "panel.l").string());
  EXPECT_EQ(found[1].target, (dir / "fractal.l").string());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lcjit::runtime
