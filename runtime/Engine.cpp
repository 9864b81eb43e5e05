// The derivation engine (see Engine.h): the coordinator of a run. Matching follows lpfg (manual
// appendix 9): the strict predecessor matches exactly; right context skips lateral branches and
// ignored modules; left context steps out of branches and over whole sibling branches; SB/EB are
// always considered.
//
// Where each part lives (each section begins with a `// ----` rule):
//   This file: The engine and its rule tables (construction, index, swapModel, candidates) ·
//     Provenance, views and interpretation (interpret, insertBefore) · The whole run (begin,
//     step, finish) · Faults (guarded, describe, the limits).
//   EngineInternal.h: what the parts share (Engine::Match, ruleTableKey).
//   EngineMatching.cpp: context matching: Brackets · Scans · Rules (matchRule, inContext,
//     applyRule, tryRules).
//   EngineDerivation.cpp: Derivation steps (forward, backward, Gillespie) · Decomposition and
//     interpretation rules (expand, decompose).
//   EngineEnvironment.cpp: the environmental pass: The pass · Requests · Answers.
//   EngineStrings.cpp: the string as files: Text (.str, -dtf) · Binary strings (.strb).
#include "runtime/Engine.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "runtime/EngineInternal.h"
#include "runtime/Functions.h"

