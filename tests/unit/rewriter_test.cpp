// Unit tests for lcjit::frontend::rewrite (L+C -> C++): generated records, rules and tables,
// produce/nproduce, contexts, groups and filters, #line mapping back to the .l file, and the
// rewriter's own error messages (FILE:LINE:COL: error: ...).
#include "frontend/lc/Rewriter.h"
#include "runtime/include/lcjit/abi.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using lcjit::frontend::rewrite;
using lcjit::frontend::Rewritten;

namespace {

// Preprocessor output for m.l: a line marker, then the model text starting on line 1.
std::string model(const std::string& text) { return "# 1 \"m.l\"\n" + text; }

const char* const kMinimal = "module A(float);\nderivation length: 1;\naxiom: A(1);\n";

// Rewrites, failing the test on error.
Rewritten ok(const std::string& text) {
  auto r = rewrite(model(text), "m.l");
  if (!r) {
    ADD_FAILURE() << "unexpected rewrite error: " << llvm::toString(r.takeError()) << "\nfor:\n" << text;
    return {};
  }
  return std::move(*r);
}

// Rewrites, expecting an error; returns its message.
std::string err(const std::string& text) {
  auto r = rewrite(model(text), "m.l");
  if (r) {
    ADD_FAILURE() << "expected a rewrite error for:\n" << text << "\ngot:\n" << r->cpp;
    return {};
  }
  return llvm::toString(r.takeError());
}

// The generated C++ without #line directives and without any whitespace: fragments can be
// compared regardless of how the emitter laid them out.
std::string squash(const std::string& cpp) {
  std::istringstream in(cpp);
  std::string line, out;
  while (std::getline(in, line)) {
    if (line.rfind("#line", 0) == 0) continue;
    for (char c : line)
      if (!std::isspace((unsigned char)c)) out += c;
  }
  return out;
}

bool has(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }
#define EXPECT_HAS(hay, needle) EXPECT_TRUE(has(hay, needle)) << "missing: " << (needle) << "\nin:\n" << (hay)
#define EXPECT_HASNT(hay, needle) EXPECT_FALSE(has(hay, needle)) << "unexpected: " << (needle) << "\nin:\n" << (hay)

size_t count(const std::string& hay, const std::string& needle) {
  size_t n = 0;
  for (size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + needle.size())) ++n;
  return n;
}

// Where a (unique, identifier-like) text of the generated C++ lands for Clang: follows #line
// directives the way Clang does and returns "FILE:LINE:COL" of the first occurrence.
std::string sourcePosition(const std::string& cpp, const std::string& text) {
  std::istringstream in(cpp);
  std::string line, file = "<generated>";
  int lineNo = 1;
  while (std::getline(in, line)) {
    if (line.rfind("#line ", 0) == 0) {
      std::istringstream d(line.substr(6));
      int n;
      d >> n;
      size_t q = line.find('"');
      if (q != std::string::npos) file = line.substr(q + 1, line.find('"', q + 1) - q - 1);
      lineNo = n;
      continue;
    }
    if (line.rfind("#", 0) != 0) {
      size_t c = line.find(text);
      if (c != std::string::npos) return file + ":" + std::to_string(lineNo) + ":" + std::to_string(c + 1);
    }
    ++lineNo;
  }
  return "<not found>";
}

// The entry of rule `index` in __lc_rules, squashed: {kind,groupKind,(int16_t)(group),(int16_t)(vgroup),
// nNewLeft,nLeft,nStrict,nRight,nNewRight,filter,__lc_pattern_i,__lc_rule_i,line} (without the
// predecessor text and file that follow: ruleNames() has those).
std::string ruleEntry(const std::string& cpp, int index) {
  std::string s = squash(cpp);
  std::string tail = ",__lc_pattern_" + std::to_string(index) + ",__lc_rule_" + std::to_string(index) + ",";
  size_t p = s.find(tail);
  if (p == std::string::npos) return "<no rule " + std::to_string(index) + ">";
  size_t b = s.rfind('{', p);
  size_t e = s.find(",\"", p);
  return s.substr(b, e - b) + "}";
}

// The predecessor text and file of rule `index` (not squashed: the text has its spaces).
std::string ruleNames(const std::string& cpp, int index) {
  std::string tail = ", __lc_pattern_" + std::to_string(index) + ", __lc_rule_" + std::to_string(index) + ", ";
  size_t p = cpp.find(tail);
  if (p == std::string::npos) return "<no rule " + std::to_string(index) + ">";
  size_t b = cpp.find(", \"", p);
  size_t e = cpp.find('}', b);
  return cpp.substr(b + 2, e - b - 2);
}

// ---- modules

TEST(RewriterModules, RecordStructEmitterAndFields) {
  auto r = ok("module A(float, int);\nmodule B;\nderivation length: 1;\naxiom: A(1, 2) B;\n");
  std::string s = squash(r.cpp);
  // Each parameter type once, as a typedef the generated code names.
  EXPECT_HAS(s, "typedeffloat__lc_P_A_0;typedefint__lc_P_A_1;");
  EXPECT_HAS(s, "struct__lc_R_A{__lc_ModuleIdid;__lc_P_A_0p0;__lc_P_A_1p1;__lc_ModuleIdid2;};");
  EXPECT_HAS(s, "enum:__lc_ModuleId{__lc_id_A=103};");
  // Without lines of its own (nodebug): a stop inside it is named at the produce that called it.
  EXPECT_HAS(s, "staticinline__attribute__((__nodebug__))void__lc_emit_A(__lc_Ctx*c,__lc_P_A_0a0,__lc_P_A_1a1){__lc_R_Ar;__builtin_memset(&r,0,sizeofr);r.id=r.id2=103;r.p0=a0;r.p1=a1;__lc_put(c,&r,sizeofr);}");
  EXPECT_HAS(s, "struct__lc_R_B{__lc_ModuleIdid;__lc_ModuleIdid2;};");
  EXPECT_HAS(s, "__lc_id_B=104");
  EXPECT_HAS(s, "staticinline__attribute__((__nodebug__))void__lc_emit_B(__lc_Ctx*c){");
  EXPECT_HAS(s, "__lc_fields_A[2]={{(uint32_t)__builtin_offsetof(__lc_R_A,p0),(uint32_t)sizeof(__lc_P_A_0),__lc_kind_of<__lc_P_A_0>(),\"float\"},"
                "{(uint32_t)__builtin_offsetof(__lc_R_A,p1),(uint32_t)sizeof(__lc_P_A_1),__lc_kind_of<__lc_P_A_1>(),\"int\"},};");
  EXPECT_HAS(s, "__lc_user_modules[]={{\"A\",(uint32_t)sizeof(__lc_R_A),2,__lc_fields_A},{\"B\",(uint32_t)sizeof(__lc_R_B),0,__lc_fields_B},};");
  ASSERT_EQ(r.userModules.size(), 2u);
  EXPECT_EQ(r.userModules[0].name, "A");
  EXPECT_EQ(r.userModules[0].id, 103);
  EXPECT_EQ(r.userModules[0].paramTypes, (std::vector<std::string>{"float", "int"}));
  EXPECT_EQ(r.userModules[1].name, "B");
  EXPECT_EQ(r.userModules[1].id, 104);
  EXPECT_TRUE(r.userModules[1].paramTypes.empty());
}

