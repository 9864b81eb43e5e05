// Unit tests for lcjit::jit::Compiler: compiling against a PCH'd header, host symbols,
// diagnostics, hot swapping, reload memory, PCH cache reuse/repair, static ctors/dtors.
#include "jit/Compiler.h"
#include "support/ReplacingFile.h"

#include <gtest/gtest.h>

#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/Object/ObjectFile.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>

#include <algorithm>
#include <malloc.h>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace lcjit::jit;

namespace {

int g_hostAddBias = 1000;
std::vector<int> g_notes;

} // namespace

// Not exported (the test binary is not linked with -rdynamic): reachable only as host symbols.
extern "C" int lcjit_test_host_add(int a, int b) { return a + b + g_hostAddBias; }
extern "C" void lcjit_test_host_note(int what) { g_notes.push_back(what); }

namespace {

std::string g_cacheRoot; // fresh per test-binary run

std::string headerPath() { return std::string(LCJIT_TEST_DATA_DIR) + "/jit/testapi.h"; }

CompilerConfig makeConfig(const std::string& cacheDir) {
  CompilerConfig c;
  c.runtimeHeader = headerPath();
  c.cacheDir = cacheDir;
  c.hostSymbols = {{"lcjit_test_host_add", reinterpret_cast<void*>(&lcjit_test_host_add)},
                   {"lcjit_test_host_note", reinterpret_cast<void*>(&lcjit_test_host_note)}};
  return c;
}

std::unique_ptr<Compiler> makeCompiler(const std::string& cacheDir) {
  auto c = Compiler::create(makeConfig(cacheDir));
  if (!c) {
    ADD_FAILURE() << llvm::toString(c.takeError());
    return nullptr;
  }
  return std::move(*c);
}

template <class Fn>
Fn lookupFn(ModelCode& code, const char* name) {
  auto p = code.lookup(name);
  if (!p) {
    ADD_FAILURE() << "lookup(" << name << "): " << llvm::toString(p.takeError());
    return nullptr;
  }
  return reinterpret_cast<Fn>(*p);
}

std::string errorText(llvm::Expected<std::unique_ptr<ModelCode>> r) {
  if (r)
    return "<compiled successfully>";
  return llvm::toString(r.takeError());
}

long rssKiB() {
  std::ifstream f("/proc/self/statm");
  long size = 0, resident = 0;
  f >> size >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

class CacheEnv : public ::testing::Environment {
public:
  void SetUp() override {
    llvm::SmallString<256> dir;
    const char* tmp = std::getenv("TMPDIR");
    std::string prefix = std::string(tmp && *tmp ? tmp : "/tmp") + "/lcjit-jit-test";
    ASSERT_FALSE(llvm::sys::fs::createUniqueDirectory(prefix, dir));
    g_cacheRoot = std::string(dir);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(g_cacheRoot, ec);
  }
};
const auto* const g_env = ::testing::AddGlobalTestEnvironment(new CacheEnv);

// One compiler shared by most tests so the PCH for each level is built once per run.
class JitTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() { compiler_ = makeCompiler(g_cacheRoot + "/shared").release(); }
  static void TearDownTestSuite() {
    delete compiler_;
    compiler_ = nullptr;
  }
  void SetUp() override { ASSERT_NE(compiler_, nullptr); }

  static std::unique_ptr<ModelCode> compileOk(const std::string& src, int optLevel = 1, CompileStats* st = nullptr) {
    CompileOptions o;
    o.optLevel = optLevel;
    auto r = compiler_->compile(src, o, st);
    if (!r) {
      ADD_FAILURE() << "compile failed:\n" << llvm::toString(r.takeError());
      return nullptr;
    }
    return std::move(*r);
  }

  static Compiler* compiler_;
};
Compiler* JitTest::compiler_ = nullptr;

// A ~150-line model-like TU: helpers, loops, switches, a std::vector, a lambda, templates.
std::string benchmarkModel(int version) {
  std::string s = "static const int kVersion = " + std::to_string(version) + ";\n";
  s += R"(
namespace {
struct Module { int id; float p[4]; };
std::vector<Module> gString;
std::vector<Module> gNext;

inline void push(std::vector<Module>& v, int id, float a, float b = 0, float c = 0) {
  Module m{id, {a, b, c, 0}};
  v.push_back(m);
}

float growth(float len, int order) {
  float f = 1.0f;
  for (int i = 0; i < order; ++i)
    f *= 0.9f;
  return len * f;
}

int classify(int id) {
  switch (id) {
  case 0: return 3;
  case 1: return 1;
  case 2: return 4;
  case 3: return 1;
  case 4: return 5;
  case 5: return 9;
  default: return 2;
  }
}

void produceA(const Module& m) {
  float len = m.p[0];
  int order = int(m.p[1]);
  push(gNext, 1, len);
  push(gNext, 2, 30);
  push(gNext, 0, growth(len, 1), float(order + 1));
  push(gNext, 3, 0);
  push(gNext, 2, -30);
  push(gNext, 0, growth(len, 2), float(order + 1));
  push(gNext, 3, 0);
}

void produceI(const Module& m) { push(gNext, 1, m.p[0] * 1.02f); }

void step() {
  gNext.clear();
  gNext.reserve(gString.size() * 4);
  for (const Module& m : gString) {
    switch (m.id) {
    case 0: produceA(m); break;
    case 1: produceI(m); break;
    default: gNext.push_back(m); break;
    }
  }
  gString.swap(gNext);
}

double interpret() {
  testapi::Turtle t;
  std::vector<testapi::Turtle> stack;
  double total = 0;
  for (const Module& m : gString) {
    switch (m.id) {
    case 1: t.forward(m.p[0]); total += m.p[0]; break;
    case 2: t.turn(m.p[0]); break;
    case 3:
      if (!stack.empty()) { t = stack.back(); stack.pop_back(); }
      break;
    default: stack.push_back(t); break;
    }
  }
  auto score = [&](double x) { return x + t.x * 0.001 + t.y * 0.001; };
  return score(total);
}

template <class T>
T clampTo(T v, T lo, T hi) { return std::max(lo, std::min(v, hi)); }

int histogram[8];
void countIds() {
  std::memset(histogram, 0, sizeof histogram);
  for (const Module& m : gString)
    histogram[clampTo(m.id, 0, 7)] += classify(m.id);
}
} // namespace

extern "C" int model_version() { return kVersion; }

extern "C" double model_run(int steps) {
  gString.clear();
  push(gString, 0, 1.0f, 0.0f);
  for (int i = 0; i < steps; ++i)
    step();
  countIds();
  std::vector<double> parts;
  for (int h : histogram)
    parts.push_back(h);
  return interpret() + testapi::sum(parts) * 1e-6;
}

extern "C" long model_size() { return long(gString.size()); }

extern "C" int model_host(int a) { return lcjit_test_host_add(a, kVersion); }
)";
  return s;
}

