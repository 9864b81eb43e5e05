// The L-system engine (a ModelRun, ModelRun.h): runs a compiled model (its __lc_Model table) the way lpfg does —
// Start, axiom, derivation steps with context matching, groups, Gillespie groups, decomposition,
// interpretation (turtle queries), End — over contiguous module buffers.
#pragma once
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <iosfwd>
#include <string>
#include <vector>

#include "runtime/ModelGuard.h"
#include "runtime/ModelRun.h"
#include "runtime/ModuleString.h"
#include "runtime/Random.h"
#include "runtime/Environment.h"
#include "runtime/Profile.h"
#include "runtime/turtle/Turtle.h"
#include "runtime/include/lcjit/abi.h"
#include <llvm/Support/Error.h>

namespace lcjit::runtime {

class FunctionStore;
struct WindowInput;

class Engine final : public ModelRun {
 public:
  Engine(const __lc_Model& model, const FunctionStore* functions);
  ~Engine();
  // Between steps: the same model compiled again (another optimisation tier; the same modules
  // and productions in the same order) takes over; the string and the derivation go on.
  void swapModel(const __lc_Model& model);
  // How the string's text names modules, for a language that names them otherwise than L+C
  // (ModuleTable::showNames); kept across swapModel.
  void showNames(ModuleTable::ShownName shown) {
    shownNames_ = shown;
    modules_.showNames(shown);
  }
  // The words of the language the model is written in, for the faults' messages and the reports
  // (LanguageWords, Profile.h).
  void useWords(const LanguageWords* words) { words_ = words; }
  // The model's rules as the reports name them, in its language's words and names.
  std::vector<RuleSource> ruleSources() const { return runtime::ruleSources(*model_, words_, shownNames_); }
  const __lc_Model& model() const { return *model_; }
  // The model's `derivation length:` (0 without one), decomposition and interpretation depths
  // (1 without), and whether it is a ring L-system: evaluated now (they are expressions; the
  // engine takes them after Start, DerivationLength() & co. whenever model code asks).
  int modelDerivationLength() const { return model_->derivationLength ? model_->derivationLength() : 0; }
  int modelDecompositionDepth() const { return model_->decompositionDepth ? model_->decompositionDepth() : 1; }
  int modelInterpretationDepth() const { return model_->interpretationDepth ? model_->interpretationDepth() : 1; }
  bool modelRingLsystem() const { return model_->ringLsystem && model_->ringLsystem() != 0; }
  // Environment()/NoEnvironment() (§6.11): whether the environment is ignored.
  void setIgnoreEnvironment(bool ignore) { ignoreEnvironment_ = ignore; }
  bool ignoreEnvironment() const { return ignoreEnvironment_; }
  // The environmental program (§5.10), or null; it must outlive the runs. At the start of every
  // step (before StartEach, unless NoEnvironment()) the string is interpreted and each E1, E2
  // and EA20 the turtle meets is sent with its turtle lines; the answers overwrite the modules'
  // parameters before the step's productions read them.
  void setEnvironment(EnvironmentLink* link) { environment_ = link; }
  // -cleanEA20: the elements of an answered EA20 past the answer's values are zeroed.
  void setCleanEA20(bool clean) { cleanEA20_ = clean; }
  // The context of the rule body running, or null (lcjit_current_ctx).
  __lc_Ctx* activeContext() const { return activeCtx_; }
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // The whole derivation as `lpfg -b` runs it: Start, axiom, steps, End. A fault (below) is
  // the error.
  llvm::Error run(const EngineHooks& hooks = {});
  // The same in pieces, for animation: begin() runs Start and the axiom (with decomposition);
  // step() one derivation step, false once the derivation length is reached or Stop() was
  // called (then End has run); finish() runs End if it has not. `hooks` must outlive them.
  void begin(const EngineHooks& hooks) override;
  bool step() override;
  void finish() override;
  // One more step with production group `group`, past the derivation length and after End (XL's
  // rule methods, which GroIMP's buttons apply to the graph as it is, as often as clicked): the
  // group stays the current one. `hooks` as begin()'s (End may have let go of them). False when
  // the step failed (a fault) or derived nothing.
  bool stepWith(int group, const EngineHooks& hooks);

