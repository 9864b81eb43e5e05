// In-process `clang -E` for .l files, as lpfg runs `g++ -E` on them: every include is resolved,
// so the model sees the macros of the headers it includes (lpfgall.h's guard, M_PI, INT_MAX ...),
// but system headers, lcjit's runtime headers among them, stay `#include` lines in the output
// (clang's -fkeep-system-includes): the C++ compile includes them, mostly from its PCH.
#include "frontend/lc/Preprocess.h"
#include "support/CacheFiles.h"
#include "frontend/ClangDiagnostics.h"
#include "support/InputFile.h"

#include <clang/Basic/Diagnostic.h>
#include <clang/Basic/DiagnosticOptions.h>
#include <clang/Basic/SourceManager.h>
#include <clang/Basic/Version.h>
#include <clang/Frontend/CompilerInstance.h>
#include <clang/Frontend/CompilerInvocation.h>
#include <clang/Frontend/FrontendAction.h>
#include <clang/Frontend/Utils.h>
#include <clang/Driver/Driver.h>
#include <clang/Lex/Preprocessor.h>
#include <clang/Lex/PreprocessorOptions.h>

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/SHA256.h>
#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/Chrono.h>
#include <llvm/Support/VirtualFileSystem.h>
#include <llvm/Support/raw_ostream.h>
#include <llvm/TargetParser/Host.h>

#include <sys/stat.h>
#include <time.h>

#include <algorithm>
#include <limits>

#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <mutex>