TEST_F(JitTest, CompilesAndCallsAtEveryOptLevel) {
  for (int level = 0; level <= 2; ++level) {
    SCOPED_TRACE("optLevel " + std::to_string(level));
    CompileStats st;
    auto code = compileOk(R"(
      extern "C" int answer(int k) {
        std::vector<int> v{1, 2, 3, k};
        return testapi::twice(testapi::sum(v)); // 2 * (6 + k)
      })",
                          level, &st);
    ASSERT_TRUE(code);
    auto fn = lookupFn<int (*)(int)>(*code, "answer");
    ASSERT_TRUE(fn);
    EXPECT_EQ(fn(15), 42);
    EXPECT_GT(st.frontendMs, 0.0);
  }
}

// Code maps back to the line (and file) its #line directive names, in the model's files only;
// an address of code that is gone, or of no code, maps to nothing.
TEST_F(JitTest, AddressesMapBackToTheSource) {
  for (int level = 0; level <= 2; ++level) {
    SCOPED_TRACE("optLevel " + std::to_string(level));
    const std::string src = "#line 40 \"/models/m.l\"\n"
                            "extern \"C\" int first(int k) {\n"  // 40
                            "  return k + 1;\n"                  // 41
                            "}\n"                                 // 42
                            "#line 7 \"/models/part.h\"\n"
                            "extern \"C\" int second(int k) { return k * 3; }\n"
                            "// " + std::to_string(level) + "\n";  // another source per level: no cache
    uintptr_t address = 0;
    {
      auto code = compileOk(src, level);
      ASSERT_TRUE(code);
      auto first = lookupFn<int (*)(int)>(*code, "first");
      auto second = lookupFn<int (*)(int)>(*code, "second");
      ASSERT_TRUE(first && second);
      address = reinterpret_cast<uintptr_t>(first);
      std::vector<SourcePlace> at = compiler_->sourceAt(address);
      ASSERT_FALSE(at.empty());
      EXPECT_EQ(at[0].file, "/models/m.l");
      EXPECT_TRUE(at[0].line == 40 || at[0].line == 41) << at[0].line;
      at = compiler_->sourceAt(reinterpret_cast<uintptr_t>(second));
      ASSERT_FALSE(at.empty());
      EXPECT_EQ(at[0].file, "/models/part.h");
      EXPECT_EQ(at[0].line, 7u);
      EXPECT_TRUE(compiler_->sourceAt(reinterpret_cast<uintptr_t>(&makeCompiler)).empty());  // lcjit's own code
    }
    EXPECT_TRUE(compiler_->sourceAt(address).empty()) << "code that was removed";
  }
}

TEST_F(JitTest, CallsHostSymbol) {
  g_notes.clear();
  auto code = compileOk(R"(
    extern "C" int callHost(int a) {
      lcjit_test_host_note(a);
      return lcjit_test_host_add(a, 3) * 10;
    })");
  ASSERT_TRUE(code);
  auto fn = lookupFn<int (*)(int)>(*code, "callHost");
  ASSERT_TRUE(fn);
  EXPECT_EQ(fn(2), (2 + 3 + 1000) * 10);
  ASSERT_EQ(g_notes.size(), 1u);
  EXPECT_EQ(g_notes[0], 2);
}

TEST_F(JitTest, SyntaxErrorPointsAtLineDirective) {
  CompileOptions o;
  std::string err = errorText(compiler_->compile("extern \"C\" int ok() { return 1; }\n"
                                                 "#line 3 \"model.l\"\n"
                                                 "    foo bar;\n",
                                                 o));
  EXPECT_NE(err.find("model.l:3:5: error: unknown type name 'foo'"), std::string::npos) << err;
  EXPECT_EQ(err.find("warning"), std::string::npos) << err;
}

TEST_F(JitTest, ErrorsCarryNotes) {
  CompileOptions o;
  std::string err = errorText(compiler_->compile("#line 10 \"model.l\"\n"
                                                 "int f() { return 1; }\n"
                                                 "int f() { return 2; }\n",
                                                 o));
  EXPECT_NE(err.find("model.l:11:5: error: redefinition of 'f'"), std::string::npos) << err;
  EXPECT_NE(err.find("model.l:10:5: note: previous definition is here"), std::string::npos) << err;
}