  // Faults. Model code runs behind a ModelGuard, one guarded call per begin(), step(), finish()
  // and interpret(): a crash, an uncaught exception, an interrupt or a limit ends that call.
  // In begin/step/finish it ends the derivation: step() returns false, finish() runs no End,
  // the string is left as it was before the failed step (stepsDone() too), and takeFault()
  // returns the message — `file:line: error: production A(x) crashed in step 3: …` — until the
  // next begin(), which starts afresh. interpret() returns it.
  llvm::Error takeFault() override;
  bool faulted() const override { return faulted_; }
  void setLimits(const EngineLimits& limits) override;
  const EngineLimits& limits() const { return limits_; }
  // How a fault finds the statement it happened in (its message then names that file:line:column
  // instead of the rule's first line). Unset: the rule's line.
  void setCodeLocator(CodeLocator locate) { locate_ = std::move(locate); }
  // From any thread (or a signal handler): the model code running now (a step, an
  // interpretation, Start…) stops, with an "interrupted" fault; a model stuck in a loop is made to
  // jump out (ModelGuard.h).
  void interrupt() override { guard_.interrupt(FaultKind::Interrupted); }
  // Other model code of this model (C++ typed at the REPL) behind the same guard and limits, so
  // that interrupt() and cancelStep() stop it too. The engine is the current one meanwhile, so
  // host functions (LoadString, UseGroup...) act on it.
  Fault runModelCode(llvm::function_ref<void()> fn);

  // From another thread (or a signal handler): abandon the derivation step in progress (the
  // string stays as before it; model code already run, StartEach included, is not undone).
  // step() then returns false. Model code that does not return is interrupted (a fault) after a
  // short grace period.
  void cancelStep() override {
    cancel_ = true;
    guard_.interrupt(FaultKind::Interrupted);
  }
  // A cancel that came after the step had finished must not stop the next one.
  void clearCancel() override { cancel_ = false; }
  int derivationLength() const override { return length_; }
  bool ended() const override { return ended_; }

  // Profiling (Profile.h): per-rule counts and times from the next begin() (or now, when turned
  // on between steps). Off: nothing is counted. Read profile() only while no step runs.
  void setProfiling(bool on);
  const Profile* profile() const { return profile_.get(); }

  // Provenance (the window's String panel): which rule made each module of the string, in which
  // step. On from the next begin(); forward and backward steps and decomposition keep it; a change
  // of the string they do not make (a Gillespie step, String input, the REPL's edits) leaves the
  // modules' origin unknown; a MouseIns insertion is unknown itself.
  struct Origin {
    static constexpr int32_t kAxiom = -1, kUnknown = -2;
    int32_t rule = kUnknown;  // index in model().rules, or kAxiom / kUnknown
    int32_t step = 0;
  };
  void setProvenance(bool on);
  bool provenance() const { return tracking_origins_; }
  // The origin of the string's module `index` (0-based, in string order).
  Origin originOf(size_t index) const;
  // Break: a step in which rule `rule` (index in model().rules; -1: none) applies sets the flag
  // takeBreak() returns (and clears); the caller stops stepping there.
  void breakOn(int rule) {
    breakRule_ = rule;
    breakHit_ = false;
  }
  int breakRule() const { return breakRule_; }
  bool takeBreak() { return std::exchange(breakHit_, false); }

  // Interprets the current string: interpretation rules (with `maximum depth`) then the turtle.
  // `sink` sees each module the turtle executes, after the turtle did; `geometry`, when given,
  // receives what the turtle draws.
  // `transcript`, when given, receives lpfg's `-dtf` turtle text.
  // `vgroup`: the view group whose interpretation rules apply (multi-view, manual §7.3).
  // A fault in an interpretation rule is the error (the string is unchanged).
  llvm::Error interpret(const std::function<void(const char* rec)>& sink, Geometry* geometry = nullptr,
                        std::string* transcript = nullptr, int vgroup = 0);
  llvm::Error interpret(Geometry& geometry, int vgroup = 0) override { return interpret(nullptr, &geometry, nullptr, vgroup); }
  // lpfg's `-dtf` text of the current string written to `out` as the turtle goes, a megabyte at
  // a time (interpret's `transcript` holds it all: 23 MB for 2 M turtle commands). An
  // interpretation fault is the error, after the text up to it.
  llvm::Error writeTurtleText(std::ostream& out, int vgroup = 0);
  // UseView/CloseView (§6.4): the views the model has opened, in order.
  void useView(int id);
  void closeView(int id);
  int numOfViews() const;  // the model's view groups (NumOfViews)
  const std::vector<int>& views() const override { return views_; }
  // Inserts one module record before the module at string offset `offset` (MouseIns, §5.9).
  bool insertBefore(size_t offset, const char* record);
  // The view file and shapes the turtle draws with (also used by the query pass: tropisms move
  // the turtle). The pointed-to data must outlive the engine's runs.
  void setTurtleSetup(const TurtleSetup& setup) {
    turtleSetup_ = setup;
    queryTropisms_.initialised = false;
  }
  const TurtleSetup& turtleSetup() const { return turtleSetup_; }
  // The contours the curve functions read and edit (curveSetPoint & co.).
  void setCurves(ContourStore* curves) { curves_ = curves; }
  ContourStore* curves() const { return curves_; }