namespace lcjit::frontend {

namespace {

bool isHSpace(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

class MemFile : public llvm::vfs::File {
public:
  MemFile(llvm::vfs::Status st, std::string content) : st_(std::move(st)), content_(std::move(content)) {}
  llvm::ErrorOr<llvm::vfs::Status> status() override { return st_; }
  llvm::ErrorOr<std::unique_ptr<llvm::MemoryBuffer>> getBuffer(const llvm::Twine& name, int64_t, bool, bool) override {
    return llvm::MemoryBuffer::getMemBufferCopy(content_, name);
  }
  std::error_code close() override { return {}; }

private:
  llvm::vfs::Status st_;
  std::string content_;
};

// The `#define NAME …` lines of one file set to the overrides' values (PreprocessOptions::
// overrides), continuation lines left empty so that every line keeps its number; `defined`
// gets every name the file defines, and `functionLike` those that take arguments.
std::string overrideDefines(const std::string& text, const std::map<std::string, std::string>& overrides,
                            std::set<std::string>& defined, std::set<std::string>& functionLike) {
  std::string out;
  out.reserve(text.size());
  size_t pos = 0;
  while (pos < text.size()) {
    // One logical line: physical lines joined by a backslash at their end.
    size_t end = pos, lines = 0;
    for (;;) {
      size_t nl = text.find('\n', end);
      if (nl == std::string::npos) {
        end = text.size();
        break;
      }
      ++lines;
      size_t last = nl;  // past the physical line's last character
      while (last > end && text[last - 1] == '\r') --last;
      const bool continued = last > end && text[last - 1] == '\\';
      end = nl + 1;
      if (!continued) break;
    }
    llvm::StringRef line = llvm::StringRef(text).slice(pos, end);
    llvm::StringRef rest = line.ltrim(" \t");
    if (rest.consume_front("#")) {
      rest = rest.ltrim(" \t");
      if (rest.consume_front("define") && !rest.empty() && (rest[0] == ' ' || rest[0] == '\t')) {
        rest = rest.ltrim(" \t");
        size_t n = 0;
        while (n < rest.size() && (std::isalnum((unsigned char)rest[n]) || rest[n] == '_')) ++n;
        std::string name = rest.take_front(n).str();
        if (!name.empty()) {
          defined.insert(name);
          if (rest.substr(n).starts_with("(")) functionLike.insert(name);
          else if (auto it = overrides.find(name); it != overrides.end()) {
            out += "#define " + name + " " + it->second;
            out.append(lines, '\n');
            pos = end;
            continue;
          }
        }
      }
    }
    out += line.str();
    pos = end;
  }
  return out;
}

// Remembers the text of every file clang reads, for restoring indentation afterwards; the
// model's own files with their #defines overridden (overrideDefines).
class RecordingFS : public llvm::vfs::ProxyFileSystem {
public:
  explicit RecordingFS(llvm::IntrusiveRefCntPtr<llvm::vfs::FileSystem> fs) : ProxyFileSystem(std::move(fs)) {}

  // The folders whose files are the model's own, and what their #defines become.
  void overrideIn(std::vector<std::string> folders, std::map<std::string, std::string> overrides) {
    folders_ = std::move(folders);
    overrides_ = std::move(overrides);
  }
  const std::set<std::string>& defined() const { return defined_; }
  const std::set<std::string>& functionLike() const { return functionLike_; }

  // An overridden file's size is its new text's: clang checks that a file it opens is as large
  // as its status said.
  llvm::ErrorOr<llvm::vfs::Status> status(const llvm::Twine& path) override {
    auto st = ProxyFileSystem::status(path);
    if (!st || !st->isRegularFile())
      return st;
    if (const std::string* text = overridden(path.str()))
      return llvm::vfs::Status::copyWithNewSize(*st, text->size());
    return st;
  }

  // Every file clang reads is read here, and only if it is a regular file (InputFile.h): an
  // #include of a FIFO or of /dev/zero is clang's "cannot open file" at the #include, not a
  // hang or all of the memory.
  llvm::ErrorOr<std::unique_ptr<llvm::vfs::File>> openFileForRead(const llvm::Twine& path) override {
    std::string name = path.str();
    llvm::sys::fs::file_status onDisk;
    auto buf = support::readInputFile(name, /*nullTerminated=*/false, &onDisk);
    if (!buf)
      return buf.getError();
    llvm::vfs::Status st = llvm::vfs::Status::copyWithNewName(onDisk, name);
    std::string text;
    if (const std::string* changed = overridden(name)) {
      text = *changed;
      st = llvm::vfs::Status::copyWithNewSize(st, text.size());
    } else {
      text = (*buf)->getBuffer().str();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      originals_[name] = text;
    }
    return std::unique_ptr<llvm::vfs::File>(new MemFile(st, std::move(text)));
  }

  std::vector<std::string> openedFiles() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> names;
    for (const auto& [name, text] : originals_)
      names.push_back(name);
    return names;
  }

  const std::string* original(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = originals_.find(name);
    return it == originals_.end() ? nullptr : &it->second;
  }

private:
  // The text of one of the model's own files with its #defines overridden (once per file), or
  // null: no overrides, or not the model's file.
  const std::string* overridden(const std::string& name) {
    if (overrides_.empty() || !modelsOwn(name))
      return nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = overridden_.find(name);
    if (it == overridden_.end()) {
      auto buf = support::readInputFile(name);
      if (!buf)
        return nullptr;
      it = overridden_.emplace(name, overrideDefines((*buf)->getBuffer().str(), overrides_, defined_, functionLike_)).first;
    }
    return &it->second;
  }
  bool modelsOwn(const std::string& name) const {
    llvm::SmallString<256> p(name);
    llvm::sys::fs::make_absolute(p);
    llvm::sys::path::remove_dots(p, /*remove_dot_dot=*/true);
    return std::any_of(folders_.begin(), folders_.end(),
                       [&](const std::string& f) { return llvm::StringRef(p).starts_with(f); });
  }
  mutable std::mutex mutex_;
  std::map<std::string, std::string> originals_;
  std::vector<std::string> folders_;  // normalised, each ending in '/'
  std::map<std::string, std::string> overrides_;
  std::map<std::string, std::string> overridden_;  // path -> its text with the overrides
  std::set<std::string> defined_, functionLike_;
};

class PrintToStringAction : public clang::PreprocessorFrontendAction {
public:
  explicit PrintToStringAction(std::string& out) : out_(out) {}

protected:
  void ExecuteAction() override {
    clang::CompilerInstance& ci = getCompilerInstance();
    llvm::raw_string_ostream os(out_);
    clang::DoPrintPreprocessedInput(ci.getPreprocessor(), &os, ci.getPreprocessorOutputOpts());
  }

private:
  std::string& out_;
};

// Parses a GNU line marker `# 12 "file" 1 3`; false if `line` is not one.
bool parseLineMarker(llvm::StringRef line, unsigned& number, std::string& file) {
  if (line.size() < 3 || line[0] != '#' || line[1] != ' ' || !std::isdigit((unsigned char)line[2]))
    return false;
  size_t i = 2;
  unsigned n = 0;
  while (i < line.size() && std::isdigit((unsigned char)line[i]))
    n = n * 10 + unsigned(line[i++] - '0');
  if (i + 1 >= line.size() || line[i] != ' ' || line[i + 1] != '"')
    return false;
  i += 2;
  std::string f;
  while (i < line.size() && line[i] != '"') {
    if (line[i] == '\\' && i + 1 < line.size())
      ++i;
    f += line[i++];
  }
  number = n;
  file = std::move(f);
  return true;
}

// -E prints N spaces for a first token in column N+1 (a tab counts as one column): put the
// original whitespace back when its length matches; kept system includes lose the comment -E
// adds to them.
std::string postProcess(const std::string& printed, const RecordingFS& fs, bool plainMarkers) {
  std::string out;
  out.reserve(printed.size() + 64);
  std::string curFile;
  unsigned curLine = 0;
  // Per-file line tables, built on first use.
  std::map<std::string, std::vector<llvm::StringRef>> lineTables;
  auto originalLine = [&](const std::string& file, unsigned lineNo) -> llvm::StringRef {
    auto it = lineTables.find(file);
    if (it == lineTables.end()) {
      std::vector<llvm::StringRef> lines;
      if (const std::string* text = fs.original(file)) {
        llvm::StringRef rest(*text);
        while (!rest.empty()) {
          auto [l, r] = rest.split('\n');
          lines.push_back(l);
          rest = r;
        }
      }
      it = lineTables.emplace(file, std::move(lines)).first;
    }
    if (lineNo == 0 || lineNo > it->second.size())
      return {};
    return it->second[lineNo - 1];
  };

  llvm::StringRef rest(printed);
  while (!rest.empty()) {
    auto [line, r] = rest.split('\n');
    bool hadNewline = line.size() < rest.size();
    rest = r;
    unsigned n;
    std::string f;
    if (parseLineMarker(line, n, f)) {
      curFile = std::move(f);
      curLine = n;
      // Without its flags (1 enter, 2 return, 3 system) a marker only sets the line and file.
      out += plainMarkers ? line.substr(0, line.rfind('"') + 1) : line;
    } else {
      llvm::StringRef l = line;
      static constexpr llvm::StringLiteral kKeptComment = " /* clang -E -fkeep-system-includes */";
      if (l.starts_with("#") && l.ends_with(kKeptComment)) {
        out += l.drop_back(kKeptComment.size());
      } else {
        size_t k = 0;
        while (k < l.size() && l[k] == ' ')
          ++k;
        if (k > 0 && curLine > 0) {
          llvm::StringRef orig = originalLine(curFile, curLine);
          size_t w = 0;
          while (w < orig.size() && isHSpace(orig[w]))
            ++w;
          if (w == k) {
            out += orig.take_front(w);
            out += l.drop_front(k);
          } else {
            out += l;
          }
        } else {
          out += l;
        }
      }
      ++curLine;
    }
    if (hadNewline)
      out += '\n';
  }
  return out;
}

// The clang driver turns `args` into a preprocessor invocation (finding the system include
// directories as for the C++ compile); its cc1 arguments are kept per argument list, since the
// driver costs about a millisecond and reloads repeat the same list.
std::shared_ptr<clang::CompilerInvocation> makeInvocation(const std::vector<std::string>& args, DiagCollector& dc) {
  static std::mutex mutex;
  static std::map<std::vector<std::string>, std::vector<std::string>> cc1ByArgs;
  std::vector<std::string> cc1;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cc1ByArgs.find(args);
    if (it != cc1ByArgs.end())
      cc1 = it->second;
  }
  if (cc1.empty()) {
    std::vector<const char*> argv;
    for (const auto& a : args)
      argv.push_back(a.c_str());
    clang::CreateInvocationOptions opts;
    opts.Diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
    opts.CC1Args = &cc1;
    if (!clang::createInvocation(argv, std::move(opts)) || dc.getNumErrors() != 0)
      return nullptr;
    std::lock_guard<std::mutex> lock(mutex);
    if (cc1ByArgs.size() > 64)
      cc1ByArgs.clear();
    cc1ByArgs[args] = cc1;
  }
  // The driver adds CPLUS_INCLUDE_PATH as system directories, whose headers would stay #include
  // lines; g++ -E expands them, and research models keep L+C (nproduce ...) in headers found
  // there: make them the model's own directories.
  for (auto& a : cc1)
    if (a == "-cxx-isystem")
      a = "-I";
  std::vector<const char*> argv;
  for (const auto& a : cc1)
    argv.push_back(a.c_str());
  auto inv = std::make_shared<clang::CompilerInvocation>();
  auto diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
  // The driver's list starts with "-cc1".
  if (argv.empty() || !clang::CompilerInvocation::CreateFromArgs(*inv, llvm::ArrayRef(argv).drop_front(1), *diags) ||
      dc.getNumErrors() != 0)
    return nullptr;
  return inv;
}

} // namespace

