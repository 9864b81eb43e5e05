// The REPL (see Repl.h).
//
// One thread does the work: the line reader hands over whole lines, and between keys the loop
// polls the watched files and draws the :view window (ReplView.h). So the model (Session,
// Engine) is only touched from this thread and needs no lock. The price: while a command runs
// (a long :run), the window does not redraw.
#include "repl/Repl.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include "runtime/turtle/Drawing.h"
#include "runtime/Engine.h"
#include "app/session/FileMonitor.h"
#include "app/common/Frame.h"
#include "runtime/Functions.h"
#include "runtime/WindowInput.h"
#include "repl/LineReader.h"
#include "app/common/PlainErrors.h"
#include "repl/ReplText.h"
#include "app/common/ModuleReport.h"
#include "app/common/ProfileReport.h"
#include "app/common/Progress.h"
#include <llvm/ADT/ScopeExit.h>
#include "app/session/Session.h"
#include "repl/ReplView.h"
#include "support/Elapsed.h"

namespace lcjit::repl {
// The REPL drives the application's Session and reuses its modes' pieces.
using namespace lcjit::app;

namespace {

using support::Clock;
using Args = std::vector<std::string>;

constexpr const char* kPrompt = "lcjit> ";
constexpr const char* kMorePrompt = "...> ";  // C++ whose brackets are still open


std::string plural(size_t n, const std::string& word) { return std::to_string(n) + " " + word + (n == 1 ? "" : "s"); }

std::optional<long> parseInt(const std::string& s) {
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end || errno) return std::nullopt;
  return v;
}

std::optional<float> parseFloat(const std::string& s) {
  char* end = nullptr;
  float v = std::strtof(s.c_str(), &end);
  if (s.empty() || *end || !std::isfinite(v)) return std::nullopt;
  return v;
}

class Repl {
 public:
  Repl(std::unique_ptr<Session> session, const ReplOptions& options)
      : session_(std::move(session)),
        options_(options),
        reader_([this](const std::string& line) { onLine(line); },
                [this](std::string_view line, size_t cursor) { return complete(line, cursor); }),
        frames_(options.width, options.height) {
    hooks_.outputFrame = [this](const char* path) { report(frames_.write(path, engine(), session_->drawing())); };
    hooks_.print = [this](const char* text) {  // the model's output starts on a line of its own
      if (progress_) progress_->clear();
      std::fputs(text, stdout);
    };
  }

  int run(const Args& inputs) {
    reader_.setPrompt(kPrompt);
    if (reader_.interactive())
      std::printf("lcjit repl: :help lists the commands; C++ typed here runs in the model; Ctrl-D leaves\n");
    if (!inputs.empty()) {
      auto files = classifyInputs(inputs);
      if (!files) {
        report(files.takeError());
      } else {
        files_ = *files;
        report(load(ReloadParts::all(), 0, "loaded"));
      }
    }
    if (options_.lab) {  // the model on screen, derived to its end as lpfg opens it, and every
                         // save of its files reloads it (to the step it is at)
      report(cmdWatch({"on"}));
      if (session_->loaded()) {
        report(cmdRun({}));
        report(cmdView({}));
      }
    }
    while (!quit_) {
      std::fflush(stdout);  // all of it shows before the wait: a script may wait for it
      // A shown window is drawn between keys; watched files are looked at ten times a second.
      auto status = reader_.poll(view_.isOpen() ? 0 : watching_ ? 100 : -1);
      if (status == repl::LineReader::Status::End) {
        if (!pendingCpp_.empty()) report(llvm::createStringError("error: the input ended inside C++ with unclosed brackets"));
        break;
      }
      if (status == repl::LineReader::Status::Interrupted) {
        pendingCpp_.clear();
        reader_.setPrompt(kPrompt);
      }
      view_.inputConsumed();
      if (quit_) break;
      pollWatch();
      pumpView();
    }
    view_.close();
    return failed_ && !reader_.interactive() ? 1 : 0;
  }

 private:
  struct Command {
    const char* name;
    const char* args;
    const char* help;
    llvm::Error (Repl::*run)(const Args&);
    bool needsModel;
  };

