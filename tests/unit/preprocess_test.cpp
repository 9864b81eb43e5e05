// Unit tests for lcjit::frontend::preprocess: macros/conditionals, quoted vs angled includes,
// line markers and indentation, error messages.
#include "frontend/lc/Preprocess.h"

#include <gtest/gtest.h>

#include <llvm/Support/FileSystem.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using lcjit::frontend::preprocess;
using lcjit::frontend::PreprocessOptions;

namespace {

class PreprocessTest : public ::testing::Test {
protected:
  void SetUp() override {
    llvm::SmallString<256> d;
    const char* tmp = std::getenv("TMPDIR");
    ASSERT_FALSE(llvm::sys::fs::createUniqueDirectory(std::string(tmp && *tmp ? tmp : "/tmp") + "/lcjit-pp-test", d));
    dir_ = std::string(d);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  std::string write(const std::string& rel, const std::string& content) {
    std::string p = dir_ + "/" + rel;
    std::filesystem::create_directories(std::filesystem::path(p).parent_path());
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

  std::string ok(const std::string& path, const PreprocessOptions& o = {}) {
    auto r = preprocess(path, o);
    if (!r) {
      ADD_FAILURE() << llvm::toString(r.takeError());
      return {};
    }
    return *r;
  }

  static std::string err(const std::string& path, const PreprocessOptions& o = {}) {
    auto r = preprocess(path, o);
    if (r)
      return "<no error>\n" + *r;
    return llvm::toString(r.takeError());
  }

  // lcjit's own runtime headers (<lpfgall.h>), as the Session passes them.
  static PreprocessOptions withRuntime() {
    PreprocessOptions o;
    o.runtimeIncludeDir = LCJIT_RUNTIME_INCLUDE_DIR;
    return o;
  }

  std::string dir_;
};

struct MappedLine {
  std::string file;
  unsigned line;
  std::string text;
};

// Reads the output the way the later rewriting pass must: line markers set (file, line).
std::vector<MappedLine> mapLines(const std::string& out) {
  std::vector<MappedLine> r;
  std::istringstream in(out);
  std::string l, file;
  unsigned line = 0;
  while (std::getline(in, l)) {
    if (l.size() > 2 && l[0] == '#' && l[1] == ' ' && std::isdigit((unsigned char)l[2])) {
      size_t q1 = l.find('"'), q2 = l.find('"', q1 + 1);
      line = unsigned(std::stoul(l.substr(2)));
      file = l.substr(q1 + 1, q2 - q1 - 1);
      continue;
    }
    r.push_back({file, line, l});
    ++line;
  }
  return r;
}

const MappedLine* findLine(const std::vector<MappedLine>& lines, const std::string& needle) {
  for (const auto& m : lines)
    if (m.text.find(needle) != std::string::npos)
      return &m;
  return nullptr;
}

TEST_F(PreprocessTest, DefinesAndConditionals) {
  std::string p = write("model.l", R"(#define STEPS 13
#if STEPS > 10
big_branch STEPS;
#else
small_branch;
#endif
#ifdef FROM_OPTIONS
opt FROM_OPTIONS;
#endif
#ifndef NOT_DEFINED
ndef_ok;
#endif
flag FLAG;
)");
  PreprocessOptions o;
  o.defines = {{"FROM_OPTIONS", "42"}, {"FLAG", ""}};
  std::string out = ok(p, o);
  EXPECT_NE(out.find("big_branch 13;"), std::string::npos) << out;
  EXPECT_EQ(out.find("small_branch"), std::string::npos) << out;
  EXPECT_NE(out.find("opt 42;"), std::string::npos) << out;
  EXPECT_NE(out.find("ndef_ok;"), std::string::npos) << out;
  EXPECT_NE(out.find("flag 1;"), std::string::npos) << out;
  EXPECT_EQ(out.find("#define"), std::string::npos) << out;
}

TEST_F(PreprocessTest, CommentsRemovedAndLSystemSyntaxAccepted) {
  std::string p = write("model.l", R"(// leading comment
/* block
   comment */
derivation length: 3;
axiom: A(1) B;
A(x) < B(y) > C(z) : { produce A(x+1); } // trailing
ignore: F + -;
)");
  std::string out = ok(p);
  EXPECT_EQ(out.find("comment"), std::string::npos) << out;
  EXPECT_EQ(out.find("trailing"), std::string::npos) << out;
  EXPECT_NE(out.find("axiom: A(1) B;"), std::string::npos) << out;
  EXPECT_NE(out.find("A(x) < B(y) > C(z) : { produce A(x+1)"), std::string::npos) << out;
  EXPECT_NE(out.find("ignore: F + -;"), std::string::npos) << out;
}

TEST_F(PreprocessTest, QuotedIncludesAreExpanded) {
  write("local.h", "int from_local_header;\n#define LOCAL_VALUE 5\n");
  write("other/inc/elsewhere.h", "int from_include_dir = LOCAL_VALUE;\n");
  std::string p = write("model.l", "#include \"local.h\"\n#include \"elsewhere.h\"\nvalue LOCAL_VALUE;\n");
  PreprocessOptions o;
  o.includeDirs = {dir_ + "/other/inc"};
  std::string out = ok(p, o);
  EXPECT_NE(out.find("int from_local_header;"), std::string::npos) << out;
  EXPECT_NE(out.find("int from_include_dir = 5;"), std::string::npos) << out;
  EXPECT_NE(out.find("value 5;"), std::string::npos) << out;
  EXPECT_EQ(out.find("#include \""), std::string::npos) << out;
}

// lpfg runs g++ -E over the model: every include is resolved and its macros count. System
// headers (the standard library's, lcjit's runtime) stay #include lines for the C++ compile.
TEST_F(PreprocessTest, SystemHeadersStayIncludeLinesAndTheirMacrosApply) {
  write("helper.h", "#include <cmath>\nint helper;\n");
  std::string p = write("model.l", R"(#include <lpfgall.h>
#define vector not_expanded_in_include_names
#include<vector>
#if 0
#include <never_included.h>
#endif
#ifdef NOPE
#include <also_never.h>
#else
#include <climits>
#endif
#include "helper.h"
#ifdef __LPFGALL_H__
lpfgall_guard_seen;
#endif
#if INT_MAX == 2147483647
int_max_seen;
#endif
double pi = M_PI;
axiom: A;
)");
  std::string out = ok(p, withRuntime());
  EXPECT_NE(out.find("\n#include <lpfgall.h>\n"), std::string::npos) << out;
  EXPECT_NE(out.find("\n#include <vector>\n"), std::string::npos) << out;  // not the macro
  EXPECT_NE(out.find("\n#include <climits>\n"), std::string::npos) << out;
  EXPECT_NE(out.find("\n#include <cmath>\n"), std::string::npos) << out;  // from a quoted include
  EXPECT_EQ(out.find("never_included"), std::string::npos) << out;
  EXPECT_EQ(out.find("also_never"), std::string::npos) << out;
  // The headers' text is not in the output; their macros were applied.
  EXPECT_EQ(out.find("namespace std"), std::string::npos) << out;
  EXPECT_NE(out.find("lpfgall_guard_seen;"), std::string::npos) << out;
  EXPECT_NE(out.find("int_max_seen;"), std::string::npos) << out;
  EXPECT_NE(out.find("double pi = 3.14159265358979323846;"), std::string::npos) << out;

  auto lines = mapLines(out);
  const MappedLine* m = findLine(lines, "#include <lpfgall.h>");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->line, 1u);
  m = findLine(lines, "#include <climits>");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->line, 10u);
  m = findLine(lines, "#include <cmath>");
  ASSERT_TRUE(m);
  EXPECT_NE(m->file.find("helper.h"), std::string::npos);
  EXPECT_EQ(m->line, 1u);
}

// A model header that insists on lpfg's header (research models do) works.
TEST_F(PreprocessTest, ModelHeadersSeeLpfgallsGuard) {
  write("quaternion.hpp", "#ifndef __LPFGALL_H__\n#error quaternion.hpp must be included after lpfgall.h\n#endif\nint q;\n");
  std::string p = write("model.l", "#include <lpfgall.h>\n#include \"quaternion.hpp\"\naxiom: A;\n");
  EXPECT_NE(ok(p, withRuntime()).find("int q;"), std::string::npos);
  std::string bad = write("bad.l", "#include \"quaternion.hpp\"\n#include <lpfgall.h>\naxiom: A;\n");
  std::string e = err(bad, withRuntime());
  EXPECT_NE(e.find("quaternion.hpp:2:2: error: quaternion.hpp must be included after lpfgall.h"), std::string::npos) << e;
}

// An angled include of the model's own header (found in an -I directory) is the model's text.
TEST_F(PreprocessTest, AngledIncludeOfAModelHeaderIsExpanded) {
  write("inc/shapes.h", "#define LEAF 7\nint from_model_header = LEAF;\n");
  std::string p = write("model.l", "#include <shapes.h>\nleaf LEAF;\n");
  PreprocessOptions o = withRuntime();
  o.includeDirs = {dir_ + "/inc"};
  std::string out = ok(p, o);
  EXPECT_NE(out.find("int from_model_header = 7;"), std::string::npos) << out;
  EXPECT_NE(out.find("leaf 7;"), std::string::npos) << out;
  EXPECT_EQ(out.find("#include <shapes.h>"), std::string::npos) << out;
}

TEST_F(PreprocessTest, MissingAngledIncludeNamesFileAndLine) {
  std::string p = write("model.l", "axiom: A;\n\n#include <no_such_header_anywhere.h>\n");
  std::string e = err(p, withRuntime());
  EXPECT_NE(e.find("model.l:3:10: error: 'no_such_header_anywhere.h' file not found"), std::string::npos) << e;
}

// The macro image of <lpfgall.h> (kept in the cache directory) gives what the real header gives,
// and is made again when a header it was made from changes.
TEST_F(PreprocessTest, MacroImageMatchesTheRealHeader) {
  std::string runtime = dir_ + "/runtime";
  write("runtime/lpfgall.h", "#ifndef __LPFGALL_H__\n#define __LPFGALL_H__\n#include <cmath>\n#include \"extra.h\"\n#endif\n");
  write("runtime/extra.h", "#define EXTRA_VALUE 1\n");
  std::string p = write("model.l", "#include <lpfgall.h>\nextra EXTRA_VALUE;\n#ifdef _GLIBCXX_CMATH\ncmath_seen;\n#endif\nmpi M_PI;\n");
  PreprocessOptions real;
  real.runtimeIncludeDir = runtime;
  PreprocessOptions cached = real;
  cached.cacheDir = dir_ + "/cache";
  std::string expected = ok(p, real);
  EXPECT_NE(expected.find("extra 1;"), std::string::npos) << expected;
  EXPECT_NE(expected.find("cmath_seen;"), std::string::npos) << expected;
  EXPECT_EQ(ok(p, cached), expected);
  EXPECT_EQ(ok(p, cached), expected);
  EXPECT_TRUE(std::filesystem::exists(dir_ + "/cache/preprocessor")) << "no macro image was made";

  // The runtime headers change (as in a new lcjit build): another image.
  write("runtime/extra.h", "#define EXTRA_VALUE 2\n");
  EXPECT_NE(ok(p, cached).find("extra 2;"), std::string::npos);
}

TEST_F(PreprocessTest, LineMarkersMapEveryLine) {
  write("inc.h", "\n\nint in_header_line3;\n");
  std::string src = "#include <lpfgall.h>\n"   // 1
                    "/* a comment\n"            // 2
                    "   spanning lines */\n"    // 3
                    "#define X 1\n"             // 4
                    "axiom: A;\n";              // 5
  for (int i = 6; i < 30; ++i)
    src += "\n";                                // 6..29: a long gap forces a marker
  src += "A(x) : {\n"                           // 30
         "\t\tproduce B(x);\n"                  // 31: tab indentation kept
         "    nextline X;\n"                    // 32
         "}\n"                                  // 33
         "#include \"inc.h\"\n"                 // 34
         "after_include;\n";                    // 35
  std::string p = write("model.l", src);
  std::string out = ok(p, withRuntime());
  auto lines = mapLines(out);

  struct Expect {
    const char* needle;
    unsigned line;
    bool inHeader;
  };
  for (const Expect& e : {Expect{"axiom: A;", 5, false}, Expect{"A(x) : {", 30, false},
                          Expect{"produce B(x);", 31, false}, Expect{"nextline 1;", 32, false},
                          Expect{"int in_header_line3;", 3, true}, Expect{"after_include;", 35, false}}) {
    const MappedLine* m = findLine(lines, e.needle);
    ASSERT_TRUE(m) << e.needle << "\n" << out;
    EXPECT_EQ(m->line, e.line) << e.needle << "\n" << out;
    EXPECT_EQ(m->file.find("inc.h") != std::string::npos, e.inHeader) << m->file;
    if (!e.inHeader)
      EXPECT_NE(m->file.find("model.l"), std::string::npos) << m->file;
  }
  EXPECT_EQ(findLine(lines, "produce B(x);")->text, "\t\tproduce B(x);");
  EXPECT_EQ(findLine(lines, "nextline 1;")->text, "    nextline 1;");
  // The first line marker names the .l file, as `clang -E` does.
  EXPECT_EQ(out.rfind("# 1 \"" + p + "\"", 0), 0u) << out.substr(0, 200);
}

TEST_F(PreprocessTest, MissingQuotedIncludeNamesFileAndLine) {
  std::string p = write("model.l", "axiom: A;\n\n\n#include \"nothere.h\"\n");
  std::string e = err(p);
  EXPECT_NE(e.find(p + ":4:10: error: 'nothere.h' file not found"), std::string::npos) << e;
}

TEST_F(PreprocessTest, ErrorDirectiveAndUnterminatedIf) {
  std::string p1 = write("err.l", "axiom: A;\n#error model is broken\n");
  std::string e1 = err(p1);
  EXPECT_NE(e1.find(p1 + ":2:2: error: model is broken"), std::string::npos) << e1;

  std::string p2 = write("unterminated.l", "axiom: A;\n#if 1\nA: B;\n");
  std::string e2 = err(p2);
  EXPECT_NE(e2.find(p2 + ":2:2: error: unterminated conditional directive"), std::string::npos) << e2;
}

TEST_F(PreprocessTest, MissingLSystemFileIsNamed) {
  std::string p = dir_ + "/no_such_model.l";
  std::string e = err(p);
  EXPECT_NE(e.find("no_such_model.l"), std::string::npos) << e;
  EXPECT_NE(e.find("error"), std::string::npos) << e;
}

TEST_F(PreprocessTest, LineDirectivesInSourceAreHonoured) {
  std::string p = write("model.l", "#line 100 \"virtual.l\"\nshifted;\n");
  auto lines = mapLines(ok(p));
  const MappedLine* m = findLine(lines, "shifted;");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->file, "virtual.l");
  EXPECT_EQ(m->line, 100u);
}

} // namespace