  const ModuleTable& modules() const { return modules_; }
  const ModuleBuffer& string() const { return string_; }
  ModuleBuffer& string() { return string_; }
  std::string text(const ModuleBuffer& s) const;  // one module per line
  // The same text written to `out` as it is formatted, a megabyte at a time: `-out x.str` of a
  // 76 MB string no longer holds it all in memory first.
  void writeText(const ModuleBuffer& s, std::ostream& out) const;
  // The current string as text (.str), written whole or not at all (support/ReplacingFile.h).
  llvm::Error writeTextFile(const std::string& path) const;
  int stepsDone() const override { return step_; }
  size_t moduleCount() const;  // counted as the last step derived it when it can be

  // Binary strings (.strb): lpfg's in-memory layout, no header.
  llvm::Error writeBinary(const std::string& path) const;
  llvm::Error readBinary(const std::string& path);

  // ---- used by the host functions model code calls (HostFunctions.cpp)
  static Engine* current();
  void useGroup(int g);
  int currentGroup() const { return group_; }
  void cutBranch() { cutBranch_ = true; }
  const char* findModule(__lc_Ctx* c, __lc_ModuleId id, size_t* at) const;
  // The turtle interpreting the string now (the innermost pass), null outside interpretation.
  Turtle* interpretingTurtle() { return turtlesInUse_ ? turtles_[turtlesInUse_ - 1].get() : nullptr; }
  void setForward(bool f) { forward_ = f; }
  void setSequential(bool on) { sequential_ = on; }
  bool forward() const { return forward_; }
  void stop() override { stopRequested_ = true; }
  int stepNo() const { return step_; }
  Rand48& random() { return random_; }
  // --seed N: this run is member N of an ensemble (Rand48::setMember); none: lpfg's streams.
  void setEnsembleMember(std::optional<uint64_t> n) {
    random_.setMember(n);
    gillespieRandom_.setMember(n);
  }
  // Report(NAME, value) of model code: the last value reported under each name (docs/sweeps.md).
  void report(std::string name, double value) { reported_[std::move(name)] = value; }
  const std::map<std::string, double>& reported() const { return reported_; }
  Rand48& gillespieRandom() { return gillespieRandom_; }
  double gillespieTime() const { return gillespieTime_; }
  void resetGillespieTime() { gillespieTime_ = 0; }
  const FunctionStore* functions() const { return functions_; }
  void print(const char* s);
  void outputFrame(const char* path);
  bool inContext(__lc_Ctx* c, int side, const __lc_ModuleId* ids, int n, const char** params);
  // lcjit_buffer_reserve: a successor growing to `bytes` (while the string has its own) must stay
  // within the memory limit; throws the fault otherwise.
  void checkGrowth(size_t bytes) const;

 private:
  struct Match;
  struct Scan {
    const char* s;
    size_t n;
    bool ring;
  };
  using RuleList = std::vector<const __lc_Rule*>;
  using RuleTable = std::vector<RuleList>;  // by module id

  const RuleList* candidates(int kind, int group, __lc_ModuleId id, bool byLast) const;
  bool matchRule(const __lc_Rule& r, const Scan& old, size_t pos, const Scan& newLeft, const Scan& newRight, Match& m) const;
  bool applyRule(const __lc_Rule& r, Match& m, ModuleBuffer& out);
  // `group`: the rule table's key (ruleTableKey); then `groupZero`'s rules, unless the same.
  bool tryRules(int kind, int group, int groupZero, const Scan& old, size_t pos, const Scan& newLeft, const Scan& newRight,
                ModuleBuffer& out, Match& m);