TEST(RewriterModules, ListsEmptyParensVoidAndCompoundTypes) {
  auto r = ok("module A(), B(void), C(unsigned int, std::pair<int, float>);\nderivation length: 1;\naxiom: A B C(1, {});\n");
  ASSERT_EQ(r.userModules.size(), 3u);
  EXPECT_TRUE(r.userModules[0].paramTypes.empty());
  EXPECT_TRUE(r.userModules[1].paramTypes.empty());
  EXPECT_EQ(r.userModules[2].id, 105);
  EXPECT_EQ(r.userModules[2].paramTypes, (std::vector<std::string>{"unsigned int", "std::pair<int,float>"}));
  EXPECT_HAS(squash(r.cpp), "typedefunsignedint__lc_P_C_0;typedefstd::pair<int,float>__lc_P_C_1;");
  EXPECT_HAS(squash(r.cpp), "struct__lc_R_C{__lc_ModuleIdid;__lc_P_C_0p0;__lc_P_C_1p1;__lc_ModuleIdid2;};");
}

TEST(RewriterModules, NoUserModules) {
  auto r = ok("derivation length: 1;\naxiom: F(1);\n");
  EXPECT_TRUE(r.userModules.empty());
  EXPECT_HAS(squash(r.cpp), "__lc_user_modules[]={{nullptr,0,0,nullptr}};");
}

// ---- axiom, derivation length, control statements