namespace {

// lpfg's preprocessing command (g++ -E -DLINUX), for the x86-64 baseline and unoptimised as
// there: a model's #if sees what it sees with lpfg.
std::vector<std::string> baseArguments(const std::string& languageStandard) {
  return {LCJIT_CLANG_EXECUTABLE, "-E", "-x", "c++", "-std=" + languageStandard, "-w", "-resource-dir",
          LCJIT_CLANG_RESOURCE_DIR, "-fkeep-system-includes", "-DLINUX"};
}

struct Run {
  std::string printed;
  llvm::IntrusiveRefCntPtr<RecordingFS> fs;
};

// Runs the preprocessor with driver arguments `args` (the input last); `mainText` replaces the
// input file's text; `macros` prints the macros defined at the end (-dM) instead of the text.
llvm::Expected<Run> runPreprocessor(const std::vector<std::string>& args, const std::optional<std::string>& mainText,
                                    bool macros, const PreprocessOptions* overriding = nullptr) {
  DiagCollector dc;
  auto inv = makeInvocation(args, dc);
  if (!inv)
    return llvm::createStringError(dc.text.empty() ? std::string("error: invalid preprocessor options") : dc.text);
  inv->getFrontendOpts().DisableFree = false;
  inv->getDiagnosticOpts().ShowCarets = false;
  if (macros) {
    inv->getPreprocessorOutputOpts().ShowMacros = 1;
    inv->getPreprocessorOutputOpts().ShowCPP = 0;
  }
  if (mainText)  // the SourceManager takes ownership of the buffer
    inv->getPreprocessorOpts().addRemappedFile(args.back(),
                                               llvm::MemoryBuffer::getMemBufferCopy(*mainText, args.back()).release());

  clang::CompilerInstance ci;
  ci.setInvocation(inv);
  ci.createDiagnostics(&dc, false);
  Run run;
  run.fs = new RecordingFS(llvm::vfs::getRealFileSystem());
  if (overriding && !overriding->overrides.empty()) {
    std::vector<std::string> folders{llvm::sys::path::parent_path(args.back()).str()};
    folders.insert(folders.end(), overriding->includeDirs.begin(), overriding->includeDirs.end());
    for (std::string& f : folders) {
      llvm::SmallString<256> p(f.empty() ? "." : f);
      llvm::sys::fs::make_absolute(p);
      llvm::sys::path::remove_dots(p, /*remove_dot_dot=*/true);
      f = p.str().str();
      if (f.back() != '/') f += '/';
    }
    run.fs->overrideIn(std::move(folders),
                       std::map<std::string, std::string>(overriding->overrides.begin(), overriding->overrides.end()));
  }
  ci.createFileManager(run.fs);
  PrintToStringAction action(run.printed);
  bool ok = ci.ExecuteAction(action);
  if (!ok || dc.getNumErrors() != 0) {
    std::string text = dc.text.empty() ? "error: preprocessing '" + args.back() + "' failed\n" : dc.text;
    while (!text.empty() && text.back() == '\n')
      text.pop_back();
    return llvm::createStringError(text);
  }
  return run;
}


constexpr llvm::StringLiteral kMacroImageFollows =
    "// lcjit: the macros <lpfgall.h> defines (frontend/Preprocess.cpp), made from the files above.\n";

// The macro image of <lpfgall.h>: one header of the #define lines that the real header and the
// standard headers under it leave defined (predefined macros left out), found before the runtime
// headers, so that `#include <lpfgall.h>` gives a model every macro lpfg's gives it without
// lexing a megabyte of standard headers in every reload (~25 ms). Its first lines are the stamps
// of the files it was made from (stampLines); it is made again when one of them changed. Kept on disk under
// `cacheDir` and known per process; nullopt (the real header is used) when it cannot be made.
std::optional<std::string> macroImageDir(const std::string& runtimeIncludeDir, const std::string& cacheDir,
                                         const std::string& prebuiltDir, const std::string& languageStandard) {
  std::vector<std::string> args = baseArguments(languageStandard);
  args.insert(args.end(), {"-isystem", runtimeIncludeDir});
  llvm::SHA256 h;
  h.update(clang::getClangFullVersion());
  for (const auto& a : args) {
    h.update(a);
    h.update(llvm::StringRef("\0", 1));
  }
  support::hashDirectoryTree(h, runtimeIncludeDir);
  const std::string name = "/preprocessor/" + llvm::toHex(h.final(), /*LowerCase=*/true).substr(0, 24);
  std::string dir = cacheDir + name;
  std::string image = dir + "/lpfgall.h";
  // Known once per process (the standard headers under it do not change meanwhile).
  static std::mutex mutex;
  static std::map<std::string, std::optional<std::string>> known;
  std::lock_guard<std::mutex> lock(mutex);
  if (auto memo = known.find(image); memo != known.end())
    return memo->second;
  std::optional<std::string>& result = known[image];

  if (auto existing = support::readInputFile(image); existing && support::stampsHold((*existing)->getBuffer(), kMacroImageFollows))
    return result = dir;
  if (!prebuiltDir.empty())
    if (auto prebuilt = support::readInputFile(prebuiltDir + name + "/lpfgall.h");
        prebuilt && support::stampsHold((*prebuilt)->getBuffer(), kMacroImageFollows))
      return result = prebuiltDir + name;

  std::string empty = cacheDir + "/preprocessor/lcjit-empty.cpp";
  std::vector<std::string> emptyArgs = args, fullArgs = args;
  emptyArgs.push_back(empty);
  fullArgs.push_back(runtimeIncludeDir + "/lpfgall.h");
  auto predefined = runPreprocessor(emptyArgs, std::string(), /*macros=*/true);
  auto all = runPreprocessor(fullArgs, std::nullopt, /*macros=*/true);
  if (!predefined || !all) {
    llvm::consumeError(predefined.takeError());
    llvm::consumeError(all.takeError());
    return result;
  }
  std::set<llvm::StringRef> builtIn;
  for (llvm::StringRef rest = predefined->printed; !rest.empty();) {
    auto [line, r] = rest.split('\n');
    builtIn.insert(line);
    rest = r;
  }
  std::optional<std::string> stamps = support::stampLines(all->fs->openedFiles());
  if (!stamps)
    return result;
  std::string text = std::move(*stamps);
  text += kMacroImageFollows;
  text += "#ifndef __LPFGALL_H__\n";
  for (llvm::StringRef rest = all->printed; !rest.empty();) {
    auto [line, r] = rest.split('\n');
    rest = r;
    if (!builtIn.count(line))
      text += line.str() + "\n";
  }
  text += "#endif\n";
  llvm::sys::fs::create_directories(dir);
  if (!support::writeCacheFile(image, text))
    return result;
  return result = dir;
}

// A model's preprocessed text kept in the cache folder, so that a run of an unchanged model skips
// Clang's driver and preprocessor (3 ms of a 11 ms run from the cache): the stamps of the files the
// preprocessor read (stampLines), then the text. Timestamps move in steps of a few
// milliseconds, so a file changed shortly before the preprocessor began (20 ms) could change again
// unseen, within the same step: then nothing is kept. The name is a hash of everything else the
// text depends on: lcjit's build, the driver arguments (options, defines, the model's path), CPATH
// and CPLUS_INCLUDE_PATH (the driver adds their folders) and the working folder (relative paths).
// A header added to an earlier include folder, shadowing one listed, is not seen (as with ccache).
class KeptText {
public:
  KeptText(const std::string& cacheDir, const std::vector<std::string>& args, bool plainMarkers) {
    llvm::SHA256 h;
    static constexpr const char* kBuild = __DATE__ " " __TIME__;  // this file's code makes the text
    h.update(kBuild);
    llvm::SmallString<256> cwd;
    llvm::sys::fs::current_path(cwd);
    h.update(cwd);
    h.update(llvm::StringRef("\0", 1));
    for (const auto& a : args) {
      h.update(a);
      h.update(llvm::StringRef("\0", 1));
    }
    h.update(plainMarkers ? "plain" : "marked");
    // The driver adds these folders to the include path (research models keep headers there).
    for (const char* var : {"CPATH", "CPLUS_INCLUDE_PATH"}) {
      const char* value = std::getenv(var);
      h.update(llvm::StringRef("\0", 1));
      h.update(value ? value : "");
    }
    path_ = cacheDir + "/preprocessed/" + llvm::toHex(h.final(), /*LowerCase=*/true).substr(0, 32);
  }

