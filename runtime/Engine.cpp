// The derivation engine (see Engine.h). Matching follows lpfg (manual appendix 9): the strict
// predecessor matches exactly; right context skips lateral branches and ignored modules; left
// context steps out of branches and over whole sibling branches; SB/EB are always considered.
#include "runtime/Engine.h"

#include <llvm/ADT/ScopeExit.h>

#include <sstream>
#include <algorithm>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "runtime/Functions.h"
#include "runtime/files/ReplacingFile.h"
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {
namespace {
constexpr size_t npos = ~size_t(0);
constexpr int kMaxPattern = 5 * 32;
thread_local Engine* gCurrent = nullptr;

struct CurrentScope {
  Engine* saved;
  explicit CurrentScope(Engine* e) : saved(gCurrent) { gCurrent = e; }
  ~CurrentScope() { gCurrent = saved; }
};
}  // namespace

// The state of one rule application; InXContext calls continue from the saved positions.
struct Engine::Match {
  const char* params[kMaxPattern];
  const __lc_Rule* rule = nullptr;
  const uint8_t* skip = nullptr;
  Scan old{}, newLeft{}, newRight{};
  size_t leftPos = 0, rightPos = 0, newLeftPos = 0, newRightPos = 0;
  bool forward = true;
  bool contexts = true;  // InXContext allowed (derivation only, as in lpfg)
};

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

static int ruleTableKey(int kind, int group, int vgroup) {
  // lpfg looks interpretation rules up by production group and view group together.
  return kind == __lc_Interpretation ? int((uint32_t(uint16_t(group)) << 16) | uint16_t(vgroup)) : group;
}

void Engine::index() {
  const __lc_Model& model = *model_;
  modules_.setUserModules(model.modules, model.nModules);
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

// ---- context scanning

void Engine::bracketsFor(const char* s, size_t n) {
  leftStop_ = {};
  brackets_.s = s;
  brackets_.n = n;
  brackets_.live = s != nullptr;
  brackets_.built = false;
}

const Engine::Brackets* Engine::bracketsOf(const Scan& sc) const {
  Brackets& b = brackets_;
  if (!b.live || sc.s != b.s || sc.n != b.n) return nullptr;
  if (!b.built) {
    b.built = true;
    b.usable = sc.n / 2 < Brackets::kNone;
    b.bySb.clear();
    b.byEb.clear();
    std::vector<uint32_t> open;  // indexes in bySb of the SBs not closed yet
    const size_t maxPairs = sc.n / 2 / (2 * sizeof(Brackets::Pair));
    for (size_t p = 0; p < sc.n && b.usable; p = modules_.next(sc.s, p)) {
      __lc_ModuleId id = ModuleTable::idAt(sc.s + p);
      b.usable = (p & 1) == 0;  // records are structs of 16-bit ids: always at even bytes
      if (id == __lc_id_SB) {
        open.push_back(uint32_t(b.bySb.size()));
        b.bySb.push_back({uint32_t(p / 2), Brackets::kNone});
        b.usable = b.usable && b.bySb.size() <= maxPairs;
      } else if (id == __lc_id_EB && !open.empty()) {
        b.bySb[open.back()].eb = uint32_t(p / 2);
        b.byEb.push_back(b.bySb[open.back()]);
        open.pop_back();
      }
    }
    if (!b.usable) {
      std::vector<Brackets::Pair>().swap(b.bySb);
      std::vector<Brackets::Pair>().swap(b.byEb);
    }
  }
  return b.usable ? &b : nullptr;
}

size_t Engine::findEndOfBranch(const Scan& sc, size_t p) const {
  // Just after an SB: its EB, from the table.
  if (p > 0 && p <= sc.n && ModuleTable::idAt(sc.s + modules_.prev(sc.s, p)) == __lc_id_SB)
    if (const Brackets* b = bracketsOf(sc)) {
      const uint32_t sb = uint32_t(modules_.prev(sc.s, p) / 2);
      auto it = std::lower_bound(b->bySb.begin(), b->bySb.end(), sb,
                                 [](const Brackets::Pair& e, uint32_t at) { return e.sb < at; });
      return it != b->bySb.end() && it->sb == sb && it->eb != Brackets::kNone ? size_t(it->eb) * 2 : npos;
    }
  int depth = 1;
  while (p < sc.n) {
    __lc_ModuleId id = ModuleTable::idAt(sc.s + p);
    if (id == __lc_id_SB) ++depth;
    else if (id == __lc_id_EB && --depth == 0) return p;
    p = modules_.next(sc.s, p);
  }
  return npos;
}

size_t Engine::findStartOfBranch(const Scan& sc, size_t p) const {
  if (const Brackets* b = bracketsOf(sc)) {  // p is an EB
    const uint32_t eb = uint32_t(p / 2);
    auto it = std::lower_bound(b->byEb.begin(), b->byEb.end(), eb,
                               [](const Brackets::Pair& e, uint32_t at) { return e.eb < at; });
    return it != b->byEb.end() && it->eb == eb ? size_t(it->sb) * 2 : npos;
  }
  int depth = 1;
  while (p > 0) {
    p = modules_.prev(sc.s, p);
    __lc_ModuleId id = ModuleTable::idAt(sc.s + p);
    if (id == __lc_id_EB) ++depth;
    else if (id == __lc_id_SB && --depth == 0) return p;
  }
  return npos;
}

// Matches `want` at or after p; on success p moves past it and the match's position is returned.
size_t Engine::scanRight(const Scan& sc, size_t& p, __lc_ModuleId want, const uint8_t* skip) const {
  if (p >= sc.n) {
    if (!sc.ring || sc.n == 0) return npos;
    p = 0;
  }
  if (want == __lc_id_EB) {
    p = findEndOfBranch(sc, p);
    if (p == npos) return npos;
  }
  size_t guard = sc.n;  // every module visited at most once, even in a ring
  for (;;) {
    if (p >= sc.n) {
      if (!sc.ring || sc.n == 0) return npos;
      p = 0;
    }
    __lc_ModuleId id = ModuleTable::idAt(sc.s + p);
    if (id == want) break;
    if (guard-- == 0) return npos;
    if (skip[id]) {
      p = modules_.next(sc.s, p);
    } else if (id == __lc_id_SB) {
      size_t e = findEndOfBranch(sc, modules_.next(sc.s, p));
      if (e == npos) return npos;
      p = modules_.next(sc.s, e);
    } else {
      return npos;
    }
  }
  size_t at = p;
  p = modules_.next(sc.s, p);
  return at;
}

// Matches `want` before p; on success p is the matched module's position (the next scan
// continues to its left).
size_t Engine::scanLeft(const Scan& sc, size_t& p, __lc_ModuleId want, const uint8_t* skip) const {
  auto stepBack = [&](size_t q) -> size_t {
    if (q == 0) {
      if (!sc.ring || sc.n == 0) return npos;
      q = sc.n;
    }
    return modules_.prev(sc.s, q);
  };
  // Wanting a module the walk would pass over anyway (not ignored, not a bracket), the walk ends at
  // the first module it cannot pass, whatever is wanted: within a step, the predecessor string's
  // is kept for the next rule that looks left of the same module.
  const bool memo = !skip[want] && want != __lc_id_SB && want != __lc_id_EB && brackets_.live && sc.s == brackets_.s;
  LeftStop& last = leftStop_;
  size_t q;
  if (memo && last.s == sc.s && last.from == p && last.skip == skip) {
    q = last.at;
  } else {
    q = stepBack(p);
    size_t guard = sc.n;
    while (q != npos) {
      __lc_ModuleId id = ModuleTable::idAt(sc.s + q);
      if (id == want) break;
      if (guard-- == 0) {
        q = npos;
        break;
      }
      if (skip[id] || id == __lc_id_SB) {
        q = stepBack(q);
      } else if (id == __lc_id_EB) {
        size_t b = findStartOfBranch(sc, q);
        q = b == npos ? npos : stepBack(b);
      } else {
        break;  // neither wanted nor passed over
      }
    }
    if (memo) last = {sc.s, p, skip, q};
  }
  if (q == npos || ModuleTable::idAt(sc.s + q) != want) return npos;
  p = q;
  return q;
}

bool Engine::matchRule(const __lc_Rule& r, const Scan& old, size_t pos, const Scan& newLeft, const Scan& newRight,
                       Match& m) const {
  const __lc_ModuleId* ids = r.pattern;
  const int iL = r.nNewLeft, iS = iL + r.nLeft, iR = iS + r.nStrict, iNR = iR + r.nRight;
  const uint8_t* skip = skipTable(r);
  if (r.nNewLeft && !m.forward) return false;
  if (r.nNewRight && m.forward) return false;
  // Strict predecessor: exact, consecutive.
  size_t p = pos;
  for (int j = 0; j < r.nStrict; ++j) {
    if (p >= old.n) {
      if (!old.ring || j == 0) return false;
      p = 0;
    }
    if (ModuleTable::idAt(old.s + p) != ids[iS + j]) return false;
    m.params[iS + j] = old.s + p;
    p = modules_.next(old.s, p);
  }
  // Right context, in the old string.
  for (int j = 0; j < r.nRight; ++j) {
    size_t at = scanRight(old, p, ids[iR + j], skip);
    if (at == npos) return false;
    m.params[iR + j] = old.s + at;
  }
  m.rightPos = p;
  // New left context (forward) replaces the ordinary left context, as in lpfg.
  size_t lp = newLeft.n;
  if (r.nNewLeft) {
    for (int j = r.nNewLeft - 1; j >= 0; --j) {
      size_t at = scanLeft(newLeft, lp, ids[j], skip);
      if (at == npos) return false;
      m.params[j] = newLeft.s + at;
    }
  }
  m.newLeftPos = lp;
  lp = pos;
  if (!r.nNewLeft) {
    for (int j = r.nLeft - 1; j >= 0; --j) {
      size_t at = scanLeft(old, lp, ids[iL + j], skip);
      if (at == npos) return false;
      m.params[iL + j] = old.s + at;
    }
  }
  m.leftPos = lp;
  // New right context (backward): the already derived part to the right.
  size_t rp = 0;
  for (int j = 0; j < r.nNewRight; ++j) {
    size_t at = scanRight(newRight, rp, ids[iNR + j], skip);
    if (at == npos) return false;
    m.params[iNR + j] = newRight.s + at;
  }
  m.newRightPos = rp;
  m.rule = &r;
  m.skip = skip;
  m.old = old;
  m.newLeft = newLeft;
  m.newRight = newRight;
  return true;
}

bool Engine::inContext(__lc_Ctx* c, int side, const __lc_ModuleId* ids, int n, const char** params) {
  Match* m = static_cast<Match*>(c->match);
  if (!m || !m->contexts) return false;
  switch (side) {
    case __lc_InLeft: {
      size_t p = m->leftPos;
      for (int j = n - 1; j >= 0; --j) {
        size_t at = scanLeft(m->old, p, ids[j], m->skip);
        if (at == npos) return false;
        params[j] = m->old.s + at;
      }
      m->leftPos = p;
      return true;
    }
    case __lc_InRight: {
      size_t p = m->rightPos;
      for (int j = 0; j < n; ++j) {
        size_t at = scanRight(m->old, p, ids[j], m->skip);
        if (at == npos) return false;
        params[j] = m->old.s + at;
      }
      m->rightPos = p;
      return true;
    }
    case __lc_InNewLeft: {
      if (!m->forward) return false;
      Scan sc{m->newLeft.s, m->newLeft.n, false};
      size_t p = m->newLeftPos;
      for (int j = n - 1; j >= 0; --j) {
        size_t at = scanLeft(sc, p, ids[j], m->skip);
        if (at == npos) return false;
        params[j] = sc.s + at;
      }
      m->newLeftPos = p;
      return true;
    }
    case __lc_InNewRight: {
      if (m->forward) return false;
      size_t p = m->newRightPos;
      for (int j = 0; j < n; ++j) {
        size_t at = scanRight(m->newRight, p, ids[j], m->skip);
        if (at == npos) return false;
        params[j] = m->newRight.s + at;
      }
      m->newRightPos = p;
      return true;
    }
  }
  return false;
}

// Runs the body; on `produce` the successor stays appended to `out`, otherwise it is discarded.
bool Engine::applyRule(const __lc_Rule& r, Match& m, ModuleBuffer& out) {
  size_t mark = out.size();
  __lc_Ctx ctx{out.raw(), 0, this, &m};
  const __lc_Rule* savedRule = runningRule_;  // a rule runs inside another through OutputFrame
  __lc_Ctx* savedCtx = activeCtx_;
  runningRule_ = &r;
  activeCtx_ = &ctx;
  if (!inspecting()) {
    r.body(&ctx, m.params);
  } else {
    auto t0 = Profile::Clock::now();
    r.body(&ctx, m.params);
    if (profile_) profile_->record(size_t(&r - model_->rules), ctx.produced != 0, Profile::Clock::now() - t0);
    if (ctx.produced && &r - model_->rules == breakRule_) breakHit_ = true;
  }
  activeCtx_ = savedCtx;
  runningRule_ = savedRule;
  if (!ctx.produced) out.resize(mark);
  else lastApplied_ = &r;
  return ctx.produced != 0;
}

bool Engine::tryRules(int kind, int group, int groupZero, const Scan& old, size_t pos, const Scan& newLeft,
                      const Scan& newRight, ModuleBuffer& out, Match& m) {
  __lc_ModuleId id = ModuleTable::idAt(old.s + pos);
  for (int pass = 0; pass < 2; ++pass) {
    int g = pass == 0 ? group : groupZero;
    if (pass == 1 && group == groupZero) break;
    const RuleList* rules = candidates(kind, g, id, false);
    if (!rules) continue;
    for (const __lc_Rule* r : *rules) {
      if (!matchRule(*r, old, pos, newLeft, newRight, m)) continue;
      if (applyRule(*r, m, out)) return true;
    }
  }
  return false;
}

// ---- derivation steps

bool Engine::deriveForward(int group) {
  next_.clear();
  const char* s = string_.data();
  size_t n = string_.size();
  bracketsFor(s, n);
  auto noBrackets = llvm::make_scope_exit([&] { bracketsFor(nullptr, 0); });
  Scan old{s, n, ring_};
  Match m;
  m.forward = true;
  // Counting costs about a nanosecond a module; the limit check needs a count only past
  // 4 bytes × maxModules, so a string a quarter of that size starts counting (one that grows
  // past it uncounted is walked once by the check, as before).
  const bool counting = n > limits_.maxModules;
  size_t pos = 0, modules = 0;
  // Provenance: `at` counts the old string's modules up to pos.
  const bool origins = tracking_origins_;
  size_t at = 0;
  if (origins) nextOrigins_.clear();
  auto originAt = [&](size_t k) { return k < origins_.size() ? origins_[k] : Origin{}; };
  while (pos < n) {
    if (cancel_.load(std::memory_order_relaxed)) return false;  // Stop during a long step
    checkStop(n + next_.size());
    __lc_ModuleId id = ModuleTable::idAt(s + pos);
    if (id == __lc_id_Cut) {
      // The Cut and the rest of its branch go; the closing EB is processed normally.
      size_t e = findEndOfBranch(old, modules_.next(s, pos));
      if (e == npos) break;
      if (origins)
        for (size_t q = pos; q < e; q = modules_.next(s, q)) ++at;
      pos = e;
      continue;
    }
    Scan newLeft{next_.data(), next_.size(), false};
    bool applied = false;
    for (int pass = 0; pass < 2 && !applied; ++pass) {
      int g = pass == 0 ? group : 0;
      if (pass == 1 && group == 0) break;
      const RuleList* rules = candidates(__lc_Production, g, id, false);
      if (!rules) continue;
      for (const __lc_Rule* r : *rules) {
        if (!matchRule(*r, old, pos, newLeft, Scan{nullptr, 0, false}, m)) continue;
        const size_t from = next_.size();
        if (applyRule(*r, m, next_)) {
          applied = true;
          if (counting)  // the successor just written: in cache
            for (size_t q = from; q < next_.size(); q = modules_.next(next_.data(), q)) ++modules;
          if (origins)
            for (size_t q = from; q < next_.size(); q = modules_.next(next_.data(), q))
              nextOrigins_.push_back({int32_t(r - model_->rules), step_});
          // Advance past the strict predecessor (wrapping in a ring ends the step).
          size_t p = pos;
          for (int j = 0; j < r->nStrict && p < n; ++j) p = modules_.next(s, p), ++at;
          if (p <= pos) p = n;
          pos = p;
          break;
        }
        newLeft = Scan{next_.data(), next_.size(), false};
      }
    }
    if (!applied) {
      size_t e = modules_.next(s, pos);
      next_.append(s + pos, e - pos);
      pos = e;
      modules += counting;
      if (origins) nextOrigins_.push_back(originAt(at++));
    }
  }
  string_.swap(next_);
  if (origins) origins_.swap(nextOrigins_);
  if (counting) noteCount(modules);
  else forgetCount();
  derived_ = true;
  return true;
}

bool Engine::deriveBackward(int group) {
  // The result grows leftwards: `next_` holds it at its end, from `front` on.
  const char* s = string_.data();
  size_t n = string_.size();
  bracketsFor(s, n);
  auto noBrackets = llvm::make_scope_exit([&] { bracketsFor(nullptr, 0); });
  Scan old{s, n, ring_};
  size_t cap = std::max<size_t>(n * 2, 4096);
  next_.clear();
  next_.resize(cap);
  size_t front = cap;
  auto prepend = [&](const char* p, size_t len) {
    if (front < len) {
      size_t used = next_.size() - front;
      size_t ncap = std::max(next_.size() * 2, used + len + 4096);
      ModuleBuffer grown;
      grown.resize(ncap);
      std::memcpy(grown.data() + ncap - used, next_.data() + front, used);
      next_.swap(grown);
      front = ncap - used;
    }
    front -= len;
    std::memcpy(next_.data() + front, p, len);
  };
  Match m;
  m.forward = false;
  // Provenance, built right to left and turned round at the end: `fromRight` counts the old
  // string's modules right of pos.
  const bool origins = tracking_origins_;
  size_t fromRight = 0;
  if (origins) nextOrigins_.clear();
  auto originFromRight = [&](size_t k) { return k < origins_.size() ? origins_[origins_.size() - 1 - k] : Origin{}; };
  size_t pos = n;
  while (pos > 0) {
    if (cancel_.load(std::memory_order_relaxed)) return false;  // Stop during a long step
    checkStop(n + next_.size());
    size_t q = modules_.prev(s, pos);
    __lc_ModuleId id = ModuleTable::idAt(s + q);
    Scan newRight{next_.data() + front, next_.size() - front, false};
    bool applied = false;
    for (int pass = 0; pass < 2 && !applied; ++pass) {
      int g = pass == 0 ? group : 0;
      if (pass == 1 && group == 0) break;
      const RuleList* rules = candidates(__lc_Production, g, id, true);
      if (!rules) continue;
      for (const __lc_Rule* r : *rules) {
        size_t start = q;
        bool ok = true;
        for (int j = 1; j < r->nStrict && ok; ++j) {
          if (start == 0) ok = false;
          else start = modules_.prev(s, start);
        }
        if (!ok || !matchRule(*r, old, start, Scan{nullptr, 0, false}, newRight, m)) continue;
        scratch_.clear();
        if (applyRule(*r, m, scratch_)) {
          prepend(scratch_.data(), scratch_.size());
          if (origins) {
            for (size_t k = 0; k < scratch_.size(); k = modules_.next(scratch_.data(), k))
              nextOrigins_.push_back({int32_t(r - model_->rules), step_});
            fromRight += size_t(r->nStrict);
          }
          pos = start;
          applied = true;
          break;
        }
      }
    }
    if (!applied) {
      prepend(s + q, pos - q);
      pos = q;
      if (origins) nextOrigins_.push_back(originFromRight(fromRight++));
    }
  }
  size_t used = next_.size() - front;
  std::memmove(next_.data(), next_.data() + front, used);
  next_.resize(used);
  forgetCount();
  if (origins) {
    std::reverse(nextOrigins_.begin(), nextOrigins_.end());
    origins_.swap(nextOrigins_);
  }
  string_.swap(next_);
  derived_ = true;
  return true;
}

bool Engine::deriveGillespie(int group) {
  std::vector<Reaction>& reactions = reactions_;
  ModuleBuffer& pieces = pieces_;
  reactions.clear();
  pieces.clear();
  const char* s = string_.data();
  size_t n = string_.size();
  Scan old{s, n, false};
  Match m;
  m.forward = true;
  size_t pos = 0;
  while (pos < n) {
    if (cancel_.load(std::memory_order_relaxed)) return false;  // Stop during a long step
    checkStop(n + pieces.size());
    __lc_ModuleId id = ModuleTable::idAt(s + pos);
    if (id == __lc_id_Cut) {
      size_t e = findEndOfBranch(old, modules_.next(s, pos));
      if (e == npos) break;
      pos = e;
      continue;
    }
    if (const RuleList* rules = candidates(__lc_Production, group, id, false)) {
      for (const __lc_Rule* r : *rules) {
        if (!matchRule(*r, old, pos, Scan{nullptr, 0, false}, Scan{nullptr, 0, false}, m)) continue;
        scratch_.clear();
        __lc_Ctx ctx{scratch_.raw(), 0, this, &m};
        runningRule_ = r;
        activeCtx_ = &ctx;
        r->body(&ctx, m.params);
        activeCtx_ = nullptr;
        runningRule_ = nullptr;
        if (scratch_.size() == 0) break;
        if (ModuleTable::idAt(scratch_.data()) != __lc_id_Propensity) {
          print("Invalid successor for Gillespie production: it must start with a propensity\n");
          break;
        }
        size_t end = pos;
        for (int j = 0; j < r->nStrict; ++j) end = modules_.next(s, end);
        // Split the successor at each Propensity(v) module.
        const char* g = scratch_.data();
        size_t gp = 0, gn = scratch_.size();
        while (gp < gn) {
          float v;
          std::memcpy(&v, g + gp + offsetof(__lc_R_Propensity, p0), sizeof v);
          if (!(v >= 0) || std::isinf(v)) v = 0;
          gp = modules_.next(g, gp);
          size_t from = pieces.size();
          while (gp < gn && ModuleTable::idAt(g + gp) != __lc_id_Propensity) {
            size_t e = modules_.next(g, gp);
            pieces.append(g + gp, e - gp);
            gp = e;
          }
          reactions.push_back({v, pos, end, from, pieces.size()});
        }
        // Every matching production of a Gillespie group is a reaction of its own (lpfg tries
        // them all; only an empty or invalid successor ends the search).
      }
    }
    pos = modules_.next(s, pos);
  }
  double sum = 0;
  for (auto& r : reactions) sum += r.propensity;
  if (!(sum > 0)) return true;  // nothing can happen: the string stays
  double x = sum * gillespieRandom_.next();
  const Reaction* chosen = nullptr;
  for (auto& r : reactions) {
    x -= r.propensity;
    if (x <= 0) {
      chosen = &r;
      break;
    }
  }
  // lpfg's formula and rounding: t - (1/sum)·log(1 - r).
  gillespieTime_ -= 1.0 / sum * std::log(1.0 - gillespieRandom_.next());
  if (!chosen) return true;  // rounding left x above 0: lpfg replaces nothing
  next_.clear();
  next_.append(s, chosen->from);
  next_.append(pieces.data() + chosen->succFrom, chosen->succTo - chosen->succFrom);
  next_.append(s + chosen->to, n - chosen->to);
  forgetCount();
  forgetOrigins();
  string_.swap(next_);
  derived_ = true;
  return true;
}

// Decomposition and interpretation: recursive per module, one module at a time (lpfg advances
// by one even after a multi-module match). When the depth is exhausted the original module stays.
void Engine::expand(int kind, char* src, size_t n, int depth, int group, ModuleBuffer* target, Turtle* turtle,
                    const std::function<void(const char*)>* sink, size_t level) {
  // One successor buffer per level the recursion reaches, not per level the depth allows: a
  // `maximum depth` of a billion costs nothing until decomposition goes that deep.
  if (levels_.size() <= level) levels_.resize(level + 1);
  if (!levels_[level]) levels_[level] = std::make_unique<ModuleBuffer>();
  ModuleBuffer& succ = *levels_[level];
  Scan old{src, n, ring_ && kind == __lc_Decomposition};
  Match m;
  m.forward = true;
  m.contexts = false;
  // Provenance of decomposition: a module left as it was keeps its origin; what a rule made has
  // the innermost rule's (expandOrigin_, set around the recursion).
  const bool origins = tracking_origins_ && target == &decomposed_;
  const bool topLevel = src == string_.data() && !target;
  const bool topOfString = src == string_.data();
  size_t at = 0;
  auto emit = [&](char* rec) {
    if (origins)
      decomposedOrigins_.push_back(!topOfString ? expandOrigin_ : at < origins_.size() ? origins_[at] : Origin{});
    if (target) {
      target->append(rec, modules_.recordSize(ModuleTable::idAt(rec)));
    } else {
      turtle->execute(rec);
      if (communicating_) communicate(src, size_t(rec - src), n, *turtle);
      if (sink) (*sink)(rec);
    }
  };
  // A module no rule of `group` matches tries production group 0's rules (of the same view
  // group, for interpretation rules), as lpfg does.
  const int groupZero = kind == __lc_Interpretation ? ruleTableKey(kind, 0, group & 0xffff) : 0;
  // Without a rule of this kind in either group (most models' interpretation), every module goes
  // straight to the turtle or the target: no lookups a module.
  const bool anyRules = byFirst_[kind].count(group) || byFirst_[kind].count(groupZero);
  size_t pos = 0;
  while (pos < n) {
    checkStop(target ? string_.size() + target->size() : 0);
    if (topLevel && tracking_) tracking_->currentSource = (uint32_t)pos;
    succ.clear();
    Scan newLeft = target ? Scan{target->data(), target->size(), false} : Scan{nullptr, 0, false};
    bool applied = anyRules && tryRules(kind, group, groupZero, old, pos, newLeft, Scan{nullptr, 0, false}, succ, m);
    if (applied && depth > 0) {
      // The successor buffer of this level is reused by deeper levels: work on a copy.
      if (copies_.size() <= copiesInUse_) copies_.push_back(std::make_unique<ModuleBuffer>());
      ModuleBuffer& local = *copies_[copiesInUse_++];
      local.clear();
      local.append(succ.data(), succ.size());
      const Origin outer = expandOrigin_;
      if (origins) expandOrigin_ = {int32_t(lastApplied_ - model_->rules), step_};
      expand(kind, local.data(), local.size(), depth - 1, group, target, turtle, sink, level + 1);
      expandOrigin_ = outer;
      --copiesInUse_;
    } else {
      emit(src + pos);
    }
    pos = modules_.next(src, pos);
    ++at;
  }
}

void Engine::decompose(int group) {
  if (!hasDecomposition_) return;
  forgetCount();
  decomposed_.clear();
  decomposedOrigins_.clear();
  expand(__lc_Decomposition, string_.data(), string_.size(), decompositionDepth_, group, &decomposed_, nullptr, nullptr);
  string_.swap(decomposed_);
  if (tracking_origins_) origins_.swap(decomposedOrigins_);
}

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

namespace {
// Text made in `text` and written to a stream a megabyte at a time (spill()), the rest when it
// goes: a string's text need not be held whole.
struct ChunkedText {
  static constexpr size_t kChunk = size_t(1) << 20;
  explicit ChunkedText(std::ostream& out) : out(out) { text.reserve(kChunk + 4096); }
  ~ChunkedText() { out.write(text.data(), (std::streamsize)text.size()); }
  void spill() {
    if (text.size() < kChunk) return;
    out.write(text.data(), (std::streamsize)text.size());
    text.clear();
  }
  std::ostream& out;
  std::string text;
};
}  // namespace

llvm::Error Engine::writeTurtleText(std::ostream& out, int vgroup) {
  ChunkedText chunks(out);
  return interpret([&](const char*) { chunks.spill(); }, nullptr, &chunks.text, vgroup);  // after each module
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

// lpfg's InterpretForEnvironment: one interpretation of the string (view group 0), which fills
// GetPos & co. and sends E1/E2/EA20; NoEnvironment() skips both.
void Engine::environmentPass() {
  if (ignoreEnvironment_ || (!hasQueries_ && !environment_)) return;
  Turtle& turtle = acquireTurtle();
  turtle.reset(turtleSetup_, nullptr, &queryTropisms_);
  communication_.records.clear();
  communication_.sent.clear();
  communicating_ = environment_ != nullptr;
  expand(__lc_Interpretation, string_.data(), string_.size(), interpretationDepth_,
         ruleTableKey(__lc_Interpretation, group_, 0), nullptr, &turtle, nullptr);
  communicating_ = false;
  --turtlesInUse_;
  // As in lpfg, a pass that met no communication module does not wake the program.
  if (!environment_ || communication_.records.empty()) return;
  auto answers = environment_->exchange(communication_.records, step_ + 1, [] { ModelGuard::checkpoint(); });
  if (!answers) throw Fault{FaultKind::Environment, llvm::toString(answers.takeError())};
  applyAnswers(*answers);
}

namespace {
bool isCommunication(__lc_ModuleId id) { return id == __lc_id_E1 || id == __lc_id_E2 || id == __lc_id_EA20; }
// How many floats a communication module carries.
size_t valueCount(__lc_ModuleId id) { return id == __lc_id_E1 ? 1 : id == __lc_id_E2 ? 2 : 20; }
// Where a communication module's floats start in its record (E2's two and EA20's twenty follow).
size_t parameterOffset(__lc_ModuleId id) {
  return id == __lc_id_E1 ? offsetof(__lc_R_E1, p0) : id == __lc_id_E2 ? offsetof(__lc_R_E2, p0) : offsetof(__lc_R_EA20, p0);
}

void appendTurtleLine(std::string& out, const std::string& format, double x, double y, double z) {
  if (format.empty()) return;
  char buf[512];
  // The format was checked when the .e file was read: at most three floating-point conversions.
  int n = std::snprintf(buf, sizeof buf, format.c_str(), x, y, z);
  if (n > 0) out.append(buf, std::min<size_t>(size_t(n), sizeof buf - 1));
  out += '\n';
}
}  // namespace

// One communication module met by the environmental pass: `ID E(v,…)` with lpfg's %f values,
// the module after it in the same string when `following module:` asks, then the turtle lines.
// The id is the module's byte offset in the string; a module an interpretation rule produced
// is not in the string, so it gets an id past the string's end and its answer goes nowhere.
void Engine::communicate(const char* src, size_t pos, size_t n, const Turtle& turtle) {
  const __lc_ModuleId id = ModuleTable::idAt(src + pos);
  if (!isCommunication(id)) return;
  const CommSpec& spec = environment_->spec();
  const bool inString = src == string_.data();
  const size_t sentId = inString ? pos : string_.size() + communication_.records.size();
  if (inString) communication_.sent[pos] = id;
  std::string& out = communication_.records.emplace_back();
  char buf[64];
  std::snprintf(buf, sizeof buf, "%zu E(", sentId);
  out += buf;
  const char* p = src + pos + parameterOffset(id);
  for (size_t i = 0; i < valueCount(id); ++i) {
    float v;
    std::memcpy(&v, p + i * sizeof(float), sizeof v);
    std::snprintf(buf, sizeof buf, i ? ",%f" : "%f", double(v));
    out += buf;
  }
  out += ')';
  size_t next = modules_.next(src, pos);
  if (spec.followingModule && next < n) modules_.format(src + next, out);
  out += '\n';
  const TurtleState& t = turtle.state();
  appendTurtleLine(out, spec.position, t.position.x, t.position.y, t.position.z);
  appendTurtleLine(out, spec.heading, t.heading.x, t.heading.y, t.heading.z);
  appendTurtleLine(out, spec.left, t.left.x, t.left.y, t.left.z);
  appendTurtleLine(out, spec.up, t.up.x, t.up.y, t.up.z);
  appendTurtleLine(out, spec.lineWidth, t.width, t.width, t.width);
  appendTurtleLine(out, spec.scaleFactor, t.csScale, t.csScale, t.csScale);
}

// The answers, as lpfg takes them: `ID E(v,…)` for a module sent this step; E1 takes exactly one
// value, E2 two, EA20 one to twenty (the rest kept, or zeroed with -cleanEA20). Anything else is
// a warning and changes nothing; modules without an answer keep their values.
void Engine::applyAnswers(const std::string& answers) {
  const std::string& file = environment_->spec().file;
  size_t start = 0;
  while (start < answers.size()) {
    size_t end = answers.find('\n', start);
    if (end == std::string::npos) end = answers.size();
    std::string line = answers.substr(start, end - start);
    start = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const char* c = line.c_str();
    char* after = nullptr;
    unsigned long long at = std::strtoull(c, &after, 10);
    size_t open = line.find('(');
    if (after == c || open == std::string::npos) {
      warn(file + ": warning: the environmental program's answer '" + line.substr(0, 80) +
           "' is not 'ID E(values)': ignored");
      continue;
    }
    size_t close = line.find(')', open);
    const std::vector<float> values = communicationValues(
        std::string_view(line).substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1));
    auto sent = communication_.sent.find(size_t(at));
    const bool known = sent != communication_.sent.end();
    const __lc_ModuleId module = known ? sent->second : __lc_id_E1;
    const char* name = known ? modules_.info(module).name : nullptr;
    const size_t want = valueCount(module);
    const bool fits = module == __lc_id_EA20 ? values.size() <= want : values.size() == want;
    if (!known || !fits) {
      warn(file + ": warning: invalid answer from the environmental program for position " + std::to_string(at) +
           (name ? std::string(" (") + name + ", " + std::to_string(values.size()) + " values)" : std::string(" (no such module was sent)")) +
           ": ignored");
      continue;
    }
    char* p = string_.data() + at + parameterOffset(module);
    for (size_t i = 0; i < want; ++i) {
      if (i >= values.size() && !cleanEA20_) break;
      float v = i < values.size() ? values[i] : 0.0f;
      std::memcpy(p + i * sizeof(float), &v, sizeof v);
    }
  }
}

void Engine::warn(const std::string& message) const {
  if (hooks_ && hooks_->warning) hooks_->warning(message);
  else std::fprintf(stderr, "%s\n", message.c_str());
}

// ---- the whole run

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
  length_ = modelDerivationLength();
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

// ---- faults

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
    who = r.kind == __lc_Production      ? "production "
          : r.kind == __lc_Decomposition ? "decomposition rule "
                                         : "interpretation rule ";
    who += r.predecessor ? r.predecessor : "";
  } else if (runningCall_) {
    who = runningCall_;
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

std::string Engine::text(const ModuleBuffer& str) const {
  std::ostringstream out;
  writeText(str, out);
  return std::move(out).str();
}

void Engine::writeText(const ModuleBuffer& str, std::ostream& out) const {
  ChunkedText chunks(out);
  for (size_t p = 0; p < str.size() && out; p = modules_.next(str.data(), p)) {
    modules_.format(str.data() + p, chunks.text);
    chunks.text += '\n';
    chunks.spill();
  }
}

llvm::Error Engine::writeTextFile(const std::string& path) const {
  return writeWholeFile(path, [&](std::ostream& out) {
    writeText(string_, out);
    return llvm::Error::success();
  });
}

llvm::Error Engine::writeBinary(const std::string& path) const {
  return writeWholeFile(path, llvm::StringRef(string_.data(), string_.size()));
}

llvm::Error Engine::readBinary(const std::string& path) {
  auto file = textfile::readFile(path);
  if (!file) return file.takeError();
  const llvm::StringRef bytes = (*file)->getBuffer();
  // Validate every record before replacing the string.
  size_t p = 0;
  while (p < bytes.size()) {
    if (bytes.size() - p < 4)
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: truncated module at byte %zu", path.c_str(), p);
    __lc_ModuleId id = ModuleTable::idAt(bytes.data() + p);
    if (!modules_.valid(id))
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: unknown module id %u at byte %zu", path.c_str(),
                                     (unsigned)id, p);
    size_t size = modules_.recordSize(id);
    if (bytes.size() - p < size || ModuleTable::idAt(bytes.data() + p + size - 2) != id)
      return llvm::createStringError(llvm::inconvertibleErrorCode(), "%s: error: corrupt module '%s' at byte %zu", path.c_str(),
                                     modules_.info(id).name, p);
    // A pointer (Label's text, a T* parameter) written by another run points into that run's
    // memory: the turtle or model code would follow it into whatever is there now (found by
    // fuzz_strb). A struct or typedef hiding a pointer is not seen here.
    const __lc_ModuleInfo& info = modules_.info(id);
    for (uint32_t i = 0; i < info.nFields; ++i) {
      const __lc_Field& f = info.fields[i];
      std::string_view type = f.typeName ? f.typeName : "";
      while (!type.empty() && type.back() == ' ') type.remove_suffix(1);
      if (f.kind == __lc_FK_Text || (!type.empty() && type.back() == '*'))
        return llvm::createStringError(llvm::inconvertibleErrorCode(),
                                       "%s: error: module '%s' at byte %zu has a pointer parameter (%s), which a binary "
                                       "string cannot carry from one run to another",
                                       path.c_str(), info.name, p, f.kind == __lc_FK_Text ? "const char*" : f.typeName);
    }
    p += size;
  }
  forgetCount();
  forgetOrigins();
  string_.clear();
  string_.append(bytes.data(), bytes.size());
  return llvm::Error::success();
}

}  // namespace lcjit::runtime