TEST(RewriterStatements, AxiomAndDerivationLength) {
  auto r = ok("module A(float);\nderivation length: 2 + 3;\naxiom: A(1) SB() F(2) EB() A(3.5f);\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "staticint__lc_derivation_length(){return(int)(2+3);}");
  EXPECT_HAS(s, "staticvoid__lc_axiom(__lc_Ctx*__lc_ctx){__lc_emit_A(__lc_ctx,1);__lc_emit_SB(__lc_ctx);__lc_emit_F(__lc_ctx,2);"
                "__lc_emit_EB(__lc_ctx);__lc_emit_A(__lc_ctx,3.5f);}");
  EXPECT_HAS(s, "__lc_axiom,__lc_derivation_length,nullptr,nullptr,nullptr,nullptr,nullptr,nullptr,nullptr,\"m.l\",0,__lc_verify,__lc_num_of_views};");
  EXPECT_HAS(s, "extern\"C\"const__lc_Model*__lc_model(){return&__lc_the_model;}");
  EXPECT_EQ(r.ruleCount, 0);
}

TEST(RewriterStatements, CapitalAxiomSpelling) {
  auto r = ok("module A;\nderivation length: 1;\nAxiom: A A;\n");
  EXPECT_HAS(squash(r.cpp), "staticvoid__lc_axiom(__lc_Ctx*__lc_ctx){__lc_emit_A(__lc_ctx);__lc_emit_A(__lc_ctx);}");
}

TEST(RewriterStatements, EmptyAxiom) {
  auto r = ok("derivation length: 1;\naxiom: ;\n");
  EXPECT_HAS(squash(r.cpp), "staticvoid__lc_axiom(__lc_Ctx*__lc_ctx){}");
}

TEST(RewriterStatements, ControlStatementsAndDepths) {
  auto r = ok(std::string(kMinimal) +
              "Start: { int a = 1; }\nStartEach: { }\nEndEach: { }\nEnd: { }\n"
              "ring L-system: 1;\ndecomposition:\nmaximum depth: 4;\ninterpretation:\nmaximum depth: 7;\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "staticvoid__lc_start(){inta=1;}");
  EXPECT_HAS(s, "staticvoid__lc_start_each(){}");
  EXPECT_HAS(s, "staticvoid__lc_end_each(){}");
  EXPECT_HAS(s, "staticvoid__lc_end(){}");
  EXPECT_HAS(s, "staticint__lc_ring_lsystem(){return(int)(1);}");
  EXPECT_HAS(s, "staticint__lc_decomposition_depth(){return(int)(4);}");
  EXPECT_HAS(s, "staticint__lc_interpretation_depth(){return(int)(7);}");
  EXPECT_HAS(s, "__lc_axiom,__lc_derivation_length,__lc_ring_lsystem,__lc_decomposition_depth,__lc_interpretation_depth,"
                "__lc_start,__lc_start_each,__lc_end_each,__lc_end,\"m.l\",0,__lc_verify,__lc_num_of_views};");
}

TEST(RewriterStatements, CppPassesThrough) {
  // Namespace-scope C++ with ':' in it must not be taken for a predecessor.
  auto r = ok("#include <vector>\n"
              "struct Base { int b = 0; };\n"
              "struct S : Base { public: int x; S() : x(0) {} };\n"
              "enum class E : int { X, Y };\n"
              "template <class T> struct W : T { };\n"
              "static int pick(int a) { return a > 0 ? 1 : 2; }\n"
              "std::vector<int> v;\n"
              "int counter = true ? 1 : 0;\n"
              "namespace ns { int q; }\n"
              "int ns2 = ns::q;\n" +
              std::string(kMinimal));
  std::string s = squash(r.cpp);
  EXPECT_HAS(r.cpp, "#include <vector>\n");
  EXPECT_HAS(s, "structS:Base{public:intx;S():x(0){}};");
  EXPECT_HAS(s, "enumclassE:int{X,Y};");
  EXPECT_HAS(s, "template<classT>structW:T{};");
  EXPECT_HAS(s, "staticintpick(inta){returna>0?1:2;}");
  EXPECT_HAS(s, "std::vector<int>v;");
  EXPECT_HAS(s, "intns2=ns::q;");
  EXPECT_EQ(r.ruleCount, 0);
}

// ---- productions

TEST(RewriterRules, ProductionLoadsParametersAndTable) {
  auto r = ok(std::string(kMinimal) + "A(x): { produce A(x + 1); }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "staticvoid__lc_rule_0(__lc_Ctx*__lc_ctx,constchar*const*__lc_m){__lc_R_A__lc_r0;__builtin_memcpy(&__lc_r0,__lc_m[0],sizeof__lc_r0);autox=__lc_r0.p0;");
  EXPECT_HAS(s, "{{__lc_emit_A(__lc_ctx,x+1);__lc_ctx->produced=1;return;}}}");
  EXPECT_HAS(s, "staticconst__lc_ModuleId__lc_pattern_0[]={103,};");
  // Production (kind 0), normal group 0, strict predecessor of one module, no filter, line 4.
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_0,__lc_rule_0,4}");
}

TEST(RewriterRules, PredefinedModuleIds) {
  auto r = ok(std::string(kMinimal) + "A(x) > SB() F(l) EB(): { produce A(x); }\nF(l): { produce f(l) Left(1) Right(2); }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "__lc_pattern_0[]={103,0,2,1,};");
  EXPECT_HAS(s, "__lc_pattern_1[]={2,};");
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,3,0,-1,__lc_pattern_0,__lc_rule_0,4}");
  EXPECT_HAS(s, "__lc_emit_f(__lc_ctx,l);__lc_emit_Left(__lc_ctx,1);__lc_emit_Right(__lc_ctx,2);");
  // F's parameter comes from the pattern's second record (index 2 in pattern order).
  EXPECT_HAS(s, "__lc_R_F__lc_r2;__builtin_memcpy(&__lc_r2,__lc_m[2],sizeof__lc_r2);autol=__lc_r2.p0;");
}

// Fault messages name a rule by its predecessor as written, and its file.
TEST(RewriterRules, PredecessorTextAndFile) {
  auto r = ok(std::string(kMinimal) + "A(x) > SB() F(l) EB(): { produce A(x); }\nF(l) < A(x) : { produce; }\n");
  EXPECT_EQ(ruleNames(r.cpp, 0), "\"A(x) > SB F(l) EB\", \"m.l\"");
  EXPECT_EQ(ruleNames(r.cpp, 1), "\"F(l) < A(x)\", \"m.l\"");
}

TEST(RewriterRules, MultiModuleStrictPredecessor) {
  auto r = ok("module A(int), B, C(float);\nderivation length: 1;\naxiom: A(1) B C(2);\nA(n) B C(y): { produce C(n * y); }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "__lc_pattern_0[]={103,104,105,};");
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,3,0,0,-1,__lc_pattern_0,__lc_rule_0,4}");
  EXPECT_HAS(s, "__lc_R_A__lc_r0;__builtin_memcpy(&__lc_r0,__lc_m[0],sizeof__lc_r0);auton=__lc_r0.p0;__lc_R_C__lc_r2;__builtin_memcpy(&__lc_r2,__lc_m[2],sizeof__lc_r2);autoy=__lc_r2.p0;");
}

struct ContextCase {
  const char* predecessor;
  const char* counts;   // nNewLeft,nLeft,nStrict,nRight,nNewRight
  const char* pattern;  // ids in source order
};

class RewriterContexts : public ::testing::TestWithParam<ContextCase> {};

TEST_P(RewriterContexts, CountsAndPattern) {
  const ContextCase& c = GetParam();
  auto r = ok(std::string("module A, B, C, D, E;\nderivation length: 1;\naxiom: A;\n") + c.predecessor + ": { produce; }\n");
  EXPECT_EQ(ruleEntry(r.cpp, 0), std::string("{0,0,(int16_t)(0),(int16_t)(0),") + c.counts + ",-1,__lc_pattern_0,__lc_rule_0,4}")
      << c.predecessor;
  EXPECT_HAS(squash(r.cpp), std::string("__lc_pattern_0[]={") + c.pattern + "};");
}

// A=103 B=104 C=105 D=106 E=107.
INSTANTIATE_TEST_SUITE_P(
    All, RewriterContexts,
    ::testing::Values(ContextCase{"B", "0,0,1,0,0", "104,"}, ContextCase{"A < B", "0,1,1,0,0", "103,104,"},
                      ContextCase{"B > C", "0,0,1,1,0", "104,105,"}, ContextCase{"A < B > C", "0,1,1,1,0", "103,104,105,"},
                      ContextCase{"A << B", "1,0,1,0,0", "103,104,"}, ContextCase{"B >> C", "0,0,1,0,1", "104,105,"},
                      ContextCase{"A << B >> C", "1,0,1,0,1", "103,104,105,"},
                      ContextCase{"A B < C D > E", "0,2,2,1,0", "103,104,105,106,107,"},
                      ContextCase{"A << B < C > D >> E", "1,1,1,1,1", "103,104,105,106,107,"},
                      ContextCase{"A < B C >> D E", "0,1,2,0,2", "103,104,105,106,107,"},
                      ContextCase{"SB() A < B > EB()", "0,2,1,1,0", "0,103,104,1,"}));

TEST(RewriterRules, ProduceAndNproduce) {
  auto r = ok("module A(int), B;\nderivation length: 1;\naxiom: A(3);\n"
              "A(n): {\n  for (int i = 0; i < n; ++i) nproduce B;\n  nproduce A(0);\n  produce;\n}\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "for(inti=0;i<n;++i){__lc_emit_B(__lc_ctx);}");
  EXPECT_HAS(s, "{__lc_emit_A(__lc_ctx,0);}");
  // The empty produce only marks the rule applied.
  EXPECT_HAS(s, "{__lc_ctx->produced=1;return;}");
  EXPECT_EQ(count(s, "__lc_ctx->produced=1;return;"), 1u);
}

TEST(RewriterRules, NproduceAloneHasNoReturn) {
  auto r = ok("module A, B;\nderivation length: 1;\naxiom: A;\nA: { nproduce B B; }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "{{__lc_emit_B(__lc_ctx);__lc_emit_B(__lc_ctx);}}");
  EXPECT_HASNT(s, "produced");
  EXPECT_HASNT(s, "return;");
}

// lpfg's translator takes produce and nproduce anywhere (a model's grow() helper nproduces):
// outside a rule body they write to the rule running (lcjit_current_ctx()); in a control
// statement no rule runs, and what nproduce writes is dropped.
TEST(RewriterRules, ProduceInFunctionsAndControlStatements) {
  auto r = ok("module A(int), B;\nderivation length: 1;\naxiom: A(3);\n"
              "void grow(int n) { for (int i = 0; i < n; ++i) nproduce B; }\n"
              "void finish() { produce A(0); }\n"
              "End: { nproduce B; }\n"
              "A(n): { grow(n); finish(); }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "for(inti=0;i<n;++i){__lc_Ctx*__lc_ctx=lcjit_current_ctx();__lc_emit_B(__lc_ctx);}");
  EXPECT_HAS(s, "voidfinish(){{__lc_Ctx*__lc_ctx=lcjit_current_ctx();__lc_emit_A(__lc_ctx,0);__lc_ctx->produced=1;return;}}");
  EXPECT_HAS(s, "staticvoid__lc_end(){{__lc_Ctx*__lc_ctx=lcjit_current_ctx();__lc_emit_B(__lc_ctx);}}");
  // A variable that happens to be called produce, as C++ allows, stays a variable.
  auto v = ok(std::string(kMinimal) + "int f() { int produce = 2; return produce * 3; }\n");
  EXPECT_HAS(squash(v.cpp), "intf(){intproduce=2;returnproduce*3;}");
}

// `module X = N;` (lpfg's translator takes it): X is N, the next module N+1; the ids between
// have nameless table entries.
TEST(RewriterModules, ExplicitIds) {
  auto r = ok("module A(int) = 105;\nmodule B;\nderivation length: 1;\naxiom: A(1) B;\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "__lc_id_A=105");
  EXPECT_HAS(s, "__lc_id_B=106");
  EXPECT_HAS(s, "__lc_user_modules[]={{\"\",4,0,nullptr},{\"\",4,0,nullptr},{\"A\",");
  EXPECT_HAS(s, "__lc_the_model={" + std::to_string(__lc_AbiVersion) + ",4,");
}

// NumOfViews: the highest `vgroup` number declared, plus 1, as lpfg's translator counts them
// (a group without rules counts; `window N:` is the same declaration); 1 without any.
TEST(RewriterStatements, NumOfViewsCountsDeclaredViewGroups) {
  std::string none = squash(ok("module A;\nderivation length: 1;\naxiom: A;\n").cpp);
  EXPECT_HAS(none, "staticint__lc_num_of_views(){intn=0;returnn+1;}");
  std::string some = squash(ok("module A;\nderivation length: 1;\naxiom: A;\ninterpretation:\nvgroup 2:\n"
                               "A : { produce F(1); }\nendvgroup\nwindow 1:\n").cpp);
  EXPECT_HAS(some, "if((int)(2)>n)n=(int)(2);if((int)(1)>n)n=(int)(1);returnn+1;");
}

// VerifyString (manual §10.4): its module ids go into the model table.
TEST(RewriterStatements, VerifyStringListsModuleIds) {
  std::string s = squash(ok("module A, B;\nderivation length: 1;\naxiom: A;\nVerifyString: A B B;\nA : produce A B;\n").cpp);
  EXPECT_HAS(s, "staticconst__lc_ModuleId__lc_verify[]={103,104,104,};");
  EXPECT_HAS(s, "\"m.l\",3,__lc_verify,__lc_num_of_views};");
}

// lpfg also takes one produce statement without braces as the body: `A(t) : produce A(t+dt);`.
TEST(RewriterRules, BodyWithoutBraces) {
  auto r = ok("module A(float);\nderivation length: 1;\naxiom: A(1);\nA(t) : produce A(t + 1);\n"
              "interpretation:\nA(t) : produce F(t);\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "{{__lc_emit_A(__lc_ctx,t+1);__lc_ctx->produced=1;return;}}}");
  EXPECT_HAS(s, "{{__lc_emit_F(__lc_ctx,t);__lc_ctx->produced=1;return;}}}");
}

TEST(RewriterRules, ProduceWithParenthesisedGroupsAndBrackets) {
  auto r = ok("module A(float);\nderivation length: 1;\naxiom: A(1);\nA(x): { produce (A(x) SB() (F(x))) EB(); }\n");
  EXPECT_HAS(squash(r.cpp), "{__lc_emit_A(__lc_ctx,x);__lc_emit_SB(__lc_ctx);__lc_emit_F(__lc_ctx,x);__lc_emit_EB(__lc_ctx);"
                            "__lc_ctx->produced=1;return;}");
}

TEST(RewriterRules, SuccessorArgumentsWithCommasInside) {
  auto r = ok("module A(float, float);\nderivation length: 1;\naxiom: A(f2(1, 2), (3, 4));\n");
  EXPECT_HAS(squash(r.cpp), "__lc_emit_A(__lc_ctx,f2(1,2),(3,4));");
}

TEST(RewriterRules, DecompositionInterpretationHomomorphismKinds) {
  auto r = ok(std::string(kMinimal) +
              "A(x): { produce A(x); }\n"
              "decomposition:\nA(x): { produce A(x); }\n"
              "interpretation:\nA(x): { produce F(x); }\n"
              "production:\nA(x): { produce A(x); }\n"
              "homomorphism:\nA(x): { produce F(x); }\n");
  EXPECT_EQ(r.ruleCount, 5);
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_0,__lc_rule_0,4}");
  EXPECT_EQ(ruleEntry(r.cpp, 1), "{1,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_1,__lc_rule_1,6}");
  EXPECT_EQ(ruleEntry(r.cpp, 2), "{2,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_2,__lc_rule_2,8}");
  EXPECT_EQ(ruleEntry(r.cpp, 3), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_3,__lc_rule_3,10}");
  EXPECT_EQ(ruleEntry(r.cpp, 4), "{2,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_4,__lc_rule_4,12}");
}

// ---- groups and filters

// lpfg's translator takes `window N:` for `vgroup N:` and `endwindow` for `endvgroup`.
TEST(RewriterGroups, WindowIsVgroup) {
  std::string s = squash(ok("module A;\nderivation length: 1;\naxiom: A;\ninterpretation:\nwindow 2:\nA : { produce F(1); }\n"
                            "endwindow\nA : { produce F(2); }\n").cpp);
  EXPECT_HAS(s, "{2,0,(int16_t)(0),(int16_t)(2),");  // interpretation, view group 2
  EXPECT_HAS(s, "{2,0,(int16_t)(0),(int16_t)(0),");  // after endwindow: view group 0
}

// As in lpfg's translator (l2c), the production group and the view group are two settings:
// `vgroup` does not end a `group`, `endgroup` ends only the group, `endvgroup` only the view
// group, and a section header (production:, interpretation:…) ends neither.
TEST(RewriterGroups, GroupGgroupVgroupEndgroup) {
  auto r = ok(std::string(kMinimal) +
              "A(x): { produce A(x); }\n"
              "group 2:\nA(x): { produce A(x); }\n"
              "ggroup 3:\nA(x): { propensity x produce A(x); }\n"
              "vgroup 4:\nA(x): { produce A(x); }\n"
              "endgroup\nA(x): { produce A(x); }\n"
              "group NAMED:\nA(x): { produce A(x); }\nendgroup;\n"
              "interpretation:\nA(x): { produce F(x); }\n"
              "endvgroup\ngroup 5:\ninterpretation:\nA(x): { produce F(x); }\n");
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_0,__lc_rule_0,4}");
  EXPECT_EQ(ruleEntry(r.cpp, 1), "{0,0,(int16_t)(2),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_1,__lc_rule_1,6}");
  EXPECT_EQ(ruleEntry(r.cpp, 2), "{0,1,(int16_t)(3),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_2,__lc_rule_2,8}");
  EXPECT_EQ(ruleEntry(r.cpp, 3), "{0,1,(int16_t)(3),(int16_t)(4),0,0,1,0,0,-1,__lc_pattern_3,__lc_rule_3,10}");
  EXPECT_EQ(ruleEntry(r.cpp, 4), "{0,0,(int16_t)(0),(int16_t)(4),0,0,1,0,0,-1,__lc_pattern_4,__lc_rule_4,12}");
  // A group named by an identifier (e.g. an enum constant) keeps the expression.
  EXPECT_EQ(ruleEntry(r.cpp, 5), "{0,0,(int16_t)(NAMED),(int16_t)(4),0,0,1,0,0,-1,__lc_pattern_5,__lc_rule_5,14}");
  EXPECT_EQ(ruleEntry(r.cpp, 6), "{2,0,(int16_t)(0),(int16_t)(4),0,0,1,0,0,-1,__lc_pattern_6,__lc_rule_6,17}");
  EXPECT_EQ(ruleEntry(r.cpp, 7), "{2,0,(int16_t)(5),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_7,__lc_rule_7,21}");
  // propensity: the expression goes to the Propensity pseudo-module, then the successor.
  EXPECT_HAS(squash(r.cpp), "{__lc_emit_Propensity(__lc_ctx,(x));__lc_emit_A(__lc_ctx,x);__lc_ctx->produced=1;}");
}

TEST(RewriterGroups, IgnoreAndConsiderCreateFilters) {
  auto r = ok("module A, B, C;\nderivation length: 1;\naxiom: A;\n"
              "A: { produce A; }\n"
              "ignore: B C;\nA: { produce A; }\n"
              "consider: A SB EB;\nA: { produce A; }\n"
              "ignore: ;\nA: { produce A; }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "staticconst__lc_ModuleId__lc_filter_0[]={104,105,};");
  EXPECT_HAS(s, "staticconst__lc_ModuleId__lc_filter_1[]={103,0,1,};");
  EXPECT_HAS(s, "staticconst__lc_Filter__lc_filters[]={{0,2,__lc_filter_0},{1,3,__lc_filter_1},};");
  EXPECT_HAS(s, "__lc_rules,2,__lc_filters,");
  EXPECT_EQ(ruleEntry(r.cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_0,__lc_rule_0,4}");
  EXPECT_EQ(ruleEntry(r.cpp, 1), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,0,__lc_pattern_1,__lc_rule_1,6}");
  EXPECT_EQ(ruleEntry(r.cpp, 2), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,1,__lc_pattern_2,__lc_rule_2,8}");
  // `ignore: ;` cancels the filter in force.
  EXPECT_EQ(ruleEntry(r.cpp, 3), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_3,__lc_rule_3,10}");
}

TEST(RewriterGroups, NoFilters) {
  auto r = ok(kMinimal);
  EXPECT_HAS(squash(r.cpp), "__lc_filters[]={{0,0,nullptr}};");
}

// ---- InXContext

TEST(RewriterContextQueries, InLeftContextBecomesHostCall) {
  auto r = ok("module A(float), B(int);\nderivation length: 1;\naxiom: A(1) B(2);\n"
              "B(n): { float y; if (InLeftContext(A(y))) produce B(n + 1); }\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "([&]()->bool{staticconst__lc_ModuleId__lc_ids[]={103,};constchar*__lc_p[1];"
                "if(!lcjit_in_context(__lc_ctx,0,__lc_ids,1,__lc_p))returnfalse;"
                "{__lc_R_A__lc_q;__builtin_memcpy(&__lc_q,__lc_p[0],sizeof__lc_q);y=__lc_q.p0;}returntrue;}())");
}

TEST(RewriterContextQueries, SidesAndSeveralModules) {
  auto r = ok("module A(float), B(int), C;\nderivation length: 1;\naxiom: A(1) B(2);\n"
              "B(n): { float y; int k;\n"
              "  if (InRightContext(C A(y))) produce;\n"
              "  if (InNewLeftContext(B(k) C)) produce;\n"
              "  if (InNewRightContext(SB() C EB())) produce;\n}\n");
  std::string s = squash(r.cpp);
  EXPECT_HAS(s, "__lc_ids[]={105,103,};constchar*__lc_p[2];if(!lcjit_in_context(__lc_ctx,1,__lc_ids,2,__lc_p))returnfalse;"
                "{__lc_R_A__lc_q;__builtin_memcpy(&__lc_q,__lc_p[1],sizeof__lc_q);y=__lc_q.p0;}returntrue;");
  EXPECT_HAS(s, "__lc_ids[]={104,105,};constchar*__lc_p[2];if(!lcjit_in_context(__lc_ctx,2,__lc_ids,2,__lc_p))returnfalse;"
                "{__lc_R_B__lc_q;__builtin_memcpy(&__lc_q,__lc_p[0],sizeof__lc_q);k=__lc_q.p0;}returntrue;");
  EXPECT_HAS(s, "__lc_ids[]={0,105,1,};constchar*__lc_p[3];if(!lcjit_in_context(__lc_ctx,3,__lc_ids,3,__lc_p))returnfalse;returntrue;");
}

TEST(RewriterContextQueries, OutsideRulesItIsAnError) {
  EXPECT_EQ(err(std::string(kMinimal) + "Start: { float y; if (InLeftContext(A(y))) {} }\n"),
            "m.l:4:23: error: 'InLeftContext' can only be used in a production or rule body");
}

// ---- #line mapping

TEST(RewriterLines, BodyTokensMapToTheirLineAndColumn) {
  auto r = ok("module A(float);\nderivation length: 1;\naxiom: A(1);\n\n\n"
              "A(x): {\n"                               // line 6
              "  float marker_one = x;\n"               // line 7, col 9
              "  produce A(x) A(marker_two);\n"         // line 8, col 18
              "}\n"
              "\n\n\n\n\n\n\n\n\n\n\n\n"                // a gap of more than 8 lines
              "A(x) > A(z): { produce A(marker_three); }\n");  // line 22, col 26
  EXPECT_HAS(r.cpp, "#line 6 \"m.l\"\n");
  EXPECT_EQ(sourcePosition(r.cpp, "marker_one"), "m.l:7:9");
  EXPECT_EQ(sourcePosition(r.cpp, "marker_two"), "m.l:8:18");
  EXPECT_EQ(sourcePosition(r.cpp, "marker_three"), "m.l:22:26");
  EXPECT_EQ(sourcePosition(r.cpp, "static void __lc_rule_1("), "m.l:22:1");
  EXPECT_EQ(ruleEntry(r.cpp, 1), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,1,0,-1,__lc_pattern_1,__lc_rule_1,22}");
}

// A module's call starts at the module's column, also where the call before it ends just there
// (`x);` of A's call fills `x) ` up to B): a space put in between moved Clang's errors about B's
// parameters one column to the right.
TEST(RewriterLines, ModuleCallsStartAtTheModulesColumn) {
  auto r = ok("module A(float), B(float);\nderivation length: 1;\naxiom: A(x) B(y);\n");
  EXPECT_EQ(sourcePosition(r.cpp, "__lc_emit_A(__lc_ctx"), "m.l:3:8");
  EXPECT_EQ(sourcePosition(r.cpp, "__lc_emit_B(__lc_ctx"), "m.l:3:13");
}

TEST(RewriterLines, IncludedFileAndBackToMain) {
  std::string pp = "# 1 \"m.l\"\n"
                   "module A;\n"
                   "# 1 \"dir/h.h\" 1\n"
                   "inline int in_header() { return 1; }\n"
                   "\n"
                   "int header_marker = 2;\n"
                   "# 3 \"m.l\" 2\n"
                   "derivation length: 1;\n"
                   "axiom: A;\n"
                   "A: { int main_marker = 0; produce A; }\n";
  auto r = rewrite(pp, "m.l");
  ASSERT_TRUE(bool(r)) << llvm::toString(r.takeError());
  EXPECT_EQ(sourcePosition(r->cpp, "in_header"), "dir/h.h:1:12");
  EXPECT_EQ(sourcePosition(r->cpp, "header_marker"), "dir/h.h:3:5");
  EXPECT_EQ(sourcePosition(r->cpp, "main_marker"), "m.l:5:10");
  EXPECT_EQ(ruleEntry(r->cpp, 0), "{0,0,(int16_t)(0),(int16_t)(0),0,0,1,0,0,-1,__lc_pattern_0,__lc_rule_0,5}");
}

// Every argument of a long axiom line once started a fresh line padded to its column, so
// the C++ grew with the square of the line (a 200,000-character axiom gave gigabytes); and the
// axiom, run once, is not worth optimising.
TEST(RewriterLines, LongAxiomLinesStayLinear) {
  std::string axiom;
  for (int i = 0; i < 3000; ++i) axiom += "A(x) ";  // 15,000 columns, each module a call
  auto r = ok("module A(float);\nderivation length: 1;\naxiom: " + axiom + ";\n");
  // Padding every argument to its column would take 3000 × 7,500 = 22 MB; only columns up to 4096
  // are kept, about 820 arguments padded by 2,000 on average: under 2 MB, whatever the length.
  EXPECT_LT(r.cpp.size(), 2000000u);
  EXPECT_HAS(squash(r.cpp), "__attribute__((optnone,noinline))staticbool__lc_axiom_part_0(");
}

// ---- a large axiom: a table read by a loop, and calls in functions of bounded size

// A model whose axiom is `n` modules, module i written as `each(i)`, after `declarations`.
std::string axiomModel(const std::string& declarations, int n, const std::function<std::string(int)>& each) {
  std::string m = declarations + "\nderivation length: 1;\naxiom:";
  for (int i = 0; i < n; ++i) m += " " + each(i);
  return m + ";\n";
}

// The axiom's module ids as the table writes them: a char16_t string, one \x escape per module
// (none where id(i) is negative).
std::string idsTable(int n, const std::function<int(int)>& id) {
  std::string s = "staticconstchar16_t__lc_axiom_ids[]=u\"";
  char b[8];
  for (int i = 0; i < n; ++i)
    if (id(i) >= 0) s += (std::snprintf(b, sizeof b, "\\x%x", id(i)), b);
  return s + "\";";
}

// The functions that hold the axiom's calls: the squashed C++ cut at each one's start.
std::vector<std::string> axiomParts(const std::string& squashed) {
  const std::string head = "__attribute__((optnone,noinline))staticbool__lc_axiom_part_";
  std::vector<std::string> parts;
  for (size_t p = squashed.find(head); p != std::string::npos;) {
    size_t next = squashed.find(head, p + 1);
    parts.push_back(squashed.substr(p, (next == std::string::npos ? squashed.find("__lc_axiom_ids", p) : next) - p));
    p = next;
  }
  return parts;
}

// An axiom was one function of calls, whose code generation grew faster than its length (128,000
// modules: 15 s; a million: minutes). Above 1,024 modules, the numbers are data: the module ids in
// a string and the parameters in an array per type, read by one loop, and the C++ holds one call
// per module declared, however long the axiom.
TEST(RewriterAxiomTable, PlainNumbersBecomeATableReadByALoop) {
  auto number = [](int i) { return std::to_string(1000 + i % 9000); };  // as long in either axiom
  auto each = [&](int i) { return "A(" + number(i) + ") B(" + number(i) + ".5, -" + number(i) + ")"; };
  const std::string decl = "module A(int), B(float, double);";
  auto small = ok(axiomModel(decl, 1500, each)), large = ok(axiomModel(decl, 6000, each));
  for (const Rewritten* r : {&small, &large}) {
    EXPECT_EQ(count(r->cpp, "__lc_emit_A(__lc_ctx"), 1u);
    EXPECT_EQ(count(r->cpp, "__lc_emit_B(__lc_ctx"), 1u);
    EXPECT_HASNT(r->cpp, "__lc_axiom_part_");
  }
  std::string s = squash(small.cpp), ints, floats, doubles;
  for (int i = 0; i < 1500; ++i) {
    ints += number(i) + ",";
    floats += number(i) + ".5,";
    doubles += "-" + number(i) + ",";
  }
  EXPECT_HAS(s, idsTable(3000, [](int i) { return i % 2 ? 104 : 103; }));  // A is 103, B 104
  EXPECT_HAS(s, "staticconstint__lc_axiom_values_0[]={" + ints + "};");
  EXPECT_HAS(s, "staticconstfloat__lc_axiom_values_1[]={" + floats + "};");
  EXPECT_HAS(s, "staticconstdouble__lc_axiom_values_2[]={" + doubles + "};");
  EXPECT_HAS(s, "staticvoid__lc_axiom(__lc_Ctx*__lc_ctx){constint*__lc_v0=__lc_axiom_values_0;"
                "constfloat*__lc_v1=__lc_axiom_values_1;constdouble*__lc_v2=__lc_axiom_values_2;"
                "for(unsigned__lc_i=0;__lc_i<sizeof__lc_axiom_ids/2-1;++__lc_i)switch(__lc_axiom_ids[__lc_i]){"
                "case103:__lc_emit_A(__lc_ctx,__lc_v0[0]);__lc_v0+=1;break;"
                "case104:__lc_emit_B(__lc_ctx,__lc_v1[0],__lc_v2[0]);__lc_v1+=1;__lc_v2+=1;break;}}");
  // Four times the modules, four times the text (less: the rest of the model is the same).
  EXPECT_LT(large.cpp.size(), 4 * small.cpp.size());
  EXPECT_GT(large.cpp.size(), 3 * small.cpp.size());
}

TEST(RewriterAxiomTable, UpTo1024ModulesTheAxiomIsOneFunctionOfCalls) {
  auto each = [](int) { return std::string("A(1)"); };
  std::string s = squash(ok(axiomModel("module A(int);", 1024, each)).cpp);
  EXPECT_EQ(count(s, "__lc_emit_A(__lc_ctx,1);"), 1024u);
  EXPECT_HAS(s, "__attribute__((optnone,noinline))staticvoid__lc_axiom(__lc_Ctx*__lc_ctx){__lc_emit_A(__lc_ctx,1);");
  EXPECT_HAS(squash(ok(axiomModel("module A(int);", 1025, each)).cpp), idsTable(1025, [](int) { return 103; }));
}

// Any other parameter (an expression, a name, a call with side effects) keeps its call at its own
// line and column, in a function of at most 1,024 calls, where each run of calls is one case; the
// loop calls that case where the run stands, so modules and side effects keep the axiom's order.
TEST(RewriterAxiomTable, OtherParametersKeepTheirCallsInFunctionsOfBoundedSize) {
  auto each = [](int i) { return i % 3 == 2 ? "A(" + std::to_string(i) + ")" : "A(k + " + std::to_string(i) + ")"; };
  std::string s = squash(ok(axiomModel("module A(int);", 5000, each)).cpp);
  // Runs of two calls, then a module of the table: 1,667 runs, 3,334 calls.
  EXPECT_HAS(s, idsTable(5000, [](int i) { return i % 3 == 0 ? 0xffff : i % 3 == 2 ? 103 : -1; }));
  std::vector<std::string> parts = axiomParts(s);
  ASSERT_EQ(parts.size(), 4u);  // 1,024 calls a function
  size_t calls = 0;
  for (size_t p = 0; p < parts.size(); ++p) {
    EXPECT_EQ(parts[p].rfind("__attribute__((optnone,noinline))staticbool__lc_axiom_part_" + std::to_string(p) +
                                 "(__lc_Ctx*__lc_ctx,unsigned__lc_k){switch(__lc_k){case0:",
                             0),
              0u);
    size_t here = count(parts[p], "__lc_emit_A(");
    EXPECT_LE(here, 1024u);
    calls += here;
  }
  EXPECT_EQ(calls, 3334u);
  EXPECT_HAS(parts[0], "case0:__lc_emit_A(__lc_ctx,k+0);__lc_emit_A(__lc_ctx,k+1);break;case1:__lc_emit_A(__lc_ctx,k+3);");
  EXPECT_HAS(parts[0], "__lc_emit_A(__lc_ctx,k+1534);break;}return__lc_k==511;}");  // the 1,024th call: module 3 × 511 + 1
  EXPECT_HAS(s, "staticbool(*const__lc_axiom_parts[])(__lc_Ctx*,unsigned)={__lc_axiom_part_0,__lc_axiom_part_1,"
                "__lc_axiom_part_2,__lc_axiom_part_3,};");
  EXPECT_HAS(s, "default:if(__lc_axiom_parts[__lc_part](__lc_ctx,__lc_run++))++__lc_part,__lc_run=0;}}");

  // One run of 3,000 calls is one case in each of three functions: where one ends, the next goes on.
  std::string run = squash(ok(axiomModel("module A(int);", 3000, [](int i) { return "A(k + " + std::to_string(i) + ")"; })).cpp);
  EXPECT_HAS(run, idsTable(3, [](int) { return 0xffff; }));
  parts = axiomParts(run);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_HAS(parts[1], "switch(__lc_k){case0:__lc_emit_A(__lc_ctx,k+1024);");
  EXPECT_HAS(parts[1], "__lc_emit_A(__lc_ctx,k+2047);break;}return__lc_k==0;}");

  // A call keeps the module's line and column: module 4000 on a line of its own.
  auto marked = ok(axiomModel("module A(int);", 5000, [&](int i) { return i == 4000 ? "\n  A(the_marker)" : each(i); }));
  EXPECT_EQ(sourcePosition(marked.cpp, "the_marker"), "m.l:4:5");
}

// The table holds a parameter only where it means there what it means in the call: the same
// value of the parameter's type, and no error either way (an array's initializer refuses the
// narrowing a call takes). Anything else stays a call.
TEST(RewriterAxiomTable, OnlyNumbersThatMeanTheSameGoInTheTable) {
  struct Case {
    const char* type;
    const char* value;
    bool table;
  };
  const Case cases[] = {
      {"int", "7", true},           {"int", "-7", true},            {"int", "+7", true},
      {"int", "2147483647", true},  {"int", "-2147483648", true},   {"int", "2147483648", false},
      {"int", "1.5", false},        {"int", "0x10", false},         {"int", "010", false},
      {"int", "1'000", false},      {"int", "7u", false},           {"int", "'a'", false},
      {"int", "(7)", false},        {"int", "- -7", false},         {"unsigned", "-1", false},
      {"unsigned int", "4294967295", true}, {"short", "40000", false}, {"long", "5000000000", true},
      {"float", "1.5", true},       {"float", "1.5f", true},        {"float", ".5", true},
      {"float", "1e5", true},       {"float", "16777216", true},    {"float", "16777217", false},
      {"float", "1e39", false},     {"float", "1e-50", false},      {"float", "3.5L", false},
      {"float", "0x1p3", false},    {"double", "1e308", true},      {"double", "1e309", false},
      {"double", "1.5f", true},     {"double", "9007199254740993", false}, {"bool", "1", false},
      {"int*", "0", false},         {"char", "1", false},
  };
  for (const Case& c : cases) {
    std::string m = axiomModel(std::string("module A(") + c.type + "), B;", 1100, [&](int i) { return i ? "B" : "A(" + std::string(c.value) + ")"; });
    std::string s = squash(ok(m).cpp), value = squash(c.value);
    EXPECT_EQ(has(s, "__lc_emit_A(__lc_ctx," + value + ");"), !c.table) << c.type << " " << c.value;
    EXPECT_EQ(has(s, "__lc_axiom_values_0[]={" + value + ",};"), c.table) << c.type << " " << c.value;
  }
}

TEST(RewriterLines, GeneratedTablesHaveTheirOwnName) {
  auto r = ok(kMinimal);
  // The name carries where the model's text ends: just after the axiom's ';' (line 3, column 12).
  EXPECT_HAS(r.cpp, "#line 1 \"<lcjit: generated model tables m.l:3:13>\"\n");
  EXPECT_EQ(sourcePosition(r.cpp, "__lc_the_model =").rfind("<lcjit: generated model tables m.l:3:13>:", 0), 0u);
}

TEST(RewriterLines, KeptDirectivesPassThrough) {
  auto r = ok("#include <cmath>\n#pragma once\n" + std::string(kMinimal));
  EXPECT_HAS(r.cpp, "#include <cmath>\n");
  EXPECT_HAS(r.cpp, "#pragma once\n");
}

// ---- errors (FILE:LINE:COL exact)

TEST(RewriterErrors, UndeclaredModuleInPredecessor) {
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { produce A(x); }\nB(x): { produce A(x); }\n"),
            "m.l:5:1: error: undeclared module 'B'");
  EXPECT_EQ(err(std::string(kMinimal) + "B: { produce A(1); }\n"), "m.l:4:1: error: undeclared module 'B'");
  EXPECT_EQ(err(std::string(kMinimal) + "B < A(x): { produce A(x); }\n"), "m.l:4:1: error: undeclared module 'B'");
  EXPECT_EQ(err(std::string(kMinimal) + "B(y) << A(x): { produce A(x); }\n"), "m.l:4:1: error: undeclared module 'B'");
  // A later module of the predecessor.
  EXPECT_EQ(err(std::string(kMinimal) + "A(x) > Q: { produce A(x); }\n"), "m.l:4:8: error: undeclared module 'Q'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x) Q(y): { produce A(x); }\n"), "m.l:4:6: error: undeclared module 'Q'");
}

TEST(RewriterErrors, UndeclaredModuleInSuccessorAxiomAndContextQuery) {
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): {\n  produce A(x) Q(2);\n}\n"), "m.l:5:16: error: undeclared module 'Q'");
  EXPECT_EQ(err("module A;\nderivation length: 1;\naxiom: A Zed;\n"), "m.l:3:10: error: undeclared module 'Zed'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { nproduce Q; }\n"), "m.l:4:18: error: undeclared module 'Q'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { if (InLeftContext(Q)) produce; }\n"), "m.l:4:27: error: undeclared module 'Q'");
  EXPECT_EQ(err("module A;\nderivation length: 1;\naxiom: A;\nignore: A Q;\n"), "m.l:4:11: error: undeclared module 'Q'");
}

TEST(RewriterErrors, ParameterCounts) {
  EXPECT_EQ(err("module A(float, int);\nderivation length: 1;\naxiom: A(1, 2);\n\nA(x): { produce A(x, 1); }\n"),
            "m.l:5:1: error: module 'A' has 2 parameters, the predecessor gives 1");
  EXPECT_EQ(err("module A;\nderivation length: 1;\naxiom: A;\nA(x): { produce A; }\n"),
            "m.l:4:1: error: module 'A' has 0 parameters, the predecessor gives 1");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x) > F: { produce A(x); }\n"),
            "m.l:4:8: error: module 'F' has 1 parameter, the predecessor gives 0");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): {\n  if (x > 0)\n    produce A(x, 2);\n}\n"),
            "m.l:6:13: error: module 'A' has 1 parameter, 2 given");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { nproduce A(); }\n"), "m.l:4:18: error: module 'A' has 1 parameter, 0 given");
  EXPECT_EQ(err("module A(float);\nderivation length: 1;\naxiom: F(1) A;\n"), "m.l:3:13: error: module 'A' has 1 parameter, 0 given");
  EXPECT_EQ(err("module A(float, float);\nderivation length: 1;\naxiom: A(1,);\n"), "m.l:3:12: error: missing parameter of module 'A'");
  EXPECT_EQ(err("module A(float, float);\nderivation length: 1;\naxiom: A(, 1);\n"), "m.l:3:10: error: missing parameter of module 'A'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { float y; if (InLeftContext(A(y, y))) produce; }\n"),
            "m.l:4:36: error: module 'A' has 1 parameter, the predecessor gives 2");
}