  // What a fault message says the engine was doing.
  enum class Phase { Begin, Step, Finish, Interpret };
  // Runs `fn` behind the guard; on a fault returns the message (and restores the engine's
  // bookkeeping the jump skipped).
  std::optional<std::string> guarded(Phase phase, llvm::function_ref<void()> fn);
  std::string describe(const Fault& f) const;
  void fail(std::string message);
  bool stepGuarded();
  void beginGuarded();
  void interpretGuarded(const std::function<void(const char*)>& sink, Geometry* geometry, std::string* transcript,
                        int vgroup);
  // Called before each model function that is not a rule ("Start", "StartEach"…).
  void calling(const char* what) {
    runningRule_ = nullptr;
    activeCtx_ = nullptr;
    runningCall_ = what;
  }
  // The per-module checks of the derivation loops: an interrupt or a limit.
  void checkStop(size_t bytesInUse) const {
    if (guard_.stopRequested()) throw ModelStop{};
    if (bytesInUse > limits_.maxMemory) checkGrowth(bytesInUse);
  }
  void checkModules() const;
  Turtle& acquireTurtle();

  // False when cancelStep() interrupted them (the string is then unchanged).
  bool deriveForward(int group);
  // One production applied (XL's SEQUENTIAL_MODE): the first of the group's (then group 0's), in
  // their order, that applies anywhere, where it first applies in the string.
  bool deriveSequential(int group);
  bool deriveBackward(int group);
  bool deriveGillespie(int group);
  void decompose(int group);
  // `depth`: the levels it may still go down; `level`: how far down it is (its buffer's index).
  void expand(int kind, char* src, size_t n, int depth, int group, ModuleBuffer* target, Turtle* turtle,
              const std::function<void(const char*)>* sink, size_t level = 0);
  // The environmental pass at the start of a step: query modules filled, communication modules
  // sent and answered.
  void environmentPass();
  void communicate(const char* src, size_t pos, size_t n, const Turtle& turtle);
  void applyAnswers(const std::string& answers);
  void warn(const std::string& message) const;

  size_t scanRight(const Scan& sc, size_t& p, __lc_ModuleId want, const uint8_t* skip) const;
  size_t scanLeft(const Scan& sc, size_t& p, __lc_ModuleId want, const uint8_t* skip) const;
  size_t findEndOfBranch(const Scan& sc, size_t p) const;
  size_t findStartOfBranch(const Scan& sc, size_t p) const;
  // The matched SB/EB pairs of the predecessor string while a step derives it, made on the first
  // branch a context scan skips: a scan otherwise walked every skipped branch module by module
  // (signal.l spent 79 % of its derivation in scanLeft). Only for the string `s` of `n` bytes and
  // only while `live` (the step that set it is running). Positions are kept in halves (records
  // start at even bytes), 16 bytes a pair; a table that would outgrow half the string (a string
  // of brackets) or a string past 8 GB is not made: the scans walk, as before.
  struct Brackets {
    struct Pair {
      uint32_t sb, eb;  // byte positions / 2; eb kNone: the SB is never closed
    };
    static constexpr uint32_t kNone = UINT32_MAX;
    const char* s = nullptr;
    size_t n = 0;
    bool live = false, built = false, usable = false;
    std::vector<Pair> bySb, byEb;  // ordered by SB and by EB
  };
  const Brackets* bracketsOf(const Scan& sc) const;
  void bracketsFor(const char* s, size_t n);  // a step begins deriving this string
  mutable Brackets brackets_;
  // The number of modules of string_ as the forward step that made it counted them, once the
  // string is large enough for the limit check to need a count (it walked the whole string
  // twice a step past 400 MB: 31 % of a 72 M-module run). Only for the buffer and size it was
  // counted for; anything else that changes the string forgets it.
  struct Counted {
    const char* s = nullptr;
    size_t n = 0, modules = 0;
  } counted_;
  void noteCount(size_t modules) { counted_ = {string_.data(), string_.size(), modules}; }
  void forgetCount() { counted_ = {}; }
  // Where scanLeft's last walk over the predecessor string stopped (see scanLeft); reset with
  // the brackets.
  struct LeftStop {
    const char* s = nullptr;
    size_t from = 0;
    const uint8_t* skip = nullptr;
    size_t at = 0;
  };
  mutable LeftStop leftStop_;
  const uint8_t* skipTable(const __lc_Rule& r) const;

  void index();  // the rule tables for model_

