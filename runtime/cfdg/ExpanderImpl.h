// What the files of the shape-expansion engine share (Expander.cpp, Adjustments.cpp,
// DesignFunctions.cpp): a state's transform as an Affine, and how a design's run stops. Internal
// to runtime/cfdg.
#pragma once
#include <string>

#include "runtime/cfdg/Affine.h"
#include "runtime/include/lcjit/cfdg.h"

namespace lcjit::runtime::cfdg {

constexpr double kPi = 3.14159265358979323846;

inline Affine affineOf(const __cf_State& s) { return {s.sx, s.shy, s.shx, s.sy, s.tx, s.ty}; }
inline void setAffine(__cf_State& s, const Affine& a) {
  s.sx = a.sx, s.shy = a.shy, s.shx = a.shx, s.sy = a.sy, s.tx = a.tx, s.ty = a.ty;
}
// `m` applied before the state's own transform.
inline void premultiplyState(__cf_State& s, const Affine& m) {
  Affine a = affineOf(s);
  a.premultiply(m);
  setAffine(s, a);
}

// A design's run stops with this message: an error of the design that its code or the engine
// finds (expand() catches it and reports the message).
struct Stop {
  std::string message;
};
[[noreturn]] inline void fail(__cf_Ctx*, const std::string& message) { throw Stop{message}; }

}  // namespace lcjit::runtime::cfdg