namespace {

// OriginalColumns: a column of the preprocessed text back on the line as written. The written
// columns are counted by hand; the preprocessed ones are found in the output (how -E spaces an
// expansion is clang's business).
TEST_F(PreprocessTest, ColumnsMapBackToTheLineAsWritten) {
  const std::string file = write("m.l",
                                 "#define LENGTH 2.5\n"
                                 "#define SQ(x) ((x) * (x))\n"
                                 "float a = LENGTH + SQ(b) + bad1;\n"  // 3: a 7, LENGTH 11, SQ 20, b 23, bad1 28
                                 "float c = /* note */ d + bad2;\n"    // 4: bad2 26
                                 "float e = f + bad3;\n");             // 5: unchanged
  const std::string out = ok(file);
  const auto lines = mapLines(out);
  auto printedColumn = [&](const std::string& needle) {
    const MappedLine* m = findLine(lines, needle);
    return m ? unsigned(m->text.find(needle) + 1) : 0u;
  };
  lcjit::frontend::OriginalColumns columns(out);
  ASSERT_NE(printedColumn("bad1"), 28u);  // the expansion does move it
  EXPECT_EQ(columns.column(file, 3, printedColumn("bad1")), 28u);
  EXPECT_EQ(columns.column(file, 3, printedColumn("a =")), 7u);
  EXPECT_EQ(columns.column(file, 3, printedColumn("2.5")), 11u);   // in LENGTH's expansion: LENGTH
  EXPECT_EQ(columns.column(file, 3, printedColumn("((b)")), 20u);   // SQ's own text: SQ
  EXPECT_EQ(columns.column(file, 3, printedColumn("b) *")), 23u);   // its argument: where written
  EXPECT_EQ(columns.column(file, 4, printedColumn("bad2")), 26u);
  EXPECT_EQ(columns.column(file, 5, 15), 15u);
  EXPECT_EQ(columns.column(file, 3, 0), 0u);  // no column stays none
  // The same file named another way (relative to the current directory) is the same file.
  const std::string relative = std::filesystem::relative(file).string();
  EXPECT_EQ(columns.column(relative, 4, printedColumn("bad2")), 26u);
  // Diagnostics: the FILE:LINE:COL that starts a line; other lines as they were.
  const std::string b1 = std::to_string(printedColumn("bad1"));
  EXPECT_EQ(columns.diagnostics(file + ":3:" + b1 + ": error: use of undeclared identifier 'bad1'\n  text: 3:4: x\n"),
            file + ":3:28: error: use of undeclared identifier 'bad1'\n  text: 3:4: x\n");
}

}  // namespace