// Live editing: a quick-tier compile sets up the next one's front end on another thread, and
// the next compile of the same unit only parses. Checked: it is used, the code and diagnostics
// are those of the new text (a shorter text is padded, never mixed with the old one), and a
// text longer than what was set up or another unit's compile starts from scratch.
TEST_F(JitTest, QuickTiersBeginTheNextFrontEndAhead) {
  CompileOptions o;
  o.optLevel = 0;
  o.bufferName = "ahead.cpp";
  o.beginNextAhead = true;
  o.useObjectCache = false;
  auto source = [](int k) {
    return "extern \"C\" int v() { return " + std::to_string(k) + "; }\n" + std::string(k == 1 ? 400 : 0, ' ') + "// " +
           std::to_string(k) + "\n";
  };
  CompileStats st;
  auto first = compiler_->compile(source(1), o, &st);
  ASSERT_TRUE(bool(first)) << llvm::toString(first.takeError());
  EXPECT_FALSE(st.frontendBegunAhead);
  // The next front end is set up in the background; keep editing until a compile finds it.
  // Up to 30 s of edits: on a busy machine the other thread may be slow to get to it.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  bool used = false;
  for (int k = 2; std::chrono::steady_clock::now() < deadline && !used; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    auto code = compiler_->compile(source(k), o, &st);
    ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
    EXPECT_EQ(lookupFn<int (*)()>(**code, "v")(), k);
    used = st.frontendBegunAhead;
  }
  ASSERT_TRUE(used);
  // An error through a front end set up ahead: the new text's line and column.
  bool errorAhead = false;
  deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline && !errorAhead) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::string err = errorText(compiler_->compile("#line 7 \"ahead.l\"\n  oops;\n", o, &st));
    EXPECT_NE(err.find("ahead.l:7:3: error: "), std::string::npos) << err;
    errorAhead = st.frontendBegunAhead;
  }
  EXPECT_TRUE(errorAhead);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto big = compiler_->compile("extern \"C\" int v() { return 99; }\n//" + std::string(200000, 'x') + "\n", o, &st);
  ASSERT_TRUE(bool(big)) << llvm::toString(big.takeError());
  EXPECT_FALSE(st.frontendBegunAhead);
  EXPECT_EQ(lookupFn<int (*)()>(**big, "v")(), 99);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  CompileOptions other = o;
  other.bufferName = "other.cpp";
  auto elsewhere = compiler_->compile(source(5), other, &st);
  ASSERT_TRUE(bool(elsewhere)) << llvm::toString(elsewhere.takeError());
  EXPECT_FALSE(st.frontendBegunAhead);
  EXPECT_EQ(lookupFn<int (*)()>(**elsewhere, "v")(), 5);
}

TEST_F(JitTest, GarbageAndBadInputsFailCleanly) {
  CompileOptions o;
  std::string garbage;
  for (int i = 0; i < 4000; ++i)
    garbage += char((i * 7919 + 13) % 256);
  EXPECT_NE(errorText(compiler_->compile(garbage, o)).find("error:"), std::string::npos);
  EXPECT_NE(errorText(compiler_->compile("}}}}((((", o)).find("error:"), std::string::npos);

  // Resolved only at link time: must be an error, not a crash at the first call.
  std::string unresolved = errorText(compiler_->compile(
      "extern \"C\" int lcjit_nowhere_to_be_found(); extern \"C\" int g() { return lcjit_nowhere_to_be_found(); }", o));
  EXPECT_NE(unresolved.find("lcjit_nowhere_to_be_found"), std::string::npos) << unresolved;

  // Bad inline asm is only detected by the back end, whose default is exit(1).
  std::string badAsm =
      errorText(compiler_->compile("extern \"C\" void h() { asm volatile(\"not_an_instruction %eax\"); }", o));
  EXPECT_NE(badAsm.find("error"), std::string::npos) << badAsm;

  // Limits that clang enforces with errors, not stack overflows.
  std::string deep = "int deep = " + std::string(5000, '(') + "1" + std::string(5000, ')') + ";";
  EXPECT_NE(errorText(compiler_->compile(deep, o)).find("error:"), std::string::npos);
  std::string recursive = errorText(compiler_->compile(
      "template <int N> struct R { static constexpr int v = R<N + 1>::v + 1; };\n"
      "extern \"C\" int r() { return R<0>::v; }\n",
      o));
  EXPECT_NE(recursive.find("error:"), std::string::npos) << recursive;
  EXPECT_NE(errorText(compiler_->compile(std::string("int x = 1;\0 garbage", 20), o)).find("error:"),
            std::string::npos);

  // The compiler still works afterwards.
  auto code = compileOk("extern \"C\" int alive() { return 5; }");
  ASSERT_TRUE(code);
  EXPECT_EQ(lookupFn<int (*)()>(*code, "alive")(), 5);
  EXPECT_FALSE(code->lookup("not_defined_here"));
}

TEST_F(JitTest, HotSwapKeepsOldVersionAlive) {
  auto v1 = compileOk(R"(static int counter = 100; extern "C" int version() { return 1; }
                         extern "C" int bump() { return ++counter; })");
  ASSERT_TRUE(v1);
  auto v1version = lookupFn<int (*)()>(*v1, "version");
  auto v1bump = lookupFn<int (*)()>(*v1, "bump");
  ASSERT_TRUE(v1version && v1bump);
  EXPECT_EQ(v1version(), 1);
  EXPECT_EQ(v1bump(), 101);

  // Same symbol names: each version lives in its own JITDylib.
  auto v2 = compileOk(R"(static int counter = 200; extern "C" int version() { return 2; }
                         extern "C" int bump() { return ++counter; })");
  ASSERT_TRUE(v2);
  auto v2version = lookupFn<int (*)()>(*v2, "version");
  auto v2bump = lookupFn<int (*)()>(*v2, "bump");
  ASSERT_TRUE(v2version && v2bump);
  EXPECT_NE(v1->name(), v2->name());
  EXPECT_EQ(v1version(), 1);
  EXPECT_EQ(v2version(), 2);
  EXPECT_EQ(v1bump(), 102);
  EXPECT_EQ(v2bump(), 201);

  v1.reset();
  EXPECT_EQ(v2version(), 2);
  EXPECT_EQ(v2bump(), 202);
}

TEST_F(JitTest, StaticConstructorsAndDestructorsRun) {
  g_notes.clear();
  auto code = compileOk(R"(
    struct Tracker {
      int id;
      Tracker(int i) : id(i) { lcjit_test_host_note(id); }
      ~Tracker() { lcjit_test_host_note(-id); }
    };
    Tracker t1(7);
    static std::vector<int> table = {1, 2, 3};
    extern "C" int tableSum() { return testapi::sum(table) + t1.id; }
  )");
  ASSERT_TRUE(code);
  ASSERT_EQ(g_notes, std::vector<int>{7}); // ran during compile(), before any lookup
  auto fn = lookupFn<int (*)()>(*code, "tableSum");
  ASSERT_TRUE(fn);
  EXPECT_EQ(fn(), 13);
  code.reset();
  EXPECT_EQ(g_notes, (std::vector<int>{7, -7})); // destructor ran when the version was dropped
}