  // The kept text, if every file it was made from is as it was.
  std::optional<std::string> find() const {
    auto kept = support::readInputFile(path_, /*nullTerminated=*/false);
    llvm::StringRef rest;
    if (!kept || !support::stampsHold((*kept)->getBuffer(), kTextFollows, &rest))
      return std::nullopt;  // changed files, or damaged
    return rest.str();
  }

  // When the preprocessor began: files changed after `started` less a timestamp step are not kept.
  void begin() { started_ = nowNs(); }

  void keep(const std::vector<std::string>& files, const std::string& text) const {
    std::optional<std::string> out = support::stampLines(files, started_ - 20'000'000);
    if (!out)
      return;  // a file gone meanwhile, or just written
    *out += kTextFollows;
    *out += text;
    llvm::sys::fs::create_directories(llvm::sys::path::parent_path(path_));
    support::writeCacheFile(path_, *out);  // failing only costs the next run a preprocess
  }

private:
  static constexpr llvm::StringLiteral kTextFollows = "// lcjit: the preprocessed text follows\n";
  static int64_t nowNs() {
    struct timespec ts {};
    ::clock_gettime(CLOCK_REALTIME, &ts);
    return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  }
  std::string path_;
  int64_t started_ = 0;
};

// Every override names a value the model has: a #define of its own files (not one that takes
// arguments), or one the caller sets (a .vset value).
llvm::Error checkOverrides(const PreprocessOptions& options, const RecordingFS& fs) {
  std::string problems;
  for (const auto& [name, value] : options.overrides) {
    const bool elsewhere = std::find(options.overridableElsewhere.begin(), options.overridableElsewhere.end(), name) !=
                           options.overridableElsewhere.end();
    if (fs.functionLike().count(name))
      problems += "error: -D " + name + ": the model's " + name + " is a macro with arguments; -D sets a value\n";
    else if (!fs.defined().count(name) && !elsewhere) {
      std::string names;
      for (const std::string& n : fs.defined())
        if (!fs.functionLike().count(n)) names += (names.empty() ? "" : ", ") + n;
      std::string values;
      for (const std::string& n : options.overridableElsewhere) values += (values.empty() ? "" : ", ") + n;
      problems += "error: -D " + name + ": the model has no #define " + name +
                  (options.overridableElsewhere.empty() ? "" : " and no .vset or .tset value " + name) + "; it has " +
                  (names.empty() ? "no #define" : "#define " + names) + (values.empty() ? "" : "; .vset and .tset values " + values) +
                  "\n";
    }
  }
  if (problems.empty()) return llvm::Error::success();
  problems.pop_back();
  return llvm::createStringError(problems);
}

}  // namespace

