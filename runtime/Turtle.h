// The turtle core (manual §5.2-5.3): position and H/L/U frame moved by the predefined modules,
// a branch stack, colour and width, and the answers to the query modules GetPos & co.
#pragma once
#include <vector>

#include "ModuleString.h"
#include "lcjit/vectors.h"

namespace lcjit::runtime {

struct TurtleState {
  V3f position{0, 0, 0};
  V3f heading{0, 1, 0};
  V3f left{-1, 0, 0};
  V3f up{0, 0, 1};
  int color = 1;
  float width = 1;
  // SetCoordinateSystem: the frame the affine-geometry modules (LineTo & co.) work in.
  bool hasCoordinateSystem = false;
  V3f csOrigin, csX{1, 0, 0}, csY{0, 1, 0}, csZ{0, 0, 1};
};

class Turtle {
 public:
  void reset();
  // Executes one module record; query modules (GetPos...) get the state written into `rec`.
  void execute(char* rec);
  const TurtleState& state() const { return state_; }

 private:
  void rotate(V3f& a, V3f& b, float degrees);  // a' = cos·a + sin·b, b' = cos·b − sin·a
  void rotateAbout(V3f axis, float degrees);
  V3f mapPoint(V3f p) const;
  TurtleState state_;
  std::vector<TurtleState> stack_;
};

}  // namespace lcjit::runtime
