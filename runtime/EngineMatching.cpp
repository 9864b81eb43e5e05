// Context matching (manual appendix 9, as lpfg matches): the SB/EB pairs of the predecessor
// string, the scans right and left of a module, a rule's pattern against the string, the
// InXContext calls of a rule body, and a rule's body run on a match. The derivation loops
// (EngineDerivation.cpp) and decomposition and interpretation (expand) call tryRules, matchRule
// and applyRule.
//
// Sections, in order (each begins with a `// ----` rule): Brackets (bracketsFor, bracketsOf,
// the ends of a branch) · Scans (scanRight, scanLeft) · Rules (matchRule, inContext, applyRule,
// tryRules).
#include <algorithm>

#include "runtime/EngineInternal.h"

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// Brackets

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

// ---------------------------------------------------------------------------------------------
// Scans

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

// ---------------------------------------------------------------------------------------------
// Rules

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

const char* Engine::findModule(__lc_Ctx* c, __lc_ModuleId id, size_t* at) const {
  const Match* m = c ? static_cast<const Match*>(c->match) : nullptr;
  const char* s = m ? m->old.s : string_.data();
  const size_t n = m ? m->old.n : string_.size();
  for (size_t p = *at; p < n; p = modules_.next(s, p))
    if (ModuleTable::idAt(s + p) == id) {
      *at = modules_.next(s, p);
      return s + p;
    }
  *at = n;
  return nullptr;
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

}  // namespace lcjit::runtime