llvm::Expected<std::string> preprocess(const std::string& lsystemPath, const PreprocessOptions& options) {
  if (!options.mainText) {
    auto probe = support::readInputFile(lsystemPath);
    if (!probe)
      return llvm::createStringError(lsystemPath + ": error: cannot open file: " + probe.getError().message());
  }

  std::vector<std::string> args = baseArguments(options.languageStandard);
  for (const auto& d : options.includeDirs) {
    args.push_back("-I");
    args.push_back(d);
  }
  // After the model's own directories, like lpfg's -I $LPFGRESOURCES/include; system
  // directories, so that their headers stay #include lines.
  if (!options.runtimeIncludeDir.empty()) {
    if (!options.cacheDir.empty())
      if (auto image = macroImageDir(options.runtimeIncludeDir, options.cacheDir, options.prebuiltDir, options.languageStandard)) {
        args.push_back("-isystem");
        args.push_back(*image);
      }
    args.push_back("-isystem");
    args.push_back(options.runtimeIncludeDir);
  }
  for (const auto& [name, value] : options.defines) {
    args.push_back("-D");
    args.push_back(value.empty() ? name : name + "=" + value);
  }
  args.push_back(lsystemPath);
  std::optional<KeptText> kept;
  if (!options.cacheDir.empty() && !options.mainText && options.overrides.empty()) {
    kept.emplace(options.cacheDir, args, options.plainMarkers);
    if (std::optional<std::string> text = kept->find())
      return std::move(*text);
    kept->begin();
  }
  auto run = runPreprocessor(args, options.mainText, /*macros=*/false, &options);
  if (!run)
    return run.takeError();
  if (auto e = checkOverrides(options, *run->fs))
    return std::move(e);
  std::string text = postProcess(run->printed, *run->fs, options.plainMarkers);
  if (kept)
    kept->keep(run->fs->openedFiles(), text);
  return text;
}