// Loading the same source again reuses its object code (no front end, no codegen), but gives a
// fresh copy of the model: its globals start over and its constructors run again.
TEST_F(JitTest, IdenticalSourceComesFromTheObjectCache) {
  const std::string src = R"(
    struct Note { Note() { lcjit_test_host_note(5); } } note;
    static int counter = 10;
    extern "C" int bump() { return ++counter; })";
  g_notes.clear();
  CompileStats first, second;
  auto a = compileOk(src, 0, &first);
  auto b = compileOk(src, 0, &second);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(first.object, CompileStats::ObjectFrom::Compiled);
  EXPECT_EQ(second.object, CompileStats::ObjectFrom::Memory);
  EXPECT_EQ(second.frontendMs, 0);
  EXPECT_EQ(g_notes, (std::vector<int>{5, 5}));
  auto bumpA = lookupFn<int (*)()>(*a, "bump"), bumpB = lookupFn<int (*)()>(*b, "bump");
  ASSERT_TRUE(bumpA && bumpB);
  EXPECT_EQ(bumpA(), 11);
  EXPECT_EQ(bumpA(), 12);
  EXPECT_EQ(bumpB(), 11);  // its own globals

  // Another process (here: another Compiler on the same cache directory) finds it on disk.
  auto other = makeCompiler(g_cacheRoot + "/shared");
  ASSERT_TRUE(other);
  CompileStats third;
  CompileOptions o;
  o.optLevel = 0;
  auto c = other->compile(src, o, &third);
  ASSERT_TRUE(bool(c)) << llvm::toString(c.takeError());
  EXPECT_EQ(third.object, CompileStats::ObjectFrom::Disk);
  auto bumpC = lookupFn<int (*)()>(**c, "bump");
  ASSERT_TRUE(bumpC);
  EXPECT_EQ(bumpC(), 11);

  // A different source or level is compiled.
  CompileStats changed;
  auto d = compileOk(src + "\n// edited", 0, &changed);
  EXPECT_EQ(changed.object, CompileStats::ObjectFrom::Compiled);
  auto e = compileOk(src, 2, &changed);
  EXPECT_EQ(changed.object, CompileStats::ObjectFrom::Compiled);
}

// ORC's generic platform compiles small support modules of its own (the atexit wrappers and each
// version's __dso_handle, which holds its JITDylib's address). Their object code is kept in the
// cache folder and reused by the next process, with each version's own value written in; and
// destroying one version still runs its own static destructors and no other's. The target's data
// layout is kept there too.
TEST(JitCacheTest, PlatformObjectsAreKeptAndPatchedPerVersion) {
  const std::string dir = g_cacheRoot + "/platform";
  std::filesystem::remove_all(dir);
  auto tracker = [](int id) {
    return "struct Tracker { int id; Tracker(int i) : id(i) { lcjit_test_host_note(id); }\n"
           "  ~Tracker() { lcjit_test_host_note(-id); } };\n"
           "Tracker t(" + std::to_string(id) + ");\n";
  };
  auto load = [&](Compiler& c, int id) -> std::unique_ptr<ModelCode> {
    CompileOptions o;
    o.optLevel = 1;
    auto code = c.compile(tracker(id), o);
    if (!code) {
      ADD_FAILURE() << llvm::toString(code.takeError());
      return nullptr;
    }
    return std::move(*code);
  };
  // The support objects there: name -> inode (rewriting one replaces its inode).
  auto platformFiles = [&] {
    std::map<std::string, ino_t> files;
    for (const auto& e : std::filesystem::directory_iterator(dir + "/objects"))
      if (e.path().filename().string().starts_with("platform-")) {
        struct stat st {};
        EXPECT_EQ(::stat(e.path().c_str(), &st), 0);
        files[e.path().filename().string()] = st.st_ino;
      }
    return files;
  };

  auto dsoHandle = [](ModelCode& code) -> uint64_t {
    auto at = code.lookup("__dso_handle");
    if (!at) {
      ADD_FAILURE() << llvm::toString(at.takeError());
      return 0;
    }
    return *static_cast<const uint64_t*>(*at);
  };

  g_notes.clear();
  std::map<std::string, ino_t> kept;
  {
    auto first = makeCompiler(dir);
    ASSERT_TRUE(first);
    auto v1 = load(*first, 1), v2 = load(*first, 2);
    ASSERT_TRUE(v1 && v2);
    EXPECT_NE(dsoHandle(*v1), 0u);
    EXPECT_NE(dsoHandle(*v1), dsoHandle(*v2));  // the second was patched, not compiled
    v1.reset();
    EXPECT_EQ(g_notes, (std::vector<int>{1, 2, -1}));
    v2.reset();
    EXPECT_EQ(g_notes, (std::vector<int>{1, 2, -1, -2}));
    kept = platformFiles();
    EXPECT_EQ(kept.size(), 3u);  // the process-wide wrappers, the per-version module, the data layout
    std::string layout;
    for (const auto& [name, inode] : kept)
      if (llvm::StringRef(name).ends_with(".dl"))
        layout = llvm::cantFail(llvm::errorOrToExpected(llvm::MemoryBuffer::getFile(dir + "/objects/" + name)))
                     ->getBuffer()
                     .str();
    auto host = llvm::cantFail(llvm::orc::JITTargetMachineBuilder::detectHost());
    EXPECT_EQ(layout, llvm::cantFail(host.getDefaultDataLayoutForTarget()).getStringRepresentation());
  }
  g_notes.clear();
  auto second = makeCompiler(dir);
  ASSERT_TRUE(second);
  auto v3 = load(*second, 3), v4 = load(*second, 4);
  ASSERT_TRUE(v3 && v4);
  EXPECT_NE(dsoHandle(*v3), 0u);
  EXPECT_NE(dsoHandle(*v3), dsoHandle(*v4));
  v4.reset();
  v3.reset();
  EXPECT_EQ(g_notes, (std::vector<int>{3, 4, -4, -3}));
  EXPECT_EQ(platformFiles(), kept);  // read, not compiled and written again
}