  static const std::vector<Command>& commands() {
    static const std::vector<Command> list = {
        {":load", "[files] model.l",
         "load a model with lpfg's input files (.v .map .mat .vset .func …); a failed load keeps the model loaded",
         &Repl::cmdLoad, false},
        {":reload", "", "re-read the model's files, recompile, and re-run to the current step", &Repl::cmdReload, false},
        {":step", "[N]", "derive N more steps (1)", &Repl::cmdStep, true},
        {":run", "", "derive to the end", &Repl::cmdRun, true},
        {":rewind", "", "back to the axiom (step 0)", &Repl::cmdRewind, true},
        {":string", "[--module NAME…] [--from I] [--count N]",
         "the string, one module a line with its index; a screenful at a time on a terminal", &Repl::cmdString, true},
        {":module", "I", "the parameters of the string's module I", &Repl::cmdModule, true},
        {":set", "[NAME VALUE]",
         "give a .vset parameter or a tunable value a value and re-run to the current step; alone: list them",
         &Repl::cmdSet, true},
        {":time", "", "time a whole derivation, and the interpretation of its string", &Repl::cmdTime, true},
        {":profile", "[N]",
         "derive the whole model and interpret it, counting each rule: the N (20) hottest, with applications and "
         "milliseconds",
         &Repl::cmdProfile, true},
        {":save", "FILE",
         "write the string (.str .strb), a picture (.png .jpg .bmp) or geometry (.obj .ply .stl .gltf .glb .svg .ps .eps .pov)",
         &Repl::cmdSave, true},
        {":group", "[N]", "derive with production group N from the next step; alone: list the groups", &Repl::cmdGroup,
         true},
        {":productions", "", "the model's rules: line, kind, group, predecessor", &Repl::cmdProductions, true},
        {":watch", "[on|off]", "reload when one of the model's files changes", &Repl::cmdWatch, false},
        {":view", "[close]", "show the model in a window that follows the commands; the prompt stays", &Repl::cmdView,
         true},
        {":help", "[COMMAND]", "this list", &Repl::cmdHelp, false},
        {":quit", "", "leave (Ctrl-D too)", &Repl::cmdQuit, false},
    };
    return list;
  }

  // ---- input

  void onLine(const std::string& line) {
    if (!pendingCpp_.empty()) {
      pendingCpp_ += '\n';
      pendingCpp_ += line;
      if (!repl::isCompleteCpp(pendingCpp_)) return;
      std::string cpp = std::move(pendingCpp_);
      pendingCpp_.clear();
      reader_.setPrompt(kPrompt);
      evaluate(cpp);
    } else {
      size_t first = line.find_first_not_of(" \t");
      if (first == std::string::npos) return;
      if (line[first] == ':') {
        command(line.substr(first));
      } else if (!repl::isCompleteCpp(line)) {
        pendingCpp_ = line;
        reader_.setPrompt(kMorePrompt);
      } else {
        evaluate(line);
      }
    }
    std::fflush(stdout);
  }

  void command(const std::string& line) {
    auto words = repl::splitWords(line);
    if (!words) return report(words.takeError());
    const std::string& name = words->front();
    auto it = std::find_if(commands().begin(), commands().end(), [&](const Command& c) { return name == c.name; });
    if (it == commands().end()) return report(llvm::createStringError("error: unknown command '" + name + "' (:help lists them)"));
    if (it->needsModel && !session_->loaded()) return report(llvm::createStringError("error: no model is loaded (:load [files] model.l)"));
    report((this->*(it->run))(Args(words->begin() + 1, words->end())));
  }

  void evaluate(const std::string& cpp) {
    if (!session_->loaded())
      return report(llvm::createStringError("error: no model is loaded: C++ typed here is compiled against one (:load [files] model.l)"));
    repl::LineReader::setInterruptible(&engine());  // Ctrl-C stops C++ that does not return
    auto value = session_->evaluate(cpp);
    repl::LineReader::setInterruptible(nullptr);
    engine().clearCancel();  // an interrupt of the input must not cancel the next step
    repl::LineReader::takeInterrupt();  // … nor count as one of the prompt
    if (!value) return report(value.takeError());
    if (!value->empty()) std::printf("%s\n", value->c_str());
    view_.markChanged();  // a statement may have changed what the model draws
  }

