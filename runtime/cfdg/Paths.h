// Context Free's paths, as cfdg 3.4 builds, measures and paints them. A path is a shape whose body
// is path operations (MOVETO, LINETO, ARCTO, CURVETO, …, CLOSEPOLY: AGG path_storage calls) and
// path commands (STROKE, FILL: paint the operations since the previous command). Its body runs
// when the path is finished, from the path's seed, measuring each command's outline with AGG's
// converters (the bounds the picture is fitted to), and runs again from the same seed when it is
// drawn, painting each command. The compiled body calls the __cf_path… functions of lcjit/cfdg.h,
// defined here.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "runtime/cfdg/Expander.h"
#include "runtime/cfdg/PathVertex.h"

namespace lcjit::runtime::cfdg {

// Context Free's flags of path operations and commands (CF::…, the same numbers).
enum PathFlag : int {
  kJoinMask = 7, kJoinPresent = 8, kCapShift = 4, kCapMask = 7 << 4, kCapPresent = 8 << 4,
  kArcCW = 1 << 8, kArcLarge = 1 << 9, kContinuous = 1 << 10, kAlign = 1 << 11, kEvenOdd = 1 << 12,
  kIsoWidth = 1 << 13, kFill = 1 << 14, kBlendPresent = 1 << 20
};

// A command as cfdg records it: the first vertex of the operations it covers (to the next stop),
// its flags (CF::… and kFill, with the blend mode of its state), stroke width and miter limit.
struct PathCommandInfo {
  unsigned index = 0;
  int flags = 0;
  double width = 0.1;
  double miterLimit = 4.0;
};

// Paints one command: its outline (the covered vertices), how, and the state it paints with.
using PathPainter =
    std::function<void(const std::vector<PathVertex>& outline, const PathCommandInfo& info, const __cf_State& state)>;

class PathEngine {
 public:
  // `bound`: the run's shape values, which a sub-path element may name (null: none yet).
  explicit PathEngine(const __cf_Design& design, const std::deque<std::vector<double>>* bound = nullptr);
  ~PathEngine();
  PathEngine(const PathEngine&) = delete;
  PathEngine& operator=(const PathEngine&) = delete;

  bool isPath(int shape) const { return shape >= 4 && design_.shapes[shape].isPath != 0; }

  // Finishes path `shape` with state `s`: runs its body in `c` from `seed` (c->cur is left where
  // the body leaves it, as cfdg leaves its one running seed), measuring each command's outline
  // with curves flattened for world scale `scale`. Returns the union of the commands' boxes
  // (invalid if none) and sets `area` to its area.
  Bounds measure(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed, double scale,
                 double& area);
  // A primitive's outline was measured, stroked 0.1 wide, with this world transform determinant:
  // cfdg measures primitives with the converters it measures paths with, whose curve angle
  // tolerance (set by strokes, used by fills) carries over.
  void primitiveMeasured(double determinant);
  // Runs finished path `p` of expansion `e` again (with its rand_static() values and its frame's
  // time), giving each command to `paint`.
  void paint(const FinishedPath& p, const Expansion& e, const PathPainter& paint);
  // Context Free's `-V` picture of finished path `p`: per command (and per copy of a tiled
  // picture, `copies`: Tiling.h), a group with its paint and its transform (the path's state, the
  // fit `f`, the copy's offset, `toSvg`) holding its outline, an SVG path (numbered from
  // `nextId`), or a use of the previous one when a command paints the same outline again.
  // Numbers have `precision` significant digits: cfdg's stream writes 6 until its first
  // transform, 8 from then on.
  std::string svg(const FinishedPath& p, const Expansion& e, const Framing& f,
                  const std::vector<std::pair<double, double>>& copies, const Affine& toSvg, int& nextId,
                  int& precision);

  struct Run;
  struct Measure;

 private:
  const __cf_Design& design_;
  const std::deque<std::vector<double>>* bound_;
  std::vector<int> firstRule_;  // per shape: its first rule (a path's body), -1 for none
  std::unique_ptr<Measure> measure_;
};

// The functions compiled path bodies call, by name, for the JIT to link them.
std::vector<std::pair<std::string, void*>> pathHostSymbols();

}  // namespace lcjit::runtime::cfdg
