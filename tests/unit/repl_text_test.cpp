// The REPL's text handling (repl/ReplText): Tab completion candidates for a line and a cursor,
// when typed C++ is complete, and splitting commands into words. No terminal, no model.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "repl/ReplText.h"

using namespace lcjit::repl;
namespace fs = std::filesystem;
using Words = std::vector<std::string>;

namespace {

CompletionSources sources() {
  CompletionSources s;
  s.commands = {":load", ":reload", ":save", ":set", ":step", ":string", ":watch", ":view", ":help", ":quit"};
  s.modules = {"Apex", "A", "B", "F", "f", "SB", "EB", "Internode"};
  s.parameters = {"LENGTH", "ANGLE"};
  return s;
}

Words candidates(const std::string& line, size_t cursor = std::string::npos) {
  return complete(line, cursor == std::string::npos ? line.size() : cursor, sources()).candidates;
}

}  // namespace

TEST(ReplCompletion, CommandNamesInTheFirstWord) {
  EXPECT_EQ(candidates(":st"), (Words{":step", ":string"}));
  EXPECT_EQ(candidates(":s"), (Words{":save", ":set", ":step", ":string"}));
  EXPECT_EQ(candidates("  :re"), (Words{":reload"}));
  EXPECT_EQ(candidates(":").size(), 10u);
  EXPECT_TRUE(candidates(":zz").empty());
  Completion c = complete("  :re", 5, sources());
  EXPECT_EQ(c.start, 2u);
}

TEST(ReplCompletion, ModuleNamesInCpp) {
  EXPECT_EQ(candidates("A"), (Words{"A", "Apex"}));
  EXPECT_EQ(candidates("x = In"), (Words{"Internode"}));
  // The word ends at the cursor and starts after C++ punctuation.
  Completion c = complete("f(Ap) + 1", 4, sources());
  EXPECT_EQ(c.start, 2u);
  EXPECT_EQ(c.candidates, (Words{"Apex"}));
  // A ':' later in the line is C++ (a scope or a label), not a command.
  EXPECT_EQ(candidates("std::max(Ap"), (Words{"Apex"}));
}

TEST(ReplCompletion, CommandArguments) {
  EXPECT_EQ(candidates(":string --module I"), (Words{"Internode"}));
  EXPECT_EQ(candidates(":string --module A B Ap"), (Words{"Apex"}));
  EXPECT_EQ(candidates(":string --mo"), (Words{"--module"}));
  EXPECT_EQ(candidates(":string --"), (Words{"--count", "--from", "--module"}));
  EXPECT_TRUE(candidates(":string --from A").empty());  // a number goes there
  EXPECT_EQ(candidates(":set L"), (Words{"LENGTH"}));
  EXPECT_TRUE(candidates(":set LENGTH L").empty());     // the value
  EXPECT_EQ(candidates(":watch o"), (Words{"off", "on"}));
  EXPECT_EQ(candidates(":view c"), (Words{"close"}));
  EXPECT_EQ(candidates(":help :w"), (Words{":watch"}));
  EXPECT_TRUE(candidates(":step A").empty());
}