  repl::Completion complete(std::string_view line, size_t cursor) const {
    static const runtime::ModuleTable builtins;
    repl::CompletionSources s;
    for (const Command& c : commands()) s.commands.push_back(c.name);
    const runtime::ModuleTable& table = session_->loaded() ? session_->engine().modules() : builtins;
    for (size_t id = 0; id < table.count(); ++id) s.modules.push_back(table.info((__lc_ModuleId)id).name);
    if (session_->loaded())
      for (int id = 1; id <= session_->functions().size(); ++id)
        if (session_->functions().isParameter(id)) s.parameters.emplace_back(session_->functions().nameOf(id));
    return repl::complete(line, cursor, s);
  }

  void report(llvm::Error e) {
    if (!e) return;
    std::fflush(stdout);  // in order with what was printed before, also when both go to one file
    std::string text = llvm::toString(std::move(e));
    if (options_.lab) text = inPlainLanguage(withSourceLines(text));
    std::fprintf(stderr, "%s\n", text.c_str());
    std::fflush(stderr);
    failed_ = true;
  }

  void warn(const std::string& text) {
    std::fflush(stdout);
    std::fprintf(stderr, "%s\n", text.c_str());
  }

  // ---- the model

  runtime::Engine& engine() { return session_->engine(); }

  // Loads files_ (`parts` of them: see ReloadParts) and, unless `rerunTo` is negative, starts a
  // derivation and derives to step `rerunTo`.
  llvm::Error load(ReloadParts parts, int rerunTo, const char* verb) {
    if (!loadedCurrent_) {
      // The model in memory came from other files (a :load failed): nothing of it carries over.
      parts = ReloadParts::all();
      rerunTo = std::max(rerunTo, 0);
    }
    PhaseTimes times;
    if (auto e = session_->load(files_, options_.optLevel, times, parts)) {
      std::string message = llvm::toString(std::move(e));
      if (session_->loaded()) message += "\nlcjit: keeping the model loaded before (" + loadedFiles_.lsystem + ")";
      return llvm::createStringError(message);
    }
    loadedFiles_ = files_;
    loadedCurrent_ = true;
    std::printf("%s %s\n", verb, files_.lsystem.c_str());
    for (const std::string& w : session_->warnings()) warn(w);
    if (rerunTo >= 0) {
      begin();
      deriveTo(rerunTo);
    }
    view_.markChanged();
    printStatus();
    return llvm::Error::success();
  }

  void begin() {
    engine().setProvenance(true);  // :module tells where a module came from
    engine().begin(hooks_);
    if (engine().faulted()) report(engine().takeFault());  // Start or the axiom: model code
    view_.markChanged();
  }

  // Derives until step `target` or the end of the derivation (then End runs); Ctrl-C stops it.
  void deriveTo(int target) {
    runtime::Engine& e = engine();
    repl::LineReader::setInterruptible(&e);
    app::TerminalProgress shown(::isatty(STDERR_FILENO));
    progress_ = &shown;
    auto noProgress = llvm::make_scope_exit([this] { progress_ = nullptr; });
    const auto t0 = Clock::now();
    while (!e.ended() && e.stepNo() < target) {
      bool more = e.step();
      if (shown.enabled)
        shown.update(support::msSince(t0), [&] { return app::progressText(e.stepNo(), e.derivationLength(), e.moduleCount()); });
      if (repl::LineReader::takeInterrupt()) {
        // Model code that did not return was made to: that ends the derivation, as a fault does.
        if (e.faulted()) report(e.takeFault());
        else std::printf("interrupted\n");
        break;
      }
      if (!more) {
        // A fault in model code stops the run (the string stays as before the step); the REPL
        // says so and goes on.
        if (!e.faulted() && !e.ended()) e.finish();
        if (e.faulted()) report(e.takeFault());
        break;
      }
    }
    repl::LineReader::setInterruptible(nullptr);
    e.clearCancel();
    view_.markChanged();
  }

  void printStatus() {
    runtime::Engine& e = engine();
    bool stopped = e.ended() && e.stepNo() < e.derivationLength();  // Stop() in the model
    std::printf("step %d of %d%s: %s\n", e.stepNo(), e.derivationLength(), stopped ? " (stopped)" : "",
                plural(e.moduleCount(), "module").c_str());
  }

  // ---- commands

  llvm::Error cmdLoad(const Args& args) {
    if (args.empty()) return llvm::createStringError("error: usage: :load [files] model.l");
    auto files = classifyInputs(args);
    if (!files) return files.takeError();
    files_ = *files;
    loadedCurrent_ = false;
    auto e = load(ReloadParts::all(), 0, "loaded");
    if (watching_) watchFiles();  // the new files, also when they did not load: fixing them reloads
    return e;
  }

