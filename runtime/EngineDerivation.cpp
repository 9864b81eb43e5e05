// The engine's three derivation modes: a forward step (left to right, new left context), a
// backward step (right to left, new right context), and a Gillespie step (every matching
// production of a Gillespie group a reaction, one chosen by its propensity); then the expansion
// shared by decomposition and interpretation rules (expand), and decomposition after a step.
// Engine.cpp's stepGuarded chooses the mode; EngineMatching.cpp matches the rules.
//
// Sections, in order (each begins with a `// ----` rule): Derivation steps (deriveForward,
// deriveBackward, deriveGillespie) · Decomposition and interpretation rules (expand, decompose).
#include <algorithm>
#include <cmath>
#include <cstring>

#include <llvm/ADT/ScopeExit.h>

#include "runtime/EngineInternal.h"

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// Derivation steps

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
        if (onlyRule_ && (r != onlyRule_ || onlyRuleApplied_)) continue;  // deriveSequential's
        if (!matchRule(*r, old, pos, newLeft, Scan{nullptr, 0, false}, m)) continue;
        const size_t from = next_.size();
        cutBranch_ = false;
        if (applyRule(*r, m, next_)) {
          applied = true;
          onlyRuleApplied_ = true;
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
          if (cutBranch_) {
            // The rest of the branch goes with it (XL's SPO deletion). A branch the deleted
            // module began, left empty, goes too: its SB and its EB (XL has no brackets, only
            // the branch's edge to that module).
            cutBranch_ = false;
            size_t e = pos < n ? findEndOfBranch(old, pos) : n;
            if (e == npos) e = n;
            if (origins)
              for (size_t q = pos; q < e; q = modules_.next(s, q)) ++at;
            pos = e;
            const size_t sb = from > 0 ? modules_.prev(next_.data(), from) : 0;
            if (e < n && next_.size() == from && from > 0 && ModuleTable::idAt(next_.data() + sb) == __lc_id_SB) {
              next_.resize(sb);
              modules -= counting;
              if (origins) nextOrigins_.pop_back(), ++at;
              pos = modules_.next(s, e);
            }
          }
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

bool Engine::deriveSequential(int group) {
  // Each production in turn, as GroIMP's rules are tried in order, until one applies: a forward
  // derivation in which that production alone may apply, once (a step that applies none copies
  // the string).
  auto clear = llvm::make_scope_exit([&] { onlyRule_ = nullptr; });
  for (int pass = 0; pass < 2; ++pass) {
    const int g = pass == 0 ? group : 0;
    if (pass == 1 && group == 0) break;
    for (uint32_t k = 0; k < model_->nRules; ++k) {
      const __lc_Rule& r = model_->rules[k];
      if (r.kind != __lc_Production || r.group != g) continue;
      onlyRule_ = &r;
      onlyRuleApplied_ = false;
      if (!deriveForward(group)) return false;
      if (onlyRuleApplied_) return true;
    }
  }
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

// ---------------------------------------------------------------------------------------------
// Decomposition and interpretation rules

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

}  // namespace lcjit::runtime