// A level's cc1 line is kept in the cache folder, so that a run whose code comes from the cache
// does not run Clang's driver. It must give the keys the driver's line gives (an object compiled
// after the driver ran is found through the kept line), and a kept line that is damaged, or whose
// searched folders changed, is made again by the driver.
TEST(JitCacheTest, KeptCc1LineGivesTheDriversKeys) {
  const std::string dir = g_cacheRoot + "/cc1";
  std::filesystem::remove_all(dir);
  const std::string src = "extern \"C\" int seven() { return 7; }\n";
  auto compileIn = [&](CompileStats& st) {
    auto c = makeCompiler(dir);
    if (!c)
      return false;
    CompileOptions o;
    o.optLevel = 1;
    auto code = c->compile(src, o, &st);
    if (!code) {
      ADD_FAILURE() << llvm::toString(code.takeError());
      return false;
    }
    auto fn = lookupFn<int (*)()>(**code, "seven");
    return fn && fn() == 7;
  };
  auto keptLines = [&] {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir + "/levels"))
      files.push_back(e.path().string());
    return files;
  };
  auto read = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  auto write = [](const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; };

  CompileStats first;
  ASSERT_TRUE(compileIn(first));  // the driver ran, its line was kept
  EXPECT_EQ(first.object, CompileStats::ObjectFrom::Compiled);
  auto files = keptLines();
  ASSERT_EQ(files.size(), 1u);
  const std::string kept = read(files[0]);
  EXPECT_TRUE(llvm::StringRef(kept).starts_with("// F "));  // the folders the driver searched
  EXPECT_NE(kept.find(std::string("-cc1\0-triple\0", 13)), std::string::npos);

  CompileStats second;  // a new process, with the kept line: the same keys
  ASSERT_TRUE(compileIn(second));
  EXPECT_EQ(second.object, CompileStats::ObjectFrom::Disk);
  EXPECT_EQ(second.objectKey, first.objectKey);
  EXPECT_TRUE(second.pchCached);

  write(files[0], "// lcjit-cc1 1\ngarbage");  // damaged: the driver again, the line rewritten
  CompileStats third;
  ASSERT_TRUE(compileIn(third));
  EXPECT_EQ(third.objectKey, first.objectKey);
  EXPECT_EQ(read(files[0]), kept);

  // A searched folder that changed (its stamp no longer holds): made again.
  std::string stale = kept;
  size_t space = stale.find(' ', 5);  // "// F SIZE MTIME...": the size of the first folder
  ASSERT_NE(space, std::string::npos);
  stale.insert(space, "0");
  write(files[0], stale);
  CompileStats fourth;
  ASSERT_TRUE(compileIn(fourth));
  EXPECT_EQ(fourth.objectKey, first.objectKey);
  EXPECT_EQ(read(files[0]), kept);
}

// Each function in its own section: JITLink (LLVM 19) splits a shared .text at every function's
// unwind entry, quadratic in the functions (20,000 productions took 5.3 GB).
TEST(JitCacheTest, EachFunctionHasItsOwnSection) {
  const std::string dir = g_cacheRoot + "/sections";
  auto compiler = makeCompiler(dir);
  ASSERT_TRUE(compiler);
  CompileOptions o;
  o.optLevel = 0;
  auto code = compiler->compile(R"(
    static int twice(int x) { return 2 * x; }
    static int thrice(int x) { return 3 * x; }
    extern "C" int both(int x) { return twice(x) + thrice(x); })",
                                o);
  ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
  int textSections = 0, objects = 0;
  std::error_code ec;
  for (llvm::sys::fs::directory_iterator it(dir + "/objects", ec), end; it != end && !ec; it.increment(ec)) {
    if (llvm::sys::path::extension(it->path()) != ".o")
      continue;  // ORC's own support objects (PlatformObjectsAreKeptAndPatchedPerVersion)
    auto file = llvm::MemoryBuffer::getFile(it->path());
    ASSERT_TRUE(bool(file));
    llvm::StringRef bytes = (*file)->getBuffer();
    size_t elf = bytes.find("\x7f" "ELF");  // after the cache entry's header lines
    ASSERT_NE(elf, llvm::StringRef::npos) << it->path();
    auto obj = llvm::object::ObjectFile::createObjectFile(llvm::MemoryBufferRef(bytes.substr(elf), it->path()));
    ASSERT_TRUE(bool(obj)) << llvm::toString(obj.takeError());
    ++objects;
    for (const llvm::object::SectionRef& sec : (*obj)->sections()) {
      auto name = sec.getName();
      if (name && name->starts_with(".text."))
        ++textSections;
    }
  }
  EXPECT_EQ(objects, 1);
  EXPECT_GE(textSections, 3);  // twice, thrice, both
}

// A better-optimised tier of the same source swapped in mid-run continues with the running
// version's globals (file statics, static locals, a std::vector, an anonymous namespace) and
// does not run the constructors again; the first version's destructors run once, when the
// last version using its state goes.
TEST_F(JitTest, TierSharesTheRunningVersionsState) {
  const std::string src = R"(
    struct Note { Note() { lcjit_test_host_note(1); } ~Note() { lcjit_test_host_note(-1); } } note;
    static int counter = 0;
    namespace { std::vector<int> history; }
    static int nextId() { static int id = 100; return ++id; }
    extern "C" int step(int tier) { history.push_back(tier); return ++counter * 1000 + nextId(); }
    extern "C" int historySum() { int s = 0; for (int h : history) s += h; return s + (int)history.size() * 100; })";
  g_notes.clear();
  auto quick = compileOk(src, 0);
  ASSERT_TRUE(quick);
  auto step0 = lookupFn<int (*)(int)>(*quick, "step");
  ASSERT_TRUE(step0);
  EXPECT_EQ(step0(0), 1101);
  EXPECT_EQ(step0(0), 2102);

  CompileOptions o;
  o.optLevel = 2;
  o.shareStateWith = {quick.get()};
  auto better = compiler_->compile(src, o);
  ASSERT_TRUE(bool(better)) << llvm::toString(better.takeError());
  EXPECT_EQ(g_notes, std::vector<int>{1});  // no second construction
  quick.reset();                             // the swap: the first version's code is dropped
  EXPECT_EQ(g_notes, std::vector<int>{1});   // but not its state
  auto step2 = lookupFn<int (*)(int)>(**better, "step");
  auto sum2 = lookupFn<int (*)()>(**better, "historySum");
  ASSERT_TRUE(step2 && sum2);
  EXPECT_EQ(step2(2), 3103);
  EXPECT_EQ(sum2(), 2 + 300);
  better->reset();
  EXPECT_EQ(g_notes, (std::vector<int>{1, -1}));
}