  llvm::Error cmdReload(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :reload");
    if (files_.lsystem.empty()) return llvm::createStringError("error: nothing to reload (:load [files] model.l)");
    return load(ReloadParts::all(), session_->loaded() ? engine().stepNo() : 0, "reloaded");
  }

  llvm::Error cmdStep(const Args& args) {
    std::optional<long> n = 1;
    if (args.size() == 1) n = parseInt(args[0]);
    if (args.size() > 1 || !n || *n < 1) return llvm::createStringError("error: usage: :step [N], N > 0");
    if (engine().ended())
      return llvm::createStringError("error: the derivation is over (step " + std::to_string(engine().stepNo()) + "); :rewind starts again");
    deriveTo((int)std::min<long>(engine().stepNo() + *n, INT_MAX));
    printStatus();
    return llvm::Error::success();
  }

  llvm::Error cmdRun(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :run");
    deriveTo(INT_MAX);
    printStatus();
    return llvm::Error::success();
  }

  llvm::Error cmdRewind(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :rewind");
    begin();
    printStatus();
    return llvm::Error::success();
  }

  llvm::Error cmdString(const Args& args) {
    const runtime::ModuleTable& table = engine().modules();
    std::set<__lc_ModuleId> only;
    long from = 0, count = -1;
    for (size_t i = 0; i < args.size(); ++i) {
      if (args[i] == "--module") {
        size_t j = i + 1;
        for (; j < args.size() && args[j].rfind("--", 0) != 0; ++j) {
          int id = table.find(args[j]);
          if (id < 0) return llvm::createStringError("error: no module named '" + args[j] + "'");
          only.insert((__lc_ModuleId)id);
        }
        if (j == i + 1) return llvm::createStringError("error: --module needs module names");
        i = j - 1;
      } else if ((args[i] == "--from" || args[i] == "--count") && i + 1 < args.size()) {
        auto n = parseInt(args[i + 1]);
        if (!n || *n < 0) return llvm::createStringError("error: " + args[i] + " needs a number, not '" + args[i + 1] + "'");
        (args[i] == "--from" ? from : count) = *n;
        ++i;
      } else {
        return llvm::createStringError("error: usage: :string [--module NAME…] [--from I] [--count N]");
      }
    }
    const runtime::ModuleBuffer& s = engine().string();
    size_t total = engine().moduleCount();
    int width = (int)std::to_string(total ? total - 1 : 0).size();
    // On a terminal, without --count, a screenful at a time (less one line for the question).
    bool page = reader_.interactive() && count < 0;
    int pageLines = reader_.screenRows() - 1, onPage = 0;
    long shown = 0, more = 0;
    std::string text;
    size_t index = 0;
    for (size_t p = 0; p < s.size(); p = table.next(s.data(), p), ++index) {
      if ((long)index < from || (!only.empty() && !only.count(runtime::ModuleTable::idAt(s.data() + p)))) continue;
      if (count >= 0 && shown == count) {
        ++more;
        continue;
      }
      if (page && onPage == pageLines) {
        if (!reader_.more()) return llvm::Error::success();
        onPage = 0;
      }
      text.clear();
      table.format(s.data() + p, text);
      std::printf("%*zu  %s\n", width, index, text.c_str());
      ++shown, ++onPage;
    }
    if (shown == 0 && more == 0) std::printf("(no modules)\n");
    if (more) std::printf("(and %ld more)\n", more);
    return llvm::Error::success();
  }

  llvm::Error cmdModule(const Args& args) {
    auto index = args.size() == 1 ? parseInt(args[0]) : std::nullopt;
    if (!index) return llvm::createStringError("error: usage: :module I");
    const runtime::ModuleTable& table = engine().modules();
    const runtime::ModuleBuffer& s = engine().string();
    size_t p = 0;
    for (long i = 0; p < s.size() && i < *index; ++i) p = table.next(s.data(), p);
    if (*index < 0 || p >= s.size())
      return llvm::createStringError("error: the string has " + plural(engine().moduleCount(), "module") + ", from 0");
    const char* rec = s.data() + p;
    const __lc_ModuleInfo& m = table.info(runtime::ModuleTable::idAt(rec));
    std::string text;
    table.format(rec, text);
    std::printf("%ld: %s\n", *index, text.c_str());
    std::printf("  made by: %s\n", app::originText(engine(), size_t(*index)).c_str());
    if (m.nFields == 0) std::printf("  no parameters\n");
    for (uint32_t k = 0; k < m.nFields; ++k) {
      text.clear();
      runtime::ModuleTable::formatField(m.fields[k], rec, text);
      std::printf("  p%u: %s = %s\n", k, m.fields[k].typeName, text.c_str());
    }
    return llvm::Error::success();
  }