namespace lcjit::runtime {
namespace {
thread_local Engine* gCurrent = nullptr;

struct CurrentScope {
  Engine* saved;
  explicit CurrentScope(Engine* e) : saved(gCurrent) { gCurrent = e; }
  ~CurrentScope() { gCurrent = saved; }
};
}  // namespace

// ---------------------------------------------------------------------------------------------
// The engine and its rule tables

Engine* Engine::current() { return gCurrent; }

Fault Engine::runModelCode(llvm::function_ref<void()> fn) {
  CurrentScope scope(this);
  activeCtx_ = nullptr;
  return guard_.run(fn);
}

Engine::Engine(const __lc_Model& model, const FunctionStore* functions) : model_(&model), functions_(functions) {
  setLimits(limits_);
  index();
}

void Engine::swapModel(const __lc_Model& model) {
  model_ = &model;
  for (auto* tables : {byFirst_, byLast_})
    for (int k = 0; k < 3; ++k) tables[k].clear();
  skip_.clear();
  groupKinds_.clear();
  maxGroup_ = 0;
  hasDecomposition_ = hasQueries_ = false;
  index();
}

void Engine::index() {
  const __lc_Model& model = *model_;
  modules_.setUserModules(model.modules, model.nModules);
  modules_.showNames(shownNames_);
  noSkip_.assign(modules_.count(), 0);
  for (uint32_t f = 0; f < model.nFilters; ++f) {
    const __lc_Filter& flt = model.filters[f];
    std::vector<uint8_t> skip(modules_.count(), flt.consider ? 1 : 0);
    for (uint16_t i = 0; i < flt.n; ++i)
      if (flt.ids[i] < skip.size()) skip[flt.ids[i]] = flt.consider ? 0 : 1;
    skip[__lc_id_SB] = skip[__lc_id_EB] = 0;
    skip_.push_back(std::move(skip));
  }
  for (uint32_t i = 0; i < model.nRules; ++i) {
    const __lc_Rule& r = model.rules[i];
    auto add = [&](std::map<int, RuleTable>& t, __lc_ModuleId id) {
      RuleTable& table = t[ruleTableKey(r.kind, r.group, r.vgroup)];
      if (table.size() < modules_.count()) table.resize(modules_.count());
      table[id].push_back(&r);
    };
    const __lc_ModuleId* strict = r.pattern + r.nNewLeft + r.nLeft;
    add(byFirst_[r.kind], strict[0]);
    add(byLast_[r.kind], strict[r.nStrict - 1]);
    if (r.kind == __lc_Decomposition) hasDecomposition_ = true;
    int total = r.nNewLeft + r.nLeft + r.nStrict + r.nRight + r.nNewRight;
    for (int k = 0; k < total; ++k)
      if (r.pattern[k] >= __lc_id_GetPos && r.pattern[k] <= __lc_id_GetUp) hasQueries_ = true;
    if (r.kind == __lc_Production) {
      groupKinds_[r.group] = r.groupKind;
      maxGroup_ = std::max<int>(maxGroup_, r.group);
    }
  }
}

Engine::~Engine() = default;

void Engine::outputFrame(const char* path) {
  if (hooks_ && hooks_->outputFrame) hooks_->outputFrame(path);
}

void Engine::print(const char* s) {
  if (hooks_ && hooks_->print) hooks_->print(s);
  else std::fputs(s, stdout);
}

void Engine::useGroup(int g) {
  if (g < 0 || g > maxGroup_) {
    char msg[80];
    std::snprintf(msg, sizeof msg, "Invalid group id %d\n", g);
    print(msg);
    return;
  }
  group_ = g;
}

const uint8_t* Engine::skipTable(const __lc_Rule& r) const {
  return r.filter >= 0 && (size_t)r.filter < skip_.size() ? skip_[r.filter].data() : noSkip_.data();
}

const Engine::RuleList* Engine::candidates(int kind, int group, __lc_ModuleId id, bool byLast) const {
  const auto& tables = byLast ? byLast_[kind] : byFirst_[kind];
  auto it = tables.find(group);
  if (it == tables.end() || id >= it->second.size() || it->second[id].empty()) return nullptr;
  return &it->second[id];
}

// ---------------------------------------------------------------------------------------------
// Provenance, views and interpretation

void Engine::setProvenance(bool on) {
  tracking_origins_ = on;
  if (!on) origins_.clear(), nextOrigins_.clear(), decomposedOrigins_.clear();
}

Engine::Origin Engine::originOf(size_t index) const {
  // Any change of the string made outside the tracked paths shows in the count.
  if (!tracking_origins_ || index >= origins_.size() || origins_.size() != moduleCount()) return {};
  return origins_[index];
}

int Engine::numOfViews() const { return model_->numOfViews ? model_->numOfViews() : 1; }

void Engine::useView(int id) {
  // lpfg's UseView checks the number against the model's view groups and says so in the model's
  // output; the view is not opened (its window stays empty).
  if (id < 0 || id >= numOfViews()) {
    print(("Invalid vgroup id = " + std::to_string(id) + ". Ignored\n").c_str());
    return;
  }
  if (std::find(views_.begin(), views_.end(), id) == views_.end()) views_.push_back(id);
}
void Engine::closeView(int id) { views_.erase(std::remove(views_.begin(), views_.end(), id), views_.end()); }

llvm::Error Engine::interpret(const std::function<void(const char*)>& sink, Geometry* geometry, std::string* transcript,
                              int vgroup) {
  CurrentScope scope(this);
  // OutputFrame's interpretation inside a step (or End) counts as that step's.
  const bool nested = activeCtx_ || runningCall_;
  auto message = guarded(Phase::Interpret, [&] { interpretGuarded(sink, geometry, transcript, vgroup); });
  if (profile_ && !nested) profile_->interpreted();
  if (message) return llvm::createStringError(*message);
  return llvm::Error::success();
}

void Engine::interpretGuarded(const std::function<void(const char*)>& sink, Geometry* geometry, std::string* transcript,
                              int vgroup) {
  Turtle& turtle = acquireTurtle();
  turtle.reset(turtleSetup_, geometry);
  turtle.setTranscript(transcript);
  tracking_ = geometry && geometry->trackSources ? geometry : nullptr;
  // The rules of the current production group and the view's group (manual §7.3), then those of
  // production group 0 and the view's group, as lpfg's InterpretString looks them up.
  expand(__lc_Interpretation, string_.data(), string_.size(), interpretationDepth_,
         ruleTableKey(__lc_Interpretation, group_, vgroup), nullptr, &turtle,
         sink ? &sink : nullptr);
  turtle.finish();
  tracking_ = nullptr;
  --turtlesInUse_;
}

Turtle& Engine::acquireTurtle() {
  if (turtles_.size() <= turtlesInUse_) turtles_.push_back(std::make_unique<Turtle>());
  return *turtles_[turtlesInUse_++];
}

bool Engine::insertBefore(size_t offset, const char* record) {
  if (offset > string_.size()) return false;
  size_t size = modules_.recordSize(ModuleTable::idAt(record));
  ModuleBuffer s;
  s.append(string_.data(), offset);
  s.append(record, size);
  // Its last two bytes repeat the id, as __lc_put writes them (the string is read backwards
  // too); in a record built by hand they may be padding.
  std::memcpy(s.data() + offset + size - sizeof(__lc_ModuleId), record, sizeof(__lc_ModuleId));
  s.append(string_.data() + offset, string_.size() - offset);
  if (tracking_origins_ && origins_.size() == moduleCount()) {  // the inserted module comes from no rule
    size_t index = 0;
    for (size_t p = 0; p < offset; p = modules_.next(string_.data(), p)) ++index;
    origins_.insert(origins_.begin() + std::ptrdiff_t(index), Origin{});
  }
  forgetCount();
  string_.swap(s);
  return true;
}

void Engine::warn(const std::string& message) const {
  if (hooks_ && hooks_->warning) hooks_->warning(message);
  else std::fprintf(stderr, "%s\n", message.c_str());
}

// ---------------------------------------------------------------------------------------------
// The whole run

llvm::Error Engine::run(const EngineHooks& hooks) {
  begin(hooks);
  while (step()) {
  }
  finish();
  return takeFault();
}

void Engine::begin(const EngineHooks& hooks) {
  CurrentScope scope(this);
  hooks_ = &hooks;
  step_ = 0;
  sequential_ = false;  // GroIMP's PARALLEL_MODE until the model sets another
  ended_ = false;
  faulted_ = false;
  fault_.reset();
  views_.clear();
  reported_.clear();
  gillespieTime_ = 0;
  queryTropisms_.initialised = false;
  forgetCount();
  string_.clear();
  if (profile_) profile_->reset(model_->nRules);
  if (auto message = guarded(Phase::Begin, [&] { beginGuarded(); })) fail(std::move(*message));
  if (profile_) profile_->endStep(0);
}

void Engine::setProfiling(bool on) {
  if (!on) return profile_.reset();
  if (profile_) return;
  profile_ = std::make_unique<Profile>();
  profile_->reset(model_->nRules);
}

void Engine::beginGuarded() {
  bracketsFor(nullptr, 0);  // a step that faulted did not reset them
  if (model_->start) {
    calling("Start");
    model_->start();
  }
  calling("the derivation length");
  length_ = limits_.steps >= 0 ? limits_.steps : modelDerivationLength();
  calling("the ring L-system statement");
  ring_ = modelRingLsystem();
  // A negative depth (an expression; a literal one is a compile error) decomposes nothing.
  calling("the decomposition depth");
  decompositionDepth_ = std::max(0, modelDecompositionDepth());
  calling("the interpretation depth");
  interpretationDepth_ = std::max(0, modelInterpretationDepth());
  stopRequested_ = false;
  {
    // Whatever a Start block nproduce'd is not part of the axiom here: the buffer is fresh.
    calling("the axiom");
    __lc_Ctx ctx{string_.raw(), 0, this, nullptr};
    model_->axiom(&ctx);
    calling(nullptr);
  }
  if (tracking_origins_) origins_.assign(moduleCount(), Origin{Origin::kAxiom, 0});
  decompose(group_);
  checkModules();
}

bool Engine::step() {
  if (ended_ || step_ >= length_ || stopRequested_) return false;
  CurrentScope scope(this);
  const int before = step_;
  derived_ = false;
  bool more = false;
  if (auto message = guarded(Phase::Step, [&] { more = stepGuarded(); })) {
    // As after cancelStep(): the string and the step count stay as they were before this step.
    forgetCount();
    if (derived_) string_.swap(next_), origins_.swap(nextOrigins_);
    step_ = before;
    fail(std::move(*message));
    return false;
  }
  if (profile_) profile_->endStep(step_);
  return more;
}

bool Engine::stepWith(int group, const EngineHooks& hooks) {
  if (faulted_) return false;
  hooks_ = &hooks;
  useGroup(group);
  ended_ = false;
  stopRequested_ = false;
  length_ = std::max(length_, step_ + 1);
  const int before = step_;
  step();
  return step_ > before;
}

bool Engine::stepGuarded() {
  bracketsFor(nullptr, 0);
  environmentPass();
  ++step_;
  if (model_->startEach) {
    calling("StartEach");
    model_->startEach();
    calling(nullptr);
  }
  int group = group_;
  auto kind = groupKinds_.find(group);
  bool derived = kind != groupKinds_.end() && kind->second == __lc_GillespieGroup ? deriveGillespie(group)
                 : sequential_                                                    ? deriveSequential(group)
                 : forward_                                                       ? deriveForward(group)
                                                                                  : deriveBackward(group);
  if (!derived) {
    // cancelStep(): the string stays as it was before this step.
    cancel_ = false;
    --step_;
    return false;
  }
  checkModules();
  if (hooks_->afterDerivation) hooks_->afterDerivation(step_);
  decompose(group);
  if (hasDecomposition_) checkModules();  // else the string is the one just checked
  if (model_->endEach) {
    calling("EndEach");
    model_->endEach();
    calling(nullptr);
  }
  if (hooks_->afterStep) hooks_->afterStep(step_);
  if (stopRequested_) {
    // Stop(): End runs now, as in lpfg.
    if (model_->end) {
      calling("End");
      model_->end();
      calling(nullptr);
    }
    ended_ = true;
    return false;
  }
  return step_ < length_;
}

void Engine::finish() {
  if (faulted_) {
    hooks_ = nullptr;
    return;
  }
  CurrentScope scope(this);
  auto message = guarded(Phase::Finish, [&] {
    // End is the last of this guarded call and stays named after it returns: a stop asked for
    // while it ran and seen only as the call ends is End's (guarded() puts runningCall_ back).
    if (!ended_ && model_->end) {
      calling("End");
      model_->end();
    }
  });
  if (message) fail(std::move(*message));
  ended_ = true;
  hooks_ = nullptr;
}

// ---------------------------------------------------------------------------------------------
// Faults

void Engine::setLimits(const EngineLimits& limits) {
  limits_ = limits;
  guard_.setLimits({limits.timeLimit, limits.maxMemory});
}

std::optional<std::string> Engine::guarded(Phase phase, llvm::function_ref<void()> fn) {
  // What a jump out of model code leaves behind is put back as it was (guarded calls nest: an
  // interpretation for OutputFrame runs inside a step).
  const Phase savedPhase = phase_;
  const __lc_Rule* savedRule = runningRule_;
  const char* savedCall = runningCall_;
  __lc_Ctx* savedCtx = activeCtx_;
  const bool savedCommunicating = communicating_;
  Geometry* savedTracking = tracking_;
  const size_t copies = copiesInUse_, turtles = turtlesInUse_;
  phase_ = phase;
  Fault fault = guard_.run(fn);
  std::optional<std::string> message;
  if (fault) message = describe(fault);
  phase_ = savedPhase;
  runningRule_ = savedRule;
  runningCall_ = savedCall;
  activeCtx_ = savedCtx;
  communicating_ = savedCommunicating;
  tracking_ = savedTracking;
  copiesInUse_ = copies;
  turtlesInUse_ = turtles;
  return message;
}

void Engine::fail(std::string message) {
  cancel_ = false;  // a cancelStep() that forced model code out is spent, as a quiet cancel is
  faulted_ = true;
  ended_ = true;
  fault_ = std::move(message);
}

llvm::Error Engine::takeFault() {
  if (!fault_) return llvm::Error::success();
  auto e = llvm::createStringError(*fault_);
  fault_.reset();
  return e;
}

// `m.l:13:9: error: production A(x) crashed in step 3: segmentation fault (null pointer dereference)`:
// the statement where the fault happened when the locator finds it, else the rule's first line.
std::string Engine::describe(const Fault& f) const {
  std::string where = model_->sourceFile && *model_->sourceFile ? model_->sourceFile : "model";
  std::string who;
  if (runningRule_) {
    const __lc_Rule& r = *runningRule_;
    where = (r.file && *r.file ? std::string(r.file) : where) + ":" + std::to_string(r.line);
    auto word = [&](const char* own, const char* lc) { return std::string(own ? own : lc) + " "; };
    const LanguageWords w = words_ ? *words_ : LanguageWords{};
    who = r.kind == __lc_Production      ? word(w.production, "production")
          : r.kind == __lc_Decomposition ? word(w.decomposition, "decomposition rule")
                                         : word(w.interpretation, "interpretation rule");
    // The predecessor's module as the language names it (XL's F for F_d).
    who += shownPredecessor(r.predecessor ? r.predecessor : "", shownNames_);
  } else if (runningCall_) {
    who = runningCall_;
    if (words_) {
      const std::pair<const char*, const char*> calls[] = {{"Start", words_->start}, {"StartEach", words_->startEach},
                                                           {"EndEach", words_->endEach}, {"End", words_->end}};
      for (const auto& [lc, own] : calls)
        if (own && who == lc) who = own;
    }
  } else {
    who = phase_ == Phase::Interpret ? "the interpretation" : "the derivation";
  }
  if (auto place = faultPlace(f, locate_))
    where = placeText(*place, {runningRule_ && runningRule_->file ? runningRule_->file : "",
                               model_->sourceFile ? model_->sourceFile : ""});
  std::string when;
  switch (phase_) {
    case Phase::Begin: when = "before the first step"; break;
    case Phase::Step: when = "in step " + std::to_string(step_); break;
    case Phase::Finish: when = "after step " + std::to_string(step_); break;
    case Phase::Interpret:
      when = step_ ? "while interpreting the string of step " + std::to_string(step_) : "while interpreting the axiom";
      break;
  }
  std::string text;
  switch (f.kind) {
    case FaultKind::Crash:
    case FaultKind::Abort: text = who + " crashed " + when + ": " + f.what; break;
    case FaultKind::Exception: text = who + " threw an exception " + when + ": " + f.what; break;
    case FaultKind::Interrupted: text = who + " was interrupted " + when; break;
    case FaultKind::Environment: return f.what + " (" + when + ")";
    default: text = who + " was stopped " + when + ": " + f.what; break;
  }
  return where + ": error: " + text;
}

void Engine::checkGrowth(size_t bytes) const {
  ModelGuard::checkpoint();
  if (bytes <= limits_.maxMemory) return;
  throw Fault{FaultKind::MemoryLimit,
              "the string needs " + sizeInWords(bytes) + " (limit --max-memory " + sizeInWords(limits_.maxMemory) + ")"};
}

void Engine::checkModules() const {
  constexpr size_t kSmallestRecord = 4;  // a module without parameters: its id, twice
  if (string_.size() / kSmallestRecord <= limits_.maxModules) return;  // it cannot have more
  size_t n = moduleCount();
  if (n <= limits_.maxModules) return;
  throw Fault{FaultKind::StringLimit, "the string reached " + std::to_string(n) + " modules (limit --max-modules " +
                                          std::to_string(limits_.maxModules) + ")"};
}

size_t Engine::moduleCount() const {
  if (counted_.s == string_.data() && counted_.n == string_.size() && counted_.s) return counted_.modules;
  size_t count = 0;
  for (size_t p = 0; p < string_.size(); p = modules_.next(string_.data(), p)) ++count;
  return count;
}

}  // namespace lcjit::runtime