TEST(ReplCompletion, FileNamesAfterLoadAndSave) {
  fs::path dir = fs::temp_directory_path() / ("lcjit-repl-text-" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  for (const char* f : {"model.l", "model.v", "other.l", ".hidden.l"}) std::ofstream(dir / f) << "\n";
  std::string d = dir.string() + "/";
  EXPECT_EQ(candidates(":load " + d + "mo"), (Words{d + "model.l", d + "model.v"}));
  EXPECT_EQ(candidates(":load " + d + "model.v " + d + "o"), (Words{d + "other.l"}));
  EXPECT_EQ(candidates(":save " + d + "s"), (Words{d + "sub/"}));     // a folder ends with '/'
  EXPECT_EQ(candidates(":load " + d + ".h"), (Words{d + ".hidden.l"}));  // hidden only when asked
  EXPECT_EQ(candidates(":load " + d).size(), 4u);                      // model.l model.v other.l sub/
  EXPECT_EQ(completeFileName(d + "zz"), Words{});
  fs::remove_all(dir);
}

TEST(ReplInput, CompleteCpp) {
  EXPECT_TRUE(isCompleteCpp("1 + 2"));
  EXPECT_TRUE(isCompleteCpp("int f(int x) { return x; }"));
  EXPECT_FALSE(isCompleteCpp("int f(int x) {"));
  EXPECT_FALSE(isCompleteCpp("int f(int x) {\n  return (x"));
  EXPECT_TRUE(isCompleteCpp("int f(int x) {\n  return (x\n); }"));
  EXPECT_FALSE(isCompleteCpp("v[0"));
  // Brackets in literals and comments do not count.
  EXPECT_TRUE(isCompleteCpp("puts(\"(\")"));
  EXPECT_TRUE(isCompleteCpp("char c = '{';"));
  EXPECT_TRUE(isCompleteCpp("x = 1; // {"));
  EXPECT_TRUE(isCompleteCpp("x = \"\\\"(\";"));
  EXPECT_FALSE(isCompleteCpp("x = 1; /* {"));
  EXPECT_TRUE(isCompleteCpp("x = 1; /* { */"));
  // A line-continuing backslash asks for more; too many closing brackets are the compiler's.
  EXPECT_FALSE(isCompleteCpp("#define TWICE(x) \\"));
  EXPECT_TRUE(isCompleteCpp("f())"));
  // As C++ lexes it: an unterminated literal ends at its line (the compiler says what is wrong);
  // a ' in a number separates digits; a raw string holds brackets, quotes and line breaks until
  // its delimiter; a backslash at a line's end joins the next line, to a comment too.
  EXPECT_TRUE(isCompleteCpp("\"unterminated"));
  EXPECT_TRUE(isCompleteCpp("'x"));
  EXPECT_TRUE(isCompleteCpp("\"{"));
  EXPECT_FALSE(isCompleteCpp("f(\"x"));
  EXPECT_TRUE(isCompleteCpp("int a[] = {1'000};"));
  EXPECT_TRUE(isCompleteCpp("f(0x1'0p+1'0, .5'5)"));
  EXPECT_FALSE(isCompleteCpp("int a[] = {1'000,"));
  EXPECT_TRUE(isCompleteCpp("u8'{' + L'(' + u\"[\""));
  EXPECT_TRUE(isCompleteCpp("R\"(a{b\"c)\""));
  EXPECT_TRUE(isCompleteCpp("R\"x(a)\"{)x\""));
  EXPECT_TRUE(isCompleteCpp("LR\"(()\" + u8R\"-({)-\""));
  EXPECT_FALSE(isCompleteCpp("R\"(abc"));
  EXPECT_FALSE(isCompleteCpp("R\"x(a)\""));
  EXPECT_TRUE(isCompleteCpp("R\"x(a\n{\n)x\""));
  EXPECT_FALSE(isCompleteCpp("puts(R\"(\n)\"\n"));
  EXPECT_TRUE(isCompleteCpp("R(\"{\")"));  // R is only a name here
  EXPECT_TRUE(isCompleteCpp("x = 1; // a comment \\\n{"));
  EXPECT_FALSE(isCompleteCpp("x = 1; // a comment \\"));
  EXPECT_TRUE(isCompleteCpp("puts(\"a\\\n(\")"));
}

TEST(ReplInput, SplitWords) {
  auto w = splitWords(":load  a.v\tmodel.l ");
  ASSERT_TRUE(bool(w));
  EXPECT_EQ(*w, (Words{":load", "a.v", "model.l"}));
  w = splitWords(":save \"my picture.png\"");
  ASSERT_TRUE(bool(w));
  EXPECT_EQ(*w, (Words{":save", "my picture.png"}));
  w = splitWords(":save \"unclosed");
  ASSERT_FALSE(bool(w));
  EXPECT_NE(llvm::toString(w.takeError()).find("quote"), std::string::npos);
}