  llvm::Error cmdSet(const Args& args) {
    const runtime::FunctionStore& f = session_->functions();
    std::vector<runtime::Tunables::Entry> tunables = session_->windowInput().tunables.entries();
    if (args.empty()) {
      bool any = false;
      for (int id = 1; id <= f.size(); ++id)
        if (f.isParameter(id)) {
          std::printf("%s = %g\n", std::string(f.nameOf(id)).c_str(), f.val(id));
          any = true;
        }
      for (const runtime::Tunables::Entry& t : tunables) {
        std::printf("%s = %g (tunable, %g..%g)\n", t.name.c_str(), t.moved ? t.movedTo : t.value, t.min, t.max);
        any = true;
      }
      if (!any) std::printf("(no .vset parameters or tunable values)\n");
      return llvm::Error::success();
    }
    if (args.size() != 2) return llvm::createStringError("error: usage: :set NAME VALUE");
    auto value = parseFloat(args[1]);
    if (!value) return llvm::createStringError("error: '" + args[1] + "' is not a number");
    // A .vset parameter, else a value the model marks as tunable (docs/studio.md).
    bool tunable = std::any_of(tunables.begin(), tunables.end(), [&](const auto& t) { return t.name == args[0]; });
    if (tunable && f.idOf(args[0]) == 0) session_->windowInput().tunables.move(args[0], float(*value));
    else if (auto e = session_->setParameter(args[0], *value)) return e;
    std::printf("%s = %g\n", args[0].c_str(), *value);
    int at = engine().stepNo();
    begin();
    deriveTo(at);
    printStatus();
    return llvm::Error::success();
  }

  llvm::Error cmdTime(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :time");
    auto t0 = Clock::now();
    begin();
    deriveTo(INT_MAX);
    double deriveMs = support::msSince(t0);
    t0 = Clock::now();
    runtime::Geometry geometry;
    if (auto e = engine().interpret(geometry)) return e;
    double interpretMs = support::msSince(t0);
    std::printf("derived %s in %.2f ms, interpreted in %.2f ms: %s\n", plural(engine().stepNo(), "step").c_str(),
                deriveMs, interpretMs, plural(engine().moduleCount(), "module").c_str());
    return llvm::Error::success();
  }

  llvm::Error cmdProfile(const Args& args) {
    size_t limit = 20;
    if (args.size() > 1) return llvm::createStringError("error: usage: :profile [N]");
    if (args.size() == 1) {
      auto n = parseFloat(args[0]);
      if (!n || *n < 1) return llvm::createStringError("error: '" + args[0] + "' is not a number of rules");
      limit = size_t(*n);
    }
    runtime::Engine& e = engine();
    e.setProfiling(true);
    auto off = llvm::make_scope_exit([&e] { e.setProfiling(false); });
    begin();
    deriveTo(INT_MAX);
    runtime::Geometry geometry;
    if (auto err = e.interpret(geometry)) return err;
    std::fputs(app::profileTable(app::profileRows(*e.profile(), e.ruleSources()), limit).c_str(), stdout);
    return llvm::Error::success();
  }

  llvm::Error cmdSave(const Args& args) {
    if (args.size() != 1) return llvm::createStringError("error: usage: :save FILE");
    const std::string& path = args[0];
    std::optional<OutputKind> kind = outputKindOf(path);
    if (!kind) return llvm::createStringError("error: " + path + ": unknown kind of file (" + kOutputFileTypes + ")");
    if (*kind == OutputKind::BinaryString) {
      if (auto e = engine().writeBinary(path)) return e;
    } else if (*kind == OutputKind::TextString) {
      if (auto e = engine().writeTextFile(path)) return e;
    } else if (auto e = frames_.write(path, engine(), session_->drawing())) {
      return e;
    }
    std::printf("wrote %s\n", path.c_str());
    return llvm::Error::success();
  }