TEST(RewriterErrors, ModuleDeclarations) {
  EXPECT_EQ(err("module A(float);\nmodule B, A;\nderivation length: 1;\naxiom: A(1);\n"),
            "m.l:2:11: error: module 'A' is already declared");
  EXPECT_EQ(err("module F(float);\nderivation length: 1;\naxiom: F(1);\n"),
            "m.l:1:8: error: module 'F' is already declared (it is a predefined module)");
  EXPECT_EQ(err("module  SB;\nderivation length: 1;\naxiom: ;\n"),
            "m.l:1:9: error: module 'SB' is already declared (it is a predefined module)");
  EXPECT_EQ(err("module A(float;\nderivation length: 1;\naxiom: A(1);\n"),
            "m.l:1:15: error: expected ')' to close the parameter list of module 'A'");
  EXPECT_EQ(err("module A(float, );\nderivation length: 1;\naxiom: A(1);\n"),
            "m.l:1:18: error: missing parameter type in module 'A'");
  EXPECT_EQ(err("module A(, float);\nderivation length: 1;\naxiom: A(1);\n"),
            "m.l:1:10: error: missing parameter type in module 'A'");
  EXPECT_EQ(err("module A = 5;\nderivation length: 1;\naxiom: A;\n"),
            "m.l:1:12: error: module id 5 is taken: ids below 103 are the predefined modules'");
  EXPECT_EQ(err("module A = 200;\nmodule B = 150;\nderivation length: 1;\naxiom: A;\n"),
            "m.l:2:12: error: module id 150 is taken: ids up to 200 are given already");
  // A missing ';' is reported just after the statement's last token (as clang and g++ do).
  EXPECT_EQ(err("module A\nderivation length: 1;\naxiom: A;\n"), "m.l:1:9: error: expected ';' after the module declaration");
}