TEST_F(JitTest, ExceptionsWorkInsideModelCode) {
  auto code = compileOk(R"(
    #include <stdexcept>
    extern "C" int safeDiv(int a, int b) {
      try {
        if (b == 0) throw std::runtime_error("div by zero");
        return a / b;
      } catch (const std::exception& e) {
        return -1;
      }
    })");
  ASSERT_TRUE(code);
  auto fn = lookupFn<int (*)(int, int)>(*code, "safeDiv");
  ASSERT_TRUE(fn);
  EXPECT_EQ(fn(10, 2), 5);
  EXPECT_EQ(fn(10, 0), -1);
}

TEST_F(JitTest, ExceptionsPropagateIntoHost) {
  auto code = compileOk(R"(extern "C" void throwOut(int v) { if (v) throw v; })");
  ASSERT_TRUE(code);
  auto fn = lookupFn<void (*)(int)>(*code, "throwOut");
  ASSERT_TRUE(fn);
  int caught = 0;
  try {
    fn(17);
  } catch (int v) {
    caught = v;
  }
  EXPECT_EQ(caught, 17);
}

TEST_F(JitTest, ThrowingStaticConstructorIsACompileError) {
  g_notes.clear();
  std::string err = errorText(compiler_->compile(R"(
    struct Ok { Ok() { lcjit_test_host_note(1); } ~Ok() { lcjit_test_host_note(-1); } } ok;
    struct Boom { Boom() { throw 5; } } boom;
    extern "C" int never() { return 0; })",
                                                 CompileOptions{}));
  EXPECT_NE(err.find("static initializer threw"), std::string::npos) << err;
  EXPECT_EQ(g_notes, (std::vector<int>{1, -1})); // the constructed object was destroyed
  auto code = compileOk("extern \"C\" int fine() { return 3; }");
  ASSERT_TRUE(code);
  EXPECT_EQ(lookupFn<int (*)()>(*code, "fine")(), 3);
}

TEST_F(JitTest, ThreadLocalWorks) {
  auto code = compileOk(R"(thread_local int tl = 5; extern "C" int tlBump() { return ++tl; })");
  ASSERT_TRUE(code);
  auto fn = lookupFn<int (*)()>(*code, "tlBump");
  ASSERT_TRUE(fn);
  EXPECT_EQ(fn(), 6);
  EXPECT_EQ(fn(), 7);
  int other = 0;
  std::thread([&] { other = fn(); }).join();
  EXPECT_EQ(other, 6);
}

TEST_F(JitTest, CompileOnBackgroundThreadWhileOldCodeRuns) {
  auto v1 = compileOk(benchmarkModel(1));
  ASSERT_TRUE(v1);
  auto run1 = lookupFn<double (*)(int)>(*v1, "model_run");
  ASSERT_TRUE(run1);
  double expected = run1(6);

  std::atomic<bool> done{false};
  std::unique_ptr<ModelCode> v2;
  std::string error;
  std::thread bg([&] {
    CompileOptions o;
    auto r = compiler_->compile(benchmarkModel(2), o);
    if (r)
      v2 = std::move(*r);
    else
      error = llvm::toString(r.takeError());
    done = true;
  });
  int runs = 0;
  while (!done) {
    EXPECT_EQ(run1(6), expected);
    ++runs;
  }
  bg.join();
  ASSERT_TRUE(v2) << error;
  EXPECT_GT(runs, 0);
  auto version2 = lookupFn<int (*)()>(*v2, "model_version");
  ASSERT_TRUE(version2);
  EXPECT_EQ(version2(), 2);
  v1.reset();
  auto run2 = lookupFn<double (*)(int)>(*v2, "model_run");
  EXPECT_EQ(run2(6), expected);
  EXPECT_EQ(lookupFn<int (*)(int)>(*v2, "model_host")(1), 1 + 2 + 1000);
}

TEST_F(JitTest, ConcurrentCompilesOnOneCompiler) {
  std::vector<std::unique_ptr<ModelCode>> codes(4);
  std::string errors[4];
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      CompileOptions o;
      o.optLevel = t % 2;
      auto r = compiler_->compile("extern \"C\" int which() { return " + std::to_string(t) + "; }", o);
      if (r)
        codes[t] = std::move(*r);
      else
        errors[t] = llvm::toString(r.takeError());
    });
  for (auto& th : threads)
    th.join();
  for (int t = 0; t < 4; ++t) {
    ASSERT_TRUE(codes[t]) << errors[t];
    EXPECT_EQ(lookupFn<int (*)()>(*codes[t], "which")(), t);
  }
}

TEST_F(JitTest, ReloadLoopKeepsMemoryFlat) {
  const int kWarmup = 5, kTotal = 30;
  std::unique_ptr<ModelCode> current;
  long rssAfterWarmup = 0;
  for (int i = 0; i < kTotal; ++i) {
    // 3.2 MB per version, freed by its static destructor: a version that is not torn down
    // shows up in RSS. (Built by a non-constexpr function: a C++20 `vector(n, x)` static
    // initializer would first be tried in clang's constant evaluator, which is slow.)
    auto next = compileOk(benchmarkModel(i) +
                          "static std::vector<double> makeBig() { std::vector<double> v; v.resize(400000, 1.0); return v; }\n"
                          "static std::vector<double> big = makeBig();\n"
                          "extern \"C\" double bigSum() { return testapi::sum(big); }\n");
    ASSERT_TRUE(next);
    EXPECT_EQ(lookupFn<int (*)()>(*next, "model_version")(), i);
    EXPECT_EQ(lookupFn<double (*)()>(*next, "bigSum")(), 400000.0);
    current = std::move(next); // old version destroyed after the new one is live
    if (i + 1 == kWarmup)
      rssAfterWarmup = rssKiB();
  }
  long growthKiB = rssKiB() - rssAfterWarmup;
  // Measured: under 1 MB. Leaking the per-compile clang state (~6 MB each with DisableFree) or
  // a version's data (3.2 MB each) over 25 reloads would blow well past this.
  EXPECT_LT(growthKiB, 40 * 1024) << "RSS grew by " << growthKiB << " KiB over " << (kTotal - kWarmup)
                                  << " reloads";
}