  // The model's production groups and their kinds.
  std::map<int, uint8_t> productionGroups() const {
    std::map<int, uint8_t> groups{{0, __lc_NormalGroup}};
    const __lc_Model& m = *session_->model();
    for (uint32_t i = 0; i < m.nRules; ++i)
      if (m.rules[i].kind == __lc_Production) groups[m.rules[i].group] = m.rules[i].groupKind;
    return groups;
  }

  llvm::Error cmdGroup(const Args& args) {
    std::map<int, uint8_t> groups = productionGroups();
    std::string list;
    for (auto [g, kind] : groups)
      list += (list.empty() ? "" : ", ") + std::to_string(g) + (kind == __lc_GillespieGroup ? " (Gillespie)" : "");
    if (args.empty()) {
      std::printf("group %d; the model's groups: %s\n", engine().currentGroup(), list.c_str());
      return llvm::Error::success();
    }
    auto g = args.size() == 1 ? parseInt(args[0]) : std::nullopt;
    if (!g) return llvm::createStringError("error: usage: :group [N]");
    if (!groups.count((int)*g))
      return llvm::createStringError("error: the model has no production group " + args[0] + " (its groups: " + list + ")");
    engine().useGroup((int)*g);
    std::printf("group %ld from the next step\n", *g);
    return llvm::Error::success();
  }

  llvm::Error cmdProductions(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :productions");
    const __lc_Model& m = *session_->model();
    const runtime::ModuleTable& table = engine().modules();
    if (m.nRules == 0) std::printf("(no rules)\n");
    for (uint32_t i = 0; i < m.nRules; ++i) {
      const __lc_Rule& r = m.rules[i];
      const char* kind = r.kind == __lc_Production      ? "production"
                         : r.kind == __lc_Decomposition ? "decomposition"
                                                        : "interpretation";
      std::string group = (r.groupKind == __lc_GillespieGroup ? "ggroup " : "group ") + std::to_string(r.group);
      if (r.vgroup != 0) group += ", vgroup " + std::to_string(r.vgroup);
      // The predecessor as written: new left << left < strict > right >> new right.
      const __lc_ModuleId* id = r.pattern;
      auto names = [&](int n) {
        std::string out;
        for (int k = 0; k < n; ++k) out += std::string(table.info(*id++).name) + " ";
        return out;
      };
      std::string pattern;
      if (r.nNewLeft) pattern += names(r.nNewLeft) + "<< ";
      if (r.nLeft) pattern += names(r.nLeft) + "< ";
      pattern += names(r.nStrict);
      if (r.nRight) pattern += "> " + names(r.nRight);
      if (r.nNewRight) pattern += ">> " + names(r.nNewRight);
      if (!pattern.empty()) pattern.pop_back();
      std::printf("line %-4d %-14s %-8s %s\n", r.line, kind, group.c_str(), pattern.c_str());
    }
    return llvm::Error::success();
  }

  llvm::Error cmdWatch(const Args& args) {
    if (args.size() > 1 || (args.size() == 1 && args[0] != "on" && args[0] != "off"))
      return llvm::createStringError("error: usage: :watch [on|off]");
    if (args.size() == 1) {
      watching_ = args[0] == "on";
      session_->setEditedLive(watching_);
      if (watching_) watchFiles();
      else monitor_.clear();
    }
    if (watching_) std::printf("watching %s: a change reloads the model\n", plural(watched_, "file").c_str());
    else std::printf("not watching files\n");
    return llvm::Error::success();
  }

  llvm::Error cmdView(const Args& args) {
    if (args.size() == 1 && args[0] == "close") {
      if (!view_.isOpen()) return llvm::createStringError("error: no window is open");
      view_.close();
      std::printf("window closed\n");
      return llvm::Error::success();
    }
    if (!args.empty()) return llvm::createStringError("error: usage: :view [close]");
    if (view_.isOpen()) {
      std::printf("the window is open\n");
      return llvm::Error::success();
    }
    const std::string title = "lcjit repl: " + std::filesystem::path(loadedFiles_.lsystem).filename().string();
    if (auto e = view_.open(options_.width, options_.height, title))
      return llvm::createStringError("error: " + llvm::toString(std::move(e)));
    std::printf("window open: it shows the string after every command (:view close closes it)\n");
    return llvm::Error::success();
  }