TEST(RewriterErrors, MissingAxiomOrDerivationLength) {
  // Reported just after the last token of the input (not on a line past its end).
  EXPECT_EQ(err("module A(float);\nderivation length: 1;\nA(x): { produce A(x); }\n"),
            "m.l:3:24: error: the model has no 'axiom:' statement");
  EXPECT_EQ(err("module A(float);\naxiom: A(1);\n"), "m.l:2:13: error: the model has no 'derivation length:' statement");
  EXPECT_EQ(err(""), "m.l:1:1: error: the model has no 'axiom:' statement");
  EXPECT_EQ(err("module A;\nderivation length: 1;\naxiom: A;\nAxiom: A A;\n"), "m.l:4:1: error: the model has more than one axiom");
  EXPECT_EQ(err("module A;\nderivation length: 1;\naxiom: A\n"), "m.l:3:9: error: expected ';' after the module list");
  EXPECT_EQ(err("module A;\naxiom: A;\nderivation length: 1\n"), "m.l:3:21: error: expected ';' after the derivation length expression");
}

// A statement without its ';' that runs into the next one is reported where the ';' is missing,
// not at the next statement (which read as more of the first: `derivation length: 2 module
// A(int)`, `axiom: A(0) production:`), nor at the body's '}' (the window's
// hint was about a module).
TEST(RewriterErrors, MissingSemicolonBeforeTheNextStatement) {
  EXPECT_EQ(err("derivation length: 2\nmodule A(int);\naxiom: A(0);\n"),
            "m.l:1:21: error: expected ';' after the derivation length expression");
  EXPECT_EQ(err("module A(int);\nderivation length: 2;\naxiom: A(0)\nproduction:\nA(n): { produce A(n); }\n"),
            "m.l:3:12: error: expected ';' after the axiom");
  EXPECT_EQ(err("module A(int);\nderivation length: 2;\naxiom: A(0)\nmodule B;\n"),
            "m.l:3:12: error: expected ';' after the axiom");
  EXPECT_EQ(err("module A(int);\nderivation length: 2;\naxiom: A(0);\nproduction:\nA(n): {\n  produce A(n + 1)\n}\n"),
            "m.l:6:19: error: expected ';' after the successor");
  EXPECT_EQ(err("module A(int);\nderivation length: 2;\naxiom: A(0);\nproduction:\nA(n): {\n  if (n) produce A(n)\n  else produce A(1);\n}\n"),
            "m.l:6:22: error: expected ';' after the successor");
  // A conditional over lines is one expression.
  EXPECT_TRUE(bool(rewrite(model("module A;\nbool quick = true;\nint a = 2, b = 3;\nderivation length: quick ?\n  a : b;\naxiom: A;\n"), "m.l")));
  // A module list may go on over lines.
  EXPECT_TRUE(bool(rewrite(model("module A(int);\nmodule B;\nderivation length: 2;\naxiom: A(0)\n  B A(1)\n  B;\n"), "m.l")));
}