// ---- columns as written

namespace {
std::string absolutePath(llvm::StringRef file) {
  llvm::SmallString<256> path(file);
  llvm::sys::fs::make_absolute(path);
  llvm::sys::path::remove_dots(path, /*remove_dot_dot=*/true);
  return std::string(path);
}
bool isIdentifierChar(char c) { return std::isalnum((unsigned char)c) || c == '_'; }
}  // namespace

void OriginalColumns::build() const {
  std::map<std::string, std::vector<std::string>> originals;  // absolute path -> its lines
  auto originalLines = [&](const std::string& file) -> const std::vector<std::string>& {
    auto it = originals.find(file);
    if (it != originals.end()) return it->second;
    std::vector<std::string> lines;
    if (auto buffer = support::readInputFile(file)) {
      llvm::StringRef rest = (*buffer)->getBuffer();
      while (!rest.empty()) {
        auto [l, r] = rest.split('\n');
        lines.push_back(l.rtrim('\r').str());
        rest = r;
      }
    }
    return originals.emplace(file, std::move(lines)).first->second;
  };
  std::string file;
  unsigned lineNo = 0;
  llvm::StringRef rest = text_;
  while (!rest.empty()) {
    auto [printed, r] = rest.split('\n');
    rest = r;
    unsigned n;
    std::string f;
    if (parseLineMarker(printed, n, f)) {
      file = absolutePath(f);
      lineNo = n;
      continue;
    }
    const unsigned at = lineNo++;
    if (file.empty() || printed.empty() || printed.starts_with("#")) continue;
    const std::vector<std::string>& lines = originalLines(file);
    if (at == 0 || at > lines.size()) continue;
    llvm::StringRef original = lines[at - 1];
    if (original == printed) continue;
    changed_[{file, at}] = {original.str(), printed.str()};
  }
}

