// What the engine's files share (Engine.cpp, EngineMatching.cpp, EngineDerivation.cpp,
// EngineEnvironment.cpp, EngineStrings.cpp): the state of one rule application (Engine::Match)
// and the rule tables' keys. Internal to the engine.
#pragma once
#include <cstddef>
#include <cstdint>

#include "runtime/Engine.h"

namespace lcjit::runtime {

inline constexpr size_t npos = ~size_t(0);
inline constexpr int kMaxPattern = 5 * 32;

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

inline int ruleTableKey(int kind, int group, int vgroup) {
  // lpfg looks interpretation rules up by production group and view group together.
  return kind == __lc_Interpretation ? int((uint32_t(uint16_t(group)) << 16) | uint16_t(vgroup)) : group;
}

}  // namespace lcjit::runtime