TEST(RewriterErrors, Bodies) {
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): {\n  if (x > 0) {\n    produce A(x);\n}\n"), "m.l:4:7: error: unterminated '{'");
  EXPECT_EQ(err(std::string(kMinimal) + "Start: {\n"), "m.l:4:8: error: unterminated '{'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x) { produce A(x); }\n"), "m.l:4:6: error: expected ':' after the predecessor of a production");
  EXPECT_EQ(err(std::string(kMinimal) + "decomposition:\nA(x) ;\n"),
            "m.l:5:6: error: expected ':' after the predecessor of a decomposition rule");
  EXPECT_EQ(err(std::string(kMinimal) + "interpretation:\nA(x): F(x);\n"),
            "m.l:5:7: error: expected '{' or 'produce' to start the body of an interpretation rule");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { produce A(x) }\n"), "m.l:4:21: error: expected ';' after the successor");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { produce A(x ; }\n"), "m.l:4:21: error: expected ')' to close the parameters of module 'A'");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { produce A(x) + 1; }\n"),
            "m.l:4:22: error: expected a module name in the module list, found '+'");
}

TEST(RewriterErrors, ProduceAndPropensityPlacement) {
  EXPECT_EQ(err(std::string(kMinimal) + "Start: {\n  produce A(1);\n}\n"),
            "m.l:5:3: error: 'produce' can only be used in a production or rule body");
  EXPECT_EQ(err(std::string(kMinimal) + "group 1:\nA(x): { propensity 1.0 produce A(x); }\n"),
            "m.l:5:9: error: 'propensity' can only be used in a ggroup (Gillespie group) production");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { propensity 1.0 produce A(x); }\n"),
            "m.l:4:9: error: 'propensity' can only be used in a ggroup (Gillespie group) production");
  EXPECT_EQ(err(std::string(kMinimal) + "StartEach: { propensity 1.0 produce A(1); }\n"),
            "m.l:4:14: error: 'propensity' can only be used in a production body");
  EXPECT_EQ(err(std::string(kMinimal) + "ggroup 1:\nA(x): { propensity x; }\n"),
            "m.l:5:21: error: expected 'produce' after the propensity expression");
}