namespace {
// Where printed[at] (in printed[p0, p1)) is in original[o0, o1): the common start and end of
// the two ranges match one to one, then the longest common run between them (of 2 characters at
// least), on either side of which the same is done again. Unmatched text (the rest of a macro's
// expansion) is at the start of what it replaced, not inside an identifier.
size_t alignedIndex(llvm::StringRef o, llvm::StringRef p, size_t o0, size_t o1, size_t p0, size_t p1, size_t at) {
  for (; o0 < o1 && p0 < p1 && o[o0] == p[p0]; ++o0, ++p0)
    if (at == p0) return o0;
  for (; o1 > o0 && p1 > p0 && o[o1 - 1] == p[p1 - 1]; --o1, --p1)
    if (at == p1 - 1) return o1 - 1;
  size_t best = 0, bestO = 0, bestP = 0;
  const size_t n = o1 - o0, m = p1 - p0;
  if (n > 0 && m > 0 && n * m <= 1000000) {
    std::vector<unsigned> previous(m + 1, 0), row(m + 1, 0);
    for (size_t i = 1; i <= n; ++i) {
      for (size_t j = 1; j <= m; ++j) {
        row[j] = o[o0 + i - 1] == p[p0 + j - 1] ? previous[j - 1] + 1 : 0;
        if (row[j] > best) best = row[j], bestO = o0 + i - row[j], bestP = p0 + j - row[j];
      }
      std::swap(previous, row);
    }
  }
  if (best < 2) {
    while (o0 > 0 && o0 < o.size() && isIdentifierChar(o[o0 - 1]) && isIdentifierChar(o[o0])) --o0;
    return o0;
  }
  if (at >= bestP && at < bestP + best) return bestO + (at - bestP);
  return at < bestP ? alignedIndex(o, p, o0, bestO, p0, bestP, at) : alignedIndex(o, p, bestO + best, o1, bestP + best, p1, at);
}
}  // namespace

