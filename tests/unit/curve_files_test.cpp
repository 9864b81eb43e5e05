// The editors' function and contour files (runtime/files/CurveFiles): a file written without a
// change is the file read, byte for byte, in every version vlab's editors wrote; a moved point is
// what the model's own readers then read.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/Functions.h"
#include "runtime/files/Contours.h"
#include "runtime/files/CurveFiles.h"

using namespace lcjit::runtime;

namespace {

std::string dir() {
  std::filesystem::path d = std::filesystem::path(::testing::TempDir()) / "lcjit_curve_files_test";
  std::filesystem::create_directories(d);
  return d.string();
}

std::string writeText(const std::string& name, const std::string& text) {
  std::string path = dir() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  return path;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string errorText(llvm::Error e) { return e ? llvm::toString(std::move(e)) : std::string(); }

// Files as funcedit, gallery and cuspy wrote them over the years (vlab tools manual §7.4, §8.4-8.5).
const char* kFunc = "fver 1 1\nname: grow\nsamples: 20\nflip: off\npoints: 4\n"
                    "0.000000 0.250000 1\n0.333333 0.500000 1\n0.666667 0.750000 2\n1.000000 1.000000 1\n";
const char* kOldColumns = "fver 1 1\nname: old\nsamples: 10\nflip: off\npoints: 4\n"
                          "0.000000 0.100000\n0.300000 0.200000\n0.700000 0.300000\n1.000000 0.400000\n";
const char* kRange = "range: 0.0 1.0\npoints: 4\n0.000000 0.0\n0.2 0.5\n0.8 0.5\n1 1\n";
const char* kBackground = "fver 1 1\nname: bg\nsamples: 10\nbackground: leaf.png\nbackgroundXY: 0.000000 0.000000\n"
                          "flip: on\npoints: 4\n0.000000 1.000000 1\n0.2 0.9 1\n0.8 0.1 1\n1.000000 0.000000 1\n";
const char* kSet = "funcgalleryver 1 1\nitems: 2\nfver 1 1\nname: A\nsamples: 10\nflip: off\npoints: 4\n"
                   "0.000000 0.000000 1\n0.300000 0.300000 1\n0.600000 0.600000 1\n1.000000 1.000000 1\n"
                   "fver 1 1\nname: B\nsamples: 10\nflip: off\npoints: 4\n"
                   "0.000000 1.000000\n0.300000 0.700000\n0.600000 0.400000\n1.000000 0.000000\n";
const char* kContour = "cver 1 3\nname: leaf\npoints: 4 8\ntype: or\nsamples: 8\n"
                       "-1.000000 0.000000 0.000000 3\n-0.500000 1.000000 0.000000 1\n"
                       "0.500000 1.000000 0.000000 1\n1.000000 0.000000 0.000000 3\n";
const char* kContourSet = "contourgalleryver 1 1\nitems: 2\n"
                          "cver 1 1\nname: square\npoints: 4 4\ntype: closed\n"
                          "1.000000 1.000000 0.000000 1\n1.000000 -1.000000 0.000000 1\n"
                          "-1.000000 -1.000000 0.000000 1\n-1.000000 1.000000 0.000000 1\n"
                          "cver 1 2\nname: open\npoints: 4 8\ntype: oe\n"
                          "0.000000 0.000000 0.000000 3\n0.300000 0.500000 0.000000 1\n"
                          "0.600000 0.500000 0.000000 1\n1.000000 0.000000 0.000000 3\n";
const char* kContour14 = "version: 1.4\ncontact: 0 0 0\nend: 0 0 0\nheading: 0 1 0\nup: 0 0 -1\nsize: 1\npoints: 4\n"
                         "range: 0.0 1.0\ndimension: 4\ntype: bspline\n"
                         "0.269398 -0.447751 0 3\n0.274471 -0.109864 0 1\n0.165305 0.175183 0 1\n-0.001478 0.202475 0 3\n";
const char* kContour10 = "4 2 closed\n1.0 0.0\n0.0 1.0\n-1.0 0.0\n0.0 -1.0\n";

}  // namespace

TEST(CurveFiles, UnchangedFilesComeBackByteForByte) {
  const std::pair<const char*, std::string> cases[] = {
      {"grow.func", kFunc},         {"old.func", kOldColumns},          {"range.func", kRange},
      {"bg.func", kBackground},     {"set.fset", kSet},                 {"leaf.con", kContour},
      {"set.cset", kContourSet},    {"v14.con", kContour14},            {"circle.con", kContour10},
      // Line ends and a missing last newline are the file's own, too.
      {"crlf.func", "fver 1 1\r\nname: crlf\r\nsamples: 10\r\nflip: off\r\npoints: 4\r\n0 0\r\n0.3 0.3\r\n0.6 0.6\r\n1 1\r\n"},
      {"nonl.func", std::string(kFunc).substr(0, std::string(kFunc).size() - 1)},
      {"blank.fset", std::string(kSet) + "\n"},
  };
  for (const auto& [name, text] : cases) {
    SCOPED_TRACE(name);
    std::string path = writeText(name, text);
    auto f = readCurveFile(path);
    ASSERT_TRUE(bool(f)) << llvm::toString(f.takeError());
    EXPECT_EQ(curveFileText(*f), text);
    // Moving every point to where it is changes nothing either.
    for (Curve& c : f->curves)
      for (size_t k = 0; k < c.points.size(); ++k) movePoint(c, k, c.points[k].x, c.points[k].y);
    std::string copy = dir() + "/copy-" + name;
    ASSERT_EQ(errorText(writeCurveFile(*f, copy)), "");
    EXPECT_EQ(readText(copy), text);
  }
}

TEST(CurveFiles, WhatTheyHold) {
  auto set = parseCurveFile(kSet, CurveFile::Kind::Function, "set.fset");
  ASSERT_TRUE(bool(set)) << llvm::toString(set.takeError());
  EXPECT_TRUE(set->set);
  ASSERT_EQ(set->curves.size(), 2u);
  EXPECT_EQ(set->curves[0].name, "A");
  EXPECT_EQ(set->curves[1].name, "B");
  ASSERT_EQ(set->curves[1].points.size(), 4u);
  EXPECT_DOUBLE_EQ(set->curves[1].points[1].y, 0.7);
  auto range = parseCurveFile(kRange, CurveFile::Kind::Function, "dir/branching.func");
  ASSERT_TRUE(bool(range));
  EXPECT_EQ(range->curves[0].name, "branching");  // 1.0 files are named by their file
  auto contours = parseCurveFile(kContourSet, CurveFile::Kind::Contour, "set.cset");
  ASSERT_TRUE(bool(contours));
  ASSERT_EQ(contours->curves.size(), 2u);
  EXPECT_TRUE(contours->curves[0].closed);
  EXPECT_FALSE(contours->curves[1].closed);
  EXPECT_EQ(contours->curves[1].name, "open");
  auto old = parseCurveFile(kContour10, CurveFile::Kind::Contour, "circle.con");
  ASSERT_TRUE(bool(old));
  EXPECT_TRUE(old->curves[0].closed);
  EXPECT_EQ(old->curves[0].points.size(), 4u);
  // Too few points for the count: an error naming the file and line.
  auto bad = parseCurveFile("fver 1 1\nname: x\nsamples: 10\nflip: off\npoints: 4\n0 0\n1 1\n", CurveFile::Kind::Function,
                            "bad.func");
  ASSERT_FALSE(bool(bad));
  EXPECT_NE(llvm::toString(bad.takeError()).find("bad.func:"), std::string::npos);
}

TEST(CurveFiles, AMovedFunctionPointIsWhatTheModelReads) {
  std::string path = writeText("moved.func", kFunc);
  FunctionStore before;
  ASSERT_EQ(errorText(before.loadFunction(path)), "");
  auto f = readCurveFile(path);
  ASSERT_TRUE(bool(f));
  // The third point (multiplicity 2) goes up to y = 2.
  movePoint(f->curves[0], 2, 0.6, 2.0);
  ASSERT_EQ(errorText(writeCurveFile(*f, path)), "");
  const std::string text = readText(path);
  // Only that line changed, in funcedit's "%f", its multiplicity kept.
  std::string expected = kFunc;
  expected.replace(expected.find("0.666667 0.750000 2"), 19, "0.600000 2.000000 2");
  EXPECT_EQ(text, expected);
  FunctionStore after;
  ASSERT_EQ(errorText(after.loadFunction(path)), "");
  EXPECT_GT(after.func(1, 0.6f), before.func(1, 0.6f) + 0.3f);
  auto again = readCurveFile(path);
  ASSERT_TRUE(bool(again));
  EXPECT_DOUBLE_EQ(again->curves[0].points[2].y, 2.0);
  // A point of an old two-column file stays two columns.
  auto two = parseCurveFile(kOldColumns, CurveFile::Kind::Function, "old.func");
  ASSERT_TRUE(bool(two));
  movePoint(two->curves[0], 1, 0.25, 0.5);
  EXPECT_NE(curveFileText(*two).find("\n0.250000 0.500000\n0.700000"), std::string::npos);
}

TEST(CurveFiles, AMovedContourPointIsWhatTheModelReads) {
  std::string path = writeText("movedset.cset", kContourSet);
  auto f = readCurveFile(path);
  ASSERT_TRUE(bool(f));
  movePoint(f->curves[1], 1, 0.25, 2.5);
  ASSERT_EQ(errorText(writeCurveFile(*f, path)), "");
  ContourStore store;
  ASSERT_EQ(errorText(store.loadSet(path)), "");
  ASSERT_EQ(store.size(), 3);  // the default circle, then the set's two
  EXPECT_EQ(store.nameOf(2), "open");
  bool found = false;
  for (const V3f& p : store.get(2)->controlPoints()) found = found || (p.x == 0.25f && p.y == 2.5f);
  EXPECT_TRUE(found);
  // The other contour's lines are untouched, and the moved line keeps z and multiplicity.
  const std::string text = readText(path);
  EXPECT_NE(text.find("0.250000 2.500000 0.000000 1\n"), std::string::npos);
  EXPECT_EQ(text.substr(0, text.find("cver 1 2")), std::string(kContourSet).substr(0, text.find("cver 1 2")));
  // Version 1.4 keeps its "0" z.
  auto v14 = parseCurveFile(kContour14, CurveFile::Kind::Contour, "v14.con");
  ASSERT_TRUE(bool(v14));
  movePoint(v14->curves[0], 0, 0.5, -0.5);
  EXPECT_NE(curveFileText(*v14).find("type: bspline\n0.500000 -0.500000 0 3\n"), std::string::npos);
}

TEST(CurveFiles, AddedAndRemovedPointsAreCounted) {
  // A function gets a fifth point (funcedit's Add): counted, multiplicity 1, readable by lpfg's rules.
  auto f = parseCurveFile(kFunc, CurveFile::Kind::Function, "grow.func");
  ASSERT_TRUE(bool(f));
  insertPoint(f->curves[0], 2, 0.5, 0.9);
  std::string text = curveFileText(*f);
  EXPECT_NE(text.find("points: 5\n0.000000 0.250000 1\n0.333333 0.500000 1\n0.500000 0.900000 1\n0.666667 0.750000 2\n"),
            std::string::npos)
      << text;
  std::string path = writeText("added.func", text);
  FunctionStore store;
  ASSERT_EQ(errorText(store.loadFunction(path)), "");
  removePoint(f->curves[0], 2);
  EXPECT_EQ(curveFileText(*f), std::string(kFunc));  // back as it was
  // An old two-column file's new point has two columns.
  auto two = parseCurveFile(kOldColumns, CurveFile::Kind::Function, "old.func");
  ASSERT_TRUE(bool(two));
  insertPoint(two->curves[0], 1, 0.1, 0.15);
  EXPECT_NE(curveFileText(*two).find("points: 5\n0.000000 0.100000\n0.100000 0.150000\n0.300000"), std::string::npos);
  // Contours count their points twice, the second time with multiplicities.
  auto set = parseCurveFile(kContourSet, CurveFile::Kind::Contour, "set.cset");
  ASSERT_TRUE(bool(set));
  removePoint(set->curves[1], 0);           // an end point of multiplicity 3
  insertPoint(set->curves[0], 4, 0, 2);     // the square gets a fifth corner
  text = curveFileText(*set);
  EXPECT_NE(text.find("name: square\npoints: 5 5\n"), std::string::npos) << text;
  EXPECT_NE(text.find("-1.000000 1.000000 0.000000 1\n0.000000 2.000000 0.000000 1\ncver 1 2"), std::string::npos) << text;
  EXPECT_NE(text.find("name: open\npoints: 3 5\ntype: oe\n0.300000"), std::string::npos) << text;
  ContourStore contours;
  ASSERT_EQ(errorText(contours.loadSet(writeText("edited.cset", text))), "");
  EXPECT_EQ(contours.size(), 3);
  // A 1.0 contour's header counts its points; its second number is the dimension.
  auto old = parseCurveFile(kContour10, CurveFile::Kind::Contour, "circle.con");
  ASSERT_TRUE(bool(old));
  insertPoint(old->curves[0], 1, 0.7, 0.7);
  EXPECT_EQ(curveFileText(*old), "5 2 closed\n1.0 0.0\n0.700000 0.700000\n0.0 1.0\n-1.0 0.0\n0.0 -1.0\n");
}