TEST(RewriterErrors, PredecessorShape) {
  EXPECT_EQ(err("module A, B, C;\nderivation length: 1;\naxiom: A;\nA > B < C: { produce B; }\n"),
            "m.l:4:1: error: context operators in the wrong order in this predecessor");
  EXPECT_EQ(err("module A, B, C;\nderivation length: 1;\naxiom: A;\nA < B < C: { produce B; }\n"),
            "m.l:4:1: error: context operators in the wrong order in this predecessor");
  EXPECT_EQ(err("module A, B;\nderivation length: 1;\naxiom: A;\nA < : { produce; }\n"),
            "m.l:4:1: error: empty module list in the predecessor");
  EXPECT_EQ(err("module A, B;\nderivation length: 1;\naxiom: A;\nA > B > : { produce; }\n"),
            "m.l:4:1: error: context operators in the wrong order in this predecessor");
  EXPECT_EQ(err("module A(float);\nderivation length: 1;\naxiom: A(1);\nA(1): { produce; }\n"),
            "m.l:4:3: error: expected a parameter name in the predecessor module 'A'");
  EXPECT_EQ(err("module A(float, float);\nderivation length: 1;\naxiom: A(1, 2);\nA(x y): { produce; }\n"),
            "m.l:4:5: error: expected ',' or ')' in the predecessor module 'A'");
}

TEST(RewriterErrors, ControlStatementsAndQueries) {
  EXPECT_EQ(err(std::string(kMinimal) + "Start: { }\nStart: { }\n"), "m.l:5:1: error: 'Start:' appears more than once");
  EXPECT_EQ(err(std::string(kMinimal) + "A(x): { float y; if (InLeftContext()) produce; }\n"),
            "m.l:4:22: error: InLeftContext needs at least one module");
}

TEST(RewriterErrors, ErrorsInIncludedFilesNameTheFile) {
  std::string pp = "# 1 \"m.l\"\nmodule A;\n# 1 \"inc/h.h\" 1\n\nmodule A;\n# 3 \"m.l\" 2\nderivation length: 1;\naxiom: A;\n";
  auto r = rewrite(pp, "m.l");
  ASSERT_FALSE(bool(r));
  EXPECT_EQ(llvm::toString(r.takeError()), "inc/h.h:2:8: error: module 'A' is already declared");
}

}  // namespace