  const __lc_Model* model_;
  const FunctionStore* functions_;
  ModuleTable modules_;
  std::map<int, RuleTable> byFirst_[3], byLast_[3];
  std::vector<std::vector<uint8_t>> skip_;  // per filter: 1 = not considered in context
  std::vector<uint8_t> noSkip_;
  bool hasDecomposition_ = false, hasQueries_ = false;
  std::map<int, int> groupKinds_;
  int maxGroup_ = 0;

  // A jump out of model code skips the destructors of the engine's frames, so whatever a step
  // allocates lives here, reused, rather than in locals.
  ModuleBuffer string_, next_, scratch_, decomposed_, pieces_;
  std::vector<std::unique_ptr<ModuleBuffer>> levels_;  // successor buffers per decomposition level
  std::vector<std::unique_ptr<ModuleBuffer>> copies_;   // expand()'s working copies, by nesting
  size_t copiesInUse_ = 0;
  std::vector<std::unique_ptr<Turtle>> turtles_;        // interpret()/environmentPass(), by nesting
  size_t turtlesInUse_ = 0;
  struct Reaction {
    float propensity;
    size_t from, to;          // the strict predecessor's bytes in the string
    size_t succFrom, succTo;  // the successor's bytes in `pieces_`
  };
  std::vector<Reaction> reactions_;
  int group_ = 0;
  bool forward_ = true;
  // XL's sequential derivation (lcjit_derive_sequentially): deriveSequential's production, the
  // one deriveForward may apply, and whether it has.
  bool sequential_ = false;
  const __lc_Rule* onlyRule_ = nullptr;
  bool onlyRuleApplied_ = false;
  bool cutBranch_ = false;  // the running production asked its branch's rest to go (lcjit_cut_branch)
  ModuleTable::ShownName shownNames_ = nullptr;  // showNames
  const LanguageWords* words_ = nullptr;         // useWords
  bool stopRequested_ = false;
  int step_ = 0, length_ = 0;
  bool ended_ = false;
  std::atomic<bool> cancel_{false};
  bool ring_ = false;
  int decompositionDepth_ = 1, interpretationDepth_ = 1;
  Rand48 random_, gillespieRandom_;
  std::map<std::string, double> reported_;
  double gillespieTime_ = 0;
  const EngineHooks* hooks_ = nullptr;
  __lc_Ctx* activeCtx_ = nullptr;  // the rule body running (produce in functions it calls)
  bool ignoreEnvironment_ = false;
  EnvironmentLink* environment_ = nullptr;
  bool cleanEA20_ = false;
  // During environmentPass(): the request being written and the modules it names (by the id
  // sent, which is the module's byte offset in the string).
  struct Communication {
    std::vector<std::string> records;
    std::map<size_t, __lc_ModuleId> sent;
  };
  Communication communication_;
  bool communicating_ = false;
  TurtleSetup turtleSetup_;
  // The query passes' tropism field, kept from one pass to the next during a run, as lpfg's
  // global tropisms are in a batch run (drawing passes start from the view file).
  TropismField queryTropisms_;
  std::vector<int> views_;
  Geometry* tracking_ = nullptr;  // interpret(): the geometry recording its source modules
  ContourStore* curves_ = nullptr;

  ModelGuard guard_;
  CodeLocator locate_;
  EngineLimits limits_;
  // What model code is running, for fault messages: a rule, else a named function (Start…).
  const __lc_Rule* runningRule_ = nullptr;
  std::unique_ptr<Profile> profile_;
  // What rule bodies are watched for (applyRule's slow path): a profile, a break.
  bool inspecting() const { return profile_ || breakRule_ >= 0; }
  int breakRule_ = -1;
  bool breakHit_ = false;
  // Provenance: the origins of string_'s modules; of the string a forward step makes; of the one
  // decomposition makes (apart, so that a fault after the step can put the step's back).
  bool tracking_origins_ = false;
  std::vector<Origin> origins_, nextOrigins_, decomposedOrigins_;
  const __lc_Rule* lastApplied_ = nullptr;  // the rule whose body produced last (decomposition)
  Origin expandOrigin_;                     // decomposition: the origin of what the rule running makes
  void forgetOrigins() { origins_.clear(); }
  const char* runningCall_ = nullptr;
  Phase phase_ = Phase::Begin;
  bool derived_ = false;  // this step's string has replaced the old one (which is in next_)
  bool faulted_ = false;
  std::optional<std::string> fault_;
};

}  // namespace lcjit::runtime