// What the heap keeps per compile, as bytes in use (mallinfo2: RSS hides it behind malloc's
// free lists). Measured: ~1 KB. Clang's back end leaked its TargetMachine per compile (~28 KB)
// while CodeGenOptions::DisableFree was left on; a live session compiles at every save.
TEST_F(JitTest, ACompileKeepsNoHeap) {
  CompileOptions o;
  o.optLevel = 0;
  o.useObjectCache = false;
  auto once = [&](int k) {
    auto code = compiler_->compile("extern \"C\" int k() { return " + std::to_string(k) + "; }", o);
    ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
    EXPECT_EQ(lookupFn<int (*)()>(**code, "k")(), k);
  };
  for (int k = 0; k < 10; ++k)
    once(k);
  size_t before = mallinfo2().uordblks;
  constexpr int kCompiles = 30;
  for (int k = 0; k < kCompiles; ++k)
    once(100 + k);
  long perCompile = (long(mallinfo2().uordblks) - long(before)) / kCompiles;
  EXPECT_LT(perCompile, 8 * 1024) << perCompile << " bytes kept per compile";
}

TEST(JitCacheTest, SecondCompilerReusesPch) {
  std::string dir = g_cacheRoot + "/reuse";
  CompileOptions o;
  o.optLevel = 0;
  CompileStats st1, st2, st3;
  {
    auto c1 = makeCompiler(dir);
    ASSERT_TRUE(c1);
    auto code = c1->compile("extern \"C\" int one() { return testapi::twice(1); }", o, &st1);
    ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
    EXPECT_FALSE(st1.pchCached);
    EXPECT_GT(st1.pchBuildMs, 0.0);
    // Later compiles in the same process reuse it too.
    auto again = c1->compile("extern \"C\" int two() { return 2; }", o, &st3);
    ASSERT_TRUE(bool(again)) << llvm::toString(again.takeError());
    EXPECT_TRUE(st3.pchCached);
  }
  auto c2 = makeCompiler(dir);
  ASSERT_TRUE(c2);
  auto code = c2->compile("extern \"C\" int one() { return testapi::twice(2); }", o, &st2);
  ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
  EXPECT_TRUE(st2.pchCached);
  EXPECT_EQ(reinterpret_cast<int (*)()>(cantFail((*code)->lookup("one")))(), 4);
}

TEST(JitCacheTest, ConcurrentPchBuildsIntoSameCacheDir) {
  // Two compilers (as two processes under ctest -j would) race to build the same PCH.
  std::string dir = g_cacheRoot + "/race";
  std::string errors[2];
  int results[2] = {0, 0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t)
    threads.emplace_back([&, t] {
      auto c = Compiler::create(makeConfig(dir));
      if (!c) {
        errors[t] = llvm::toString(c.takeError());
        return;
      }
      CompileOptions o;
      o.optLevel = 0;
      auto code = (*c)->compile("extern \"C\" int id(int x) { return testapi::twice(x); }", o);
      if (!code) {
        errors[t] = llvm::toString(code.takeError());
        return;
      }
      auto fn = (*code)->lookup("id");
      if (!fn) {
        errors[t] = llvm::toString(fn.takeError());
        return;
      }
      results[t] = reinterpret_cast<int (*)(int)>(*fn)(t + 1);
    });
  for (auto& th : threads)
    th.join();
  EXPECT_EQ(results[0], 2) << errors[0];
  EXPECT_EQ(results[1], 4) << errors[1];
  int pchFiles = 0;
  std::string leftovers;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.path().extension() == ".pch")
      ++pchFiles;
    else if (lcjit::support::ReplacingFile::isUnfinished(e.path().filename().string()) ||
             !(e.path().extension() == ".o" ||  // the -O0 PCH's support object
               e.path().filename() == "objects" || e.path().parent_path().filename() == "objects" ||
               e.path().filename() == "levels" || e.path().parent_path().filename() == "levels"))
      leftovers += e.path().string() + "\n";  // besides the object cache and the kept cc1 lines
  }
  EXPECT_EQ(pchFiles, 1);
  EXPECT_EQ(leftovers, ""); // no temp files left behind
}

// Old PCHs of a level (other header versions) do not pile up: building one keeps the newest
// three of that level; other levels' stay.
TEST(JitCacheTest, BuildingAPchPrunesOldOnesOfItsLevel) {
  std::string dir = g_cacheRoot + "/prune";
  std::filesystem::create_directories(dir);
  auto fake = [&](const std::string& name, int hoursAgo) {
    std::string path = dir + "/" + name;
    std::ofstream(path) << "old";
    std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now() - std::chrono::hours(hoursAgo));
  };
  for (int i = 1; i <= 4; ++i) {
    fake("testapi-O0-old" + std::to_string(i) + ".pch", i);
    fake("testapi-O0-old" + std::to_string(i) + ".pch.o", i);  // its support object
  }
  fake("testapi-O2-other.pch", 10);
  auto c = makeCompiler(dir);
  ASSERT_TRUE(c);
  CompileOptions o;
  o.optLevel = 0;
  auto code = c->compile("extern \"C\" int one() { return 1; }", o);
  ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".pch")
      left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  ASSERT_EQ(left.size(), 4u) << ::testing::PrintToString(left);  // the new one, the two newest old ones, -O2's
  EXPECT_EQ(left[0].rfind("testapi-O0-", 0), 0u);  // the one just built (a hash sorts first)
  EXPECT_EQ(left[1], "testapi-O0-old1.pch");
  EXPECT_EQ(left[2], "testapi-O0-old2.pch");
  EXPECT_EQ(left[3], "testapi-O2-other.pch");
  EXPECT_FALSE(std::filesystem::exists(dir + "/testapi-O0-old4.pch.o"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/testapi-O0-old3.pch.o"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/testapi-O0-old2.pch.o"));
}

