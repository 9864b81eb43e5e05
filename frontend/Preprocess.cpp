// In-process `clang -E` for .l files. Angled includes are hidden from the preprocessor (turned
// into `#pragma <...>` lines of the same length, which -E prints verbatim) and restored after.
#include "frontend/Preprocess.h"

#include <clang/Basic/Diagnostic.h>
#include <clang/Basic/DiagnosticOptions.h>
#include <clang/Basic/SourceManager.h>
#include <clang/Frontend/CompilerInstance.h>
#include <clang/Frontend/CompilerInvocation.h>
#include <clang/Frontend/FrontendAction.h>
#include <clang/Frontend/Utils.h>
#include <clang/Lex/Preprocessor.h>
#include <clang/Lex/PreprocessorOptions.h>

#include <llvm/ADT/StringRef.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/VirtualFileSystem.h>
#include <llvm/Support/raw_ostream.h>
#include <llvm/TargetParser/Host.h>

#include <cctype>
#include <map>
#include <mutex>

namespace lcjit::frontend {

namespace {

llvm::Error makeError(const llvm::Twine& msg) {
  return llvm::make_error<llvm::StringError>(msg, llvm::inconvertibleErrorCode());
}

bool isHSpace(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

// `#include <x>` -> `#pragma  <x>`: "include" and "pragma " have the same length, so sizes,
// line and column numbers stay exactly as on disk (clang checks file sizes against stat()).
// `#include "lpfgall.h"` is lpfg's header too and goes the same way.
void hideAngledIncludes(std::string& text) {
  size_t pos = 0;
  bool continued = false; // previous line ended in a backslash: this line is not a directive
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos)
      eol = text.size();
    if (!continued) {
      size_t i = pos;
      while (i < eol && isHSpace(text[i]))
        ++i;
      if (i < eol && text[i] == '#') {
        ++i;
        while (i < eol && isHSpace(text[i]))
          ++i;
        if (text.compare(i, 7, "include") == 0) {
          size_t j = i + 7;
          while (j < eol && isHSpace(text[j]))
            ++j;
          if (j < eol && text[j] == '<') {
            text.replace(i, 7, "pragma ");
          } else if (text.compare(j, 11, "\"lpfgall.h\"") == 0) {
            // lpfg's own header, as many models write it: the same as <lpfgall.h> (same length).
            text.replace(i, 7, "pragma ");
            text[j] = '<';
            text[j + 10] = '>';
          }
        }
      }
    }
    size_t e = eol;
    if (e > pos && text[e - 1] == '\r')
      --e;
    continued = e > pos && text[e - 1] == '\\';
    pos = eol + 1;
  }
}

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

// Serves every file clang reads with its angled includes hidden, and remembers the original
// text of each for restoring indentation afterwards.
class HidingFS : public llvm::vfs::ProxyFileSystem {
public:
  explicit HidingFS(llvm::IntrusiveRefCntPtr<llvm::vfs::FileSystem> fs) : ProxyFileSystem(std::move(fs)) {}

  llvm::ErrorOr<std::unique_ptr<llvm::vfs::File>> openFileForRead(const llvm::Twine& path) override {
    auto f = ProxyFileSystem::openFileForRead(path);
    if (!f)
      return f;
    auto st = (*f)->status();
    if (!st || !st->isRegularFile())
      return f;
    std::string name = path.str();
    auto buf = (*f)->getBuffer(name, st->getSize(), false, false);
    if (!buf)
      return buf.getError();
    std::string text = (*buf)->getBuffer().str();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      originals_[name] = text;
    }
    hideAngledIncludes(text);
    return std::unique_ptr<llvm::vfs::File>(new MemFile(*st, std::move(text)));
  }

  const std::string* original(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = originals_.find(name);
    return it == originals_.end() ? nullptr : &it->second;
  }

private:
  mutable std::mutex mutex_;
  std::map<std::string, std::string> originals_;
};

