// What the options ask for (Modes.h).
#include "app/cli/Modes.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/common/PlainErrors.h"
#include "app/common/RunRecord.h"
#include "app/session/Languages.h"

namespace lcjit::app {

namespace fs = std::filesystem;

bool haveDisplay() {
  // A build without the window behaves as with no display.
  return LCJIT_HAVE_WINDOW && (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"));
}

std::string shownIn(const std::string& model) {
  // A build without pictures shows the model as its string.
  return fs::path(model).stem().string() + (LCJIT_HAVE_RENDERING ? ".png" : ".str");
}

std::string modelOf(const std::vector<std::string>& inputs) {
  std::string model;
  for (const std::string& in : inputs)
    if (languageOf(in)) model = in;  // a grammar language's model file (the last one)
  return model;
}

bool opensWindow(const Options& o) {
  return !o.batch && o.outs.empty() && haveDisplay() && !o.emitCpp && !o.compileOnly;
}

std::string cacheInModelFolder(const std::vector<std::string>& inputs) {
  std::string model = modelOf(inputs);
  return model.empty() ? "" : (fs::path(model).parent_path() / ".lcjit-cache").string();
}

std::string settleOptions(Options& o) {
  if (o.inputs.empty()) {
    for (const char* f : {"tree.l", "tree.v", "tree.mat"}) o.inputs.push_back(examplesDir() + "/" + f);
    if (o.outs.empty()) o.outs = {shownIn("tree.l")};
    o.batch = true;
    if (!o.quiet)
      std::fprintf(stderr, "lcjit: no model given; %s the built-in example %s into %s\n",
                   LCJIT_HAVE_RENDERING ? "rendering" : "deriving", o.inputs[0].c_str(), fs::absolute(o.outs[0]).c_str());
  }
  for (std::string& dir : o.includeDirs) dir = fs::absolute(dir).lexically_normal().string();
  std::string cacheDir;
  if (o.lab) {
    // Everything the session writes goes to the model's folder: work there, cache there.
    for (std::string& in : o.inputs) in = fs::absolute(in).lexically_normal().string();
    const std::string model = modelOf(o.inputs);
    if (!model.empty()) {
      fs::current_path(fs::path(model).parent_path());
      cacheDir = cacheInModelFolder(o.inputs);
    }
    if (o.rmode.empty()) o.rmode = "cont";
    if (!o.batch && !haveDisplay()) {  // no display: keep writing MODEL.png instead
      o.watch = o.batch = true;
      if (o.outs.empty() && !model.empty()) o.outs = {shownIn(model)};
    }
  }
  return cacheDir;
}

bool labWindow(const Options& o) { return o.lab && !o.batch && haveDisplay() && !modelOf(o.inputs).empty(); }

CompileTiers compileTiers(const Options& o, bool window) {
  CompileTiers t;
  if (o.optLevel) t.optLevel = *o.optLevel;
  if (o.debugger) {  // one tier, each statement where the debugger expects it
    if (!o.optLevel) t.optLevel = 0;
  } else if ((o.watch || window) && !o.optLevel) {
    // Live coding: a quick -O0 build first, then -O2 compiled in the background and swapped in.
    t.optLevel = 0, t.betterTier = 2;
  } else if (!o.optLevel && !o.compileOnly && !o.emitCpp) {
    // A batch run: -O1 code, and -O2 compiled in the background once the run has shown it is
    // long, or taken from the cache if an earlier run compiled it (Batch.h).
    t.betterTier = 2;
  }
  return t;
}

llvm::Expected<ModelFiles> modelFiles(const Options& o) {
  auto files = classifyInputs(o.inputs);
  if (!files) return files.takeError();
  files->includeDirs.insert(files->includeDirs.begin(), o.includeDirs.begin(), o.includeDirs.end());
  for (const std::string& d : o.overrides) {
    size_t eq = d.find('=');
    if (eq == 0 || eq == std::string::npos) return llvm::createStringError("lcjit: -D " + d + ": give NAME=VALUE");
    files->overrides.emplace_back(d.substr(0, eq), d.substr(eq + 1));
  }
  files->run = o.run;
  return files;
}

llvm::Expected<std::unique_ptr<Session>> openSession(const Options& o, const ModelFiles& files,
                                                     const std::string& cacheDir, bool window) {
  auto session = Session::create(cacheDir, files.languageStandard, o.debugger);
  if (!session) return llvm::createStringError("lcjit: " + llvm::toString(session.takeError()));
  Session& s = **session;
  if (!s.cacheWarning().empty()) std::fprintf(stderr, "lcjit: warning: %s\n", s.cacheWarning().c_str());
  s.setLimits(o.limits());
  s.setEnsembleMember(o.seed);
  Session::EnvironmentSettings env;
  env.cleanEA20 = o.cleanEA20;
  env.program.answerSeconds = o.environmentTimeout;
  env.start = !o.compileOnly && !o.emitCpp;
  if (o.verbose) env.program.log = [](const std::string& line) { std::fprintf(stderr, "lcjit: %s\n", line.c_str()); };
  s.setEnvironmentSettings(env);
  s.setQuickLevelBySize(!o.optLevel);
  // Edits are coming: every compile sets up the next one's front end ahead.
  const bool watchedWindow = window && !o.rmode.empty() && o.rmode != "expl";
  s.setEditedLive(o.watch || watchedWindow);
  // The window (and a sandboxed window's child, which draws for it) shows a model without colour
  // files in colours (docs/editors.md); batch pictures stay lpfg's, which the comparison with
  // lpfg relies on.
  s.setLcjitColours(window || o.replyFd >= 0);
  return session;
}

void reportLoadError(const std::string& message, const Options& o, const ModelFiles& files, Session* session,
                     const PhaseTimes& times) {
  std::string text = withSourceLines(message);
  std::fprintf(stderr, "%s\n", o.lab ? inPlainLanguage(text).c_str() : text.c_str());
  if (!o.runRecord.empty() && !o.watch)
    if (auto e = writeRunRecord(o.runRecord, files, session, {message, o.seed}, times))
      std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
}

}  // namespace lcjit::app