  llvm::Error cmdHelp(const Args& args) {
    if (args.size() > 1) return llvm::createStringError("error: usage: :help [COMMAND]");
    bool found = false;
    for (const Command& c : commands()) {
      if (!args.empty() && args[0] != c.name && ":" + args[0] != c.name) continue;
      std::printf("%s%s%s\n      %s\n", c.name, *c.args ? " " : "", c.args, c.help);
      found = true;
    }
    if (!found) return llvm::createStringError("error: unknown command '" + args[0] + "'");
    if (args.empty())
      std::printf("Any other line is C++, compiled against the loaded model and run: an expression prints its value.\n");
    return llvm::Error::success();
  }

  llvm::Error cmdQuit(const Args& args) {
    if (!args.empty()) return llvm::createStringError("error: usage: :quit");
    quit_ = true;
    return llvm::Error::success();
  }

  // ---- :watch

  void watchFiles() {
    const runtime::DrawingFiles none;
    std::vector<std::string> files = watchedFiles(files_, session_->loaded() ? session_->drawing() : none);
    watched_ = files.size();
    if (!monitor_.watch(files)) warn("lcjit: file monitoring: " + monitor_.error());
  }

  // A change runs the §1.3 table's action, as `-rmode cont` does in the window.
  void pollWatch() {
    if (!watching_) return;
    std::vector<std::string> changed = monitor_.poll(0);
    if (changed.empty()) return;
    std::string names;
    for (const std::string& c : changed) names += (names.empty() ? "" : ", ") + c;
    reader_.interject([&] {
      for (Action a : actionsForChanges(changed, RefreshMode::Continuous)) {
        std::optional<ReloadParts> parts = reloadPartsFor(a);
        if (!parts) continue;  // New animate: the REPL does not animate
        std::printf("watch: %s changed: %s\n", names.c_str(), toString(a));
        report(load(*parts, rerunsSimulation(a) && session_->loaded() ? engine().stepNo() : -1, "reloaded"));
      }
    });
  }

  // ---- :view

  // Draws a frame of the window and sleeps until a window event or a key (at most 0.1 s).
  void pumpView() {
    if (!view_.isOpen()) return;
    const bool open = view_.pump({engine(), session_->drawing(),
                                  std::filesystem::path(loadedFiles_.lsystem).stem().string() + ".png",
                                  [this](const std::string& path) {
                                    reader_.interject([&] { report(frames_.write(path, engine(), session_->drawing())); });
                                  },
                                  [this](llvm::Error e) { report(std::move(e)); }});
    if (!open) reader_.interject([] { std::printf("window closed\n"); });
  }

  std::unique_ptr<Session> session_;
  ReplOptions options_;
  repl::LineReader reader_;
  FrameWriter frames_;
  app::TerminalProgress* progress_ = nullptr;  // deriveTo's progress line, while one runs
  runtime::EngineHooks hooks_;
  ModelFiles files_;             // of the last :load, what :reload and :watch read
  ModelFiles loadedFiles_;       // of the model in memory
  bool loadedCurrent_ = false;   // the model in memory came from files_ (no :load failed since)
  std::string pendingCpp_;       // C++ lines read until their brackets close
  bool quit_ = false, failed_ = false;
  FileMonitor monitor_;
  bool watching_ = false;
  size_t watched_ = 0;
  ReplView view_;
};

}  // namespace

int runRepl(const std::vector<std::string>& inputs, const ReplOptions& options) {
  if (options.lab) setenv("XDG_STATE_HOME", options.labFolder.c_str(), 1);  // the history: see LineReader
  auto session = Session::create(options.lab ? options.labFolder + "/.lcjit-cache" : "");
  if (!session) {
    std::fprintf(stderr, "lcjit: %s\n", llvm::toString(session.takeError()).c_str());
    return 1;
  }
  if (!(*session)->cacheWarning().empty()) std::fprintf(stderr, "lcjit: warning: %s\n", (*session)->cacheWarning().c_str());
  if (options.steps >= 0) {
    runtime::EngineLimits limits = (*session)->limits();
    limits.steps = options.steps;
    (*session)->setLimits(limits);
  }
  Repl repl(std::move(*session), options);
  return repl.run(inputs);
}

}  // namespace lcjit::repl