TEST(JitCacheTest, CorruptPchIsRebuilt) {
  std::string dir = g_cacheRoot + "/corrupt";
  CompileOptions o;
  o.optLevel = 0;
  {
    auto c1 = makeCompiler(dir);
    ASSERT_TRUE(c1);
    ASSERT_TRUE(bool(c1->compile("extern \"C\" int z() { return 0; }", o)));
  }
  int corrupted = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".pch") {
      std::ofstream(e.path(), std::ios::trunc) << "this is not a precompiled header";
      ++corrupted;
    }
  ASSERT_EQ(corrupted, 1);
  auto c2 = makeCompiler(dir);
  ASSERT_TRUE(c2);
  CompileStats st;
  auto code = c2->compile("extern \"C\" int three() { return testapi::twice(3) / 2; }", o, &st);
  ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
  EXPECT_FALSE(st.pchCached);
  EXPECT_EQ(reinterpret_cast<int (*)()>(cantFail((*code)->lookup("three")))(), 3);
}

// Level 0 compiles the header's inline code once, into a support object cached beside the PCH
// (PCH + ".o"), and models link to it instead of each emitting a copy.
TEST(JitCacheTest, O0ModelsLinkTheHeadersSupportObject) {
  std::string dir = g_cacheRoot + "/support";
  const char* source = R"(
    #include <string>
    extern "C" int labelLength(int n) { return (int)testapi::label(n).size(); }
    extern "C" double three() { return testapi::sumOfThree() + testapi::twice(0); })";
  auto check = [&](Compiler& c, int level) {
    CompileOptions o;
    o.optLevel = level;
    auto code = c.compile(source, o);
    ASSERT_TRUE(bool(code)) << llvm::toString(code.takeError());
    EXPECT_EQ(lookupFn<int (*)(int)>(**code, "labelLength")(12345), 7);  // "n=12345"
    EXPECT_EQ(lookupFn<double (*)()>(**code, "three")(), 7.0);
  };
  auto supportFile = [&] {
    std::vector<std::filesystem::path> found;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().string().ends_with(".pch.o"))
        found.push_back(e.path());
    return found;
  };
  // The format line, after the checksum line that every cache file of code starts with.
  auto header = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::string checksum, format;
    std::getline(in, checksum);
    std::getline(in, format);
    return checksum.rfind("lcjit-sha256 ", 0) == 0 && checksum.size() == 13 + 64 ? format : "no checksum: " + checksum;
  };
  {
    auto c = makeCompiler(dir);
    ASSERT_TRUE(c);
    check(*c, 0);
    check(*c, 2);  // -O2 keeps its own copies (no support object for its PCH)
  }
  auto files = supportFile();
  ASSERT_EQ(files.size(), 1u);
  EXPECT_NE(files[0].filename().string().find("-O0-"), std::string::npos);
  EXPECT_EQ(header(files[0]), "lcjit-support 1");
  auto built = std::filesystem::last_write_time(files[0]);
  {
    auto c = makeCompiler(dir);  // a new process: loads it
    ASSERT_TRUE(c);
    check(*c, 0);
  }
  EXPECT_EQ(std::filesystem::last_write_time(files[0]), built);
  std::ofstream(files[0], std::ios::trunc) << "lcjit-support 1\n99999\ntruncated";
  {
    auto c = makeCompiler(dir);  // rebuilds it
    ASSERT_TRUE(c);
    check(*c, 0);
  }
  EXPECT_EQ(header(files[0]), "lcjit-support 1");
  EXPECT_GT(std::filesystem::file_size(files[0]), 1000u);
}

TEST(JitLifetimeTest, ModelCodeMayOutliveCompiler) {
  g_notes.clear();
  std::unique_ptr<ModelCode> code;
  {
    auto c = makeCompiler(g_cacheRoot + "/shared");
    ASSERT_TRUE(c);
    CompileOptions o;
    auto r = c->compile(R"(struct D { ~D() { lcjit_test_host_note(99); } } d;
                          extern "C" int still() { return 11; })",
                        o);
    ASSERT_TRUE(bool(r)) << llvm::toString(r.takeError());
    code = std::move(*r);
  }
  EXPECT_EQ(reinterpret_cast<int (*)()>(cantFail(code->lookup("still")))(), 11);
  code.reset();
  EXPECT_EQ(g_notes, std::vector<int>{99});
}

TEST(JitConfigTest, RejectsBadConfig) {
  CompilerConfig c;
  c.runtimeHeader = "/nonexistent/lpfgall.h";
  auto r = Compiler::create(c);
  ASSERT_FALSE(bool(r));
  EXPECT_NE(llvm::toString(r.takeError()).find("/nonexistent/lpfgall.h"), std::string::npos);
}

// Not a correctness test: prints the numbers quoted in the jit report (~150-line model).
TEST_F(JitTest, ReportCompileTimes) {
  for (int level = 0; level <= 2; ++level) {
    std::vector<double> totals;
    CompileStats last;
    for (int i = 0; i < 5; ++i) {
      CompileStats st;
      auto code = compileOk(benchmarkModel(100 + i), level, &st);
      ASSERT_TRUE(code);
      auto t0 = std::chrono::steady_clock::now();
      double r = lookupFn<double (*)(int)>(*code, "model_run")(10);
      double runMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      EXPECT_GT(r, 0.0);
      totals.push_back(st.frontendMs + st.optimizeMs + st.codegenMs + st.loadMs);
      last = st;
      if (i == 4)
        std::printf("[ timing ] O%d: frontend %.1f ms, optimize %.1f ms, codegen %.1f ms, load %.1f ms, model_run(10) %.2f ms\n",
                    level, st.frontendMs, st.optimizeMs, st.codegenMs, st.loadMs, runMs);
    }
    std::sort(totals.begin(), totals.end());
    std::printf("[ timing ] O%d: median total %.1f ms (pchCached=%d)\n", level, totals[totals.size() / 2],
                int(last.pchCached));
  }
}

} // namespace