// Collects errors (and the notes attached to them) as `FILE:LINE:COL: error: MESSAGE` lines.
class DiagCollector : public clang::DiagnosticConsumer {
public:
  void HandleDiagnostic(clang::DiagnosticsEngine::Level level, const clang::Diagnostic& info) override {
    clang::DiagnosticConsumer::HandleDiagnostic(level, info);
    const char* kind = nullptr;
    switch (level) {
    case clang::DiagnosticsEngine::Error:
    case clang::DiagnosticsEngine::Fatal:
      kind = "error";
      lastWasError_ = true;
      break;
    case clang::DiagnosticsEngine::Note:
      if (!lastWasError_)
        return;
      kind = "note";
      break;
    default:
      lastWasError_ = false;
      return;
    }
    llvm::raw_string_ostream os(text);
    if (info.getLocation().isValid() && info.hasSourceManager()) {
      const clang::SourceManager& sm = info.getSourceManager();
      clang::PresumedLoc pl = sm.getPresumedLoc(sm.getFileLoc(info.getLocation()));
      if (pl.isValid())
        os << pl.getFilename() << ':' << pl.getLine() << ':' << pl.getColumn() << ": ";
    }
    llvm::SmallString<256> msg;
    info.FormatDiagnostic(msg);
    os << kind << ": " << msg << '\n';
  }
  std::string text;

private:
  bool lastWasError_ = false;
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
// original whitespace back when its length matches, and turn hidden includes back into
// `#include <...>` lines.
std::string postProcess(const std::string& printed, const HidingFS& fs) {
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
      out += line;
    } else {
      llvm::StringRef l = line;
      if (l.starts_with("#pragma <") && l.rtrim().ends_with(">")) {
        out += "#include ";
        out += l.drop_front(8).rtrim();
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

} // namespace

llvm::Expected<std::string> preprocess(const std::string& lsystemPath, const PreprocessOptions& options) {
  if (!options.mainText) {
    auto probe = llvm::MemoryBuffer::getFile(lsystemPath, /*IsText=*/true);
    if (!probe)
      return makeError("error: cannot open L-system file '" + lsystemPath + "': " + probe.getError().message());
  }

  std::vector<std::string> args = {"-triple",
                                   llvm::sys::getDefaultTargetTriple(),
                                   "-E",
                                   "-x",
                                   "c++",
                                   "-std=gnu++14",
                                   "-w",
                                   // Same predefined macros as the C++ compile (__GNUC__, __EXCEPTIONS).
                                   "-fgnuc-version=4.2.1",
                                   "-fcxx-exceptions",
                                   "-fexceptions",
                                   // Angled includes are never resolved here.
                                   "-nostdsysteminc",
                                   "-nobuiltininc"};
  for (const auto& d : options.includeDirs) {
    args.push_back("-I");
    args.push_back(d);
  }
  for (const auto& [name, value] : options.defines) {
    args.push_back("-D");
    args.push_back(value.empty() ? name : name + "=" + value);
  }
  args.push_back(lsystemPath);
  std::vector<const char*> argv;
  for (const auto& a : args)
    argv.push_back(a.c_str());

  DiagCollector dc;
  auto inv = std::make_shared<clang::CompilerInvocation>();
  {
    auto diags = clang::CompilerInstance::createDiagnostics(new clang::DiagnosticOptions, &dc, false);
    if (!clang::CompilerInvocation::CreateFromArgs(*inv, argv, *diags) || dc.getNumErrors() != 0)
      return makeError(dc.text.empty() ? std::string("error: invalid preprocessor options") : dc.text);
  }
  inv->getFrontendOpts().DisableFree = false;
  inv->getDiagnosticOpts().ShowCarets = false;
  if (options.mainText)  // the SourceManager takes ownership of the buffer
    inv->getPreprocessorOpts().addRemappedFile(lsystemPath,
                                               llvm::MemoryBuffer::getMemBufferCopy(*options.mainText, lsystemPath).release());

  clang::CompilerInstance ci;
  ci.setInvocation(inv);
  ci.createDiagnostics(&dc, false);
  llvm::IntrusiveRefCntPtr<HidingFS> fs(new HidingFS(llvm::vfs::getRealFileSystem()));
  ci.createFileManager(fs);

  std::string printed;
  PrintToStringAction action(printed);
  bool ok = ci.ExecuteAction(action);
  if (!ok || dc.getNumErrors() != 0) {
    std::string text = dc.text.empty() ? "error: preprocessing '" + lsystemPath + "' failed\n" : dc.text;
    while (!text.empty() && text.back() == '\n')
      text.pop_back();
    return makeError(text);
  }
  return postProcess(printed, *fs);
}

} // namespace lcjit::frontend
