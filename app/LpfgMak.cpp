// See LpfgMak.h.
#include "app/LpfgMak.h"
#include "runtime/files/InputFile.h"

#include <llvm/Support/CommandLine.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/StringSaver.h>
#include <llvm/Support/Program.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace lcjit::app {
namespace fs = std::filesystem;

namespace {

}  // namespace

bool isCppSource(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  return ext == ".cpp" || ext == ".cc" || ext == ".cxx" || ext == ".C" || ext == ".c++";
}

llvm::Expected<std::optional<LpfgMakBuild>> readLpfgMak(const std::string& modelDir) {
  fs::path dir = fs::absolute(modelDir.empty() ? "." : modelDir).lexically_normal();
  fs::path makefile = dir / "lpfg.mak";
  if (!fs::exists(makefile)) return std::nullopt;
  // make would wait for ever on a FIFO (and read /dev/zero until its time is up).
  if (auto readable = runtime::readInputFile(makefile.string()); !readable)
    return llvm::createStringError(makefile.string() + ": error: cannot read it: " + readable.getError().message());
  auto make = llvm::sys::findProgramByName("make");
  if (!make) return llvm::createStringError(makefile.string() + ": error: lcjit reads lpfg.mak with make, which is not installed");

  // make -n in a scratch folder that links everything of the model's and has the lsys.ii lpfg's
  // translator would have made: -B prints every command, up to date or not.
  llvm::SmallString<128> scratch;
  if (auto ec = llvm::sys::fs::createUniqueDirectory("lcjit-lpfgmak", scratch))
    return llvm::createStringError(makefile.string() + ": error: no scratch folder to read it in: " + ec.message());
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{scratch.str().str()};
  // The dummy lsys.ii first, and no link where it is: writing through a link to the model's own
  // lsys.ii (left by lpfg) would change the user's file.
  std::ofstream(fs::path(cleanup.dir) / "lsys.ii") << "\n";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    fs::path link = fs::path(cleanup.dir) / entry.path().filename();
    if (!fs::exists(fs::symlink_status(link))) fs::create_symlink(entry.path(), link, ec);
  }
  std::string out = cleanup.dir + "/make.out", err = cleanup.dir + "/make.err";
  std::optional<llvm::StringRef> redirects[] = {std::nullopt, llvm::StringRef(out), llvm::StringRef(err)};
  std::string errorText;
  int status = llvm::sys::ExecuteAndWait(*make, {*make, "-n", "-B", "-s", "-C", cleanup.dir, "-f", "lpfg.mak", "lsys.so"},
                                         std::nullopt, redirects, /*SecondsToWait=*/30, 0, &errorText);
  if (status != 0) {
    std::ifstream e(err);
    std::stringstream text;
    text << e.rdbuf();
    return llvm::createStringError(makefile.string() + ": error: make -n could not read it" +
                 (text.str().empty() ? (errorText.empty() ? "" : ": " + errorText) : ":\n" + text.str()));
  }

  LpfgMakBuild build;
  auto absolute = [&](const std::string& p) { return (fs::path(p).is_absolute() ? fs::path(p) : dir / p).lexically_normal().string(); };
  auto addOnce = [](auto& list, const auto& item) {
    for (const auto& x : list)
      if (x == item) return;
    list.push_back(item);
  };
  std::ifstream commands(out);
  for (std::string line; std::getline(commands, line);) {
    // The words of the command as sh reads them (quotes, backslashes).
    llvm::BumpPtrAllocator arena;
    llvm::StringSaver saver(arena);
    llvm::SmallVector<const char*, 32> argv;
    llvm::cl::TokenizeGNUCommandLine(line, saver, argv);
    const std::vector<std::string> words(argv.begin(), argv.end());
    bool compiles = false;
    for (const auto& w : words) compiles = compiles || w == "-c";
    if (!compiles) continue;  // the link, or anything else: nothing for lcjit
    for (size_t i = 1; i < words.size(); ++i) {
      const std::string& w = words[i];
      if (w == "-I" && i + 1 < words.size()) addOnce(build.includeDirs, absolute(words[++i]));
      else if (w.rfind("-I", 0) == 0 && w.size() > 2) addOnce(build.includeDirs, absolute(w.substr(2)));
      else if (w.rfind("-D", 0) == 0 && w.size() > 2) {
        std::string d = w.substr(2);
        size_t eq = d.find('=');
        addOnce(build.defines, eq == std::string::npos ? std::make_pair(d, std::string())
                                                       : std::make_pair(d.substr(0, eq), d.substr(eq + 1)));
      } else if (w.rfind("-std=", 0) == 0) {
        // C++11 and C++14 are what lcjit compiles anyway (kDefaultLanguageStandard); newer ones
        // are asked for.
        std::string std = w.substr(5);
        bool older = std.find("++98") != std::string::npos || std.find("++03") != std::string::npos ||
                     std.find("++0x") != std::string::npos || std.find("++11") != std::string::npos ||
                     std.find("++1y") != std::string::npos || std.find("++14") != std::string::npos;
        build.languageStandard = older ? "" : std;
      } else if (w == "-o" || w == "-MF" || w == "-include") {
        ++i;  // an argument that is no source
      } else if (isCppSource(w)) {
        addOnce(build.sources, absolute(w));
      }
    }
  }
  return build;
}

}  // namespace lcjit::app