unsigned OriginalColumns::column(llvm::StringRef file, unsigned line, unsigned column) const {
  std::call_once(built_, [this] { build(); });
  if (column == 0 || changed_.empty()) return column;
  auto it = changed_.find({absolutePath(file), line});
  if (it == changed_.end()) return column;
  llvm::StringRef o = it->second.original, p = it->second.printed;
  const size_t at = column - 1;
  if (at >= p.size()) return unsigned(at - p.size() + o.size() + 1);  // past the end (a missing ';')
  return unsigned(alignedIndex(o, p, 0, o.size(), 0, p.size(), at) + 1);
}

std::string OriginalColumns::diagnostics(llvm::StringRef text) const {
  std::call_once(built_, [this] { build(); });
  if (changed_.empty()) return text.str();
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    auto [line, rest] = text.split('\n');
    const bool hadNewline = line.size() < text.size();
    text = rest;
    // FILE:LINE:COL: at the start of the line; FILE may itself hold a ':'.
    bool mapped = false;
    for (size_t colon = line.find(':'); colon != llvm::StringRef::npos && !mapped; colon = line.find(':', colon + 1)) {
      llvm::StringRef after = line.drop_front(colon + 1);
      unsigned lineNo, column;
      llvm::StringRef digits = after.take_while([](char c) { return std::isdigit((unsigned char)c); });
      if (digits.empty() || digits.getAsInteger(10, lineNo)) continue;
      after = after.drop_front(digits.size());
      if (!after.consume_front(":")) continue;
      llvm::StringRef columnDigits = after.take_while([](char c) { return std::isdigit((unsigned char)c); });
      if (columnDigits.empty() || columnDigits.getAsInteger(10, column) || !after.drop_front(columnDigits.size()).starts_with(":"))
        continue;
      llvm::StringRef file = line.take_front(colon);
      out += (file + ":" + digits + ":" + std::to_string(this->column(file, lineNo, column))).str();
      out += after.drop_front(columnDigits.size());
      mapped = true;
    }
    if (!mapped) out += line;
    if (hadNewline) out += '\n';
  }
  return out;
}

} // namespace lcjit::frontend
