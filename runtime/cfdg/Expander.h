// The shape-expansion engine of Context Free designs (CFDG): the largest unfinished shape is
// expanded next, by a rule of its shape chosen at random by weight; a primitive is finished as
// soon as it is made, and the picture's bounds (and so the size below which shapes are no longer
// expanded) grow with each. The design's rule bodies are compiled code (lcjit/cfdg.h); this
// engine runs them, with Context Free 3.4's random numbers, queue order and size cut-off, so that
// a variation gives the shapes Context Free gives, in its order, to the last bit.
#pragma once
#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "runtime/Profile.h"
#include "runtime/cfdg/Affine.h"
#include "runtime/include/lcjit/cfdg.h"
#include "support/HugePages.h"

namespace lcjit::runtime::cfdg {

// An axis-aligned box; invalid until something is merged into it.
struct Bounds {
  double minX = 0, minY = 0, maxX = -1, maxY = -1;
  bool valid() const { return minX <= maxX && minY <= maxY; }
  void merge(const Bounds& b);
  Bounds dilated(double factor) const;  // about its own centre
};

// How a picture is fitted to its pixels (Context Free's computeScale).
struct Fit {
  double scale = 0;
  int width = 0, height = 0;  // the fitted block, at most the picture's size
  Affine toBlock;             // world → the fitted block's pixels (y up)
};
Fit fitBounds(const Bounds& bounds, int width, int height, double border, bool exact);
// With different borders left and right (x) and top and bottom (y), as a frieze has.
Fit fitBounds(const Bounds& bounds, int width, int height, double borderX, double borderY, bool exact);

// A time interval (Context Free's animation time: a shape's, a frame's, the picture's).
struct TimeSpan {
  double begin = 0, end = 0;
  bool overlaps(const TimeSpan& t) const { return !(t.begin > end || t.end < begin); }
};
constexpr double kForever = std::numeric_limits<double>::infinity();

struct ExpandOptions {
  int width = 500, height = 500;
  double minimumSize = 0.3;  // pixels; `-x`
  double border = 2;          // `-b`: -1 … 2
  uint64_t variation = 1;
  uint64_t maxShapes = 500'000'000;
  size_t maxMemory = 0;  // bytes of the whole process; 0: half the physical memory (--max-memory)
  // Time: what ftime() and frame() give, and the frame's window, of which a design that uses
  // them keeps only the shapes whose time overlaps it (a single picture's is all time).
  double frameTime = 0, frame = 0;
  TimeSpan window{-kForever, kForever};
  bool keepTimes = false;  // keep each finished shape's time (Expansion::times): frames drawn from one run
  // A frame of an animation: a frieze keeps the picture's size (repeated across it), as cfdg's
  // animation canvas is made before the frieze's final size is known.
  bool animation = false;
  // Count each rule's runs and time its body (Expansion::ruleRuns): two clock readings a rule
  // run; off, nothing is counted.
  bool profile = false;
};

// What is kept of a drawn shape: only what its picture needs (a big design keeps millions).
// 80 bytes: the colour is kept once per run (Expansion::colours), the order and kind share a word.
struct FinishedShape {
  Affine transform;                 // the unit shape into world units
  double z = 0;                     // drawing order first
  double boxArea = 0;               // of the stroked outline's box, world units
  uint64_t order : 56 = 0;          // then the order shapes were finished in
  uint64_t shape : 8 = 0;           // a primitive: 0 CIRCLE, 1 SQUARE, 2 TRIANGLE, 3 FILL; or kPathShape
  uint32_t colour = 0;              // its device colour: Expansion::colours[colour]
  union {
    int blend = 0;  // a primitive's blend flag (CF::… with bit 20), 0 for src-over
    int path;       // a path's record in Expansion::paths (its commands have their own blend)
  };
};
constexpr uint8_t kPathShape = 4;

// What a finished path keeps to be drawn: cfdg draws a path by running its body again, from the
// same seed, with the same state and parameters (its commands' colours and transforms are made
// from them). Apart from the primitives' records: a design has few paths or many primitives.
struct FinishedPath {
  int shape = 0;  // the path's shape number in the design
  uint64_t seed = 0;
  __cf_State state{};
  std::unique_ptr<double[]> params;  // the parameter block (null for none)
};

// What a design's settings make of its picture, as the run found them: CF::Tile (a lattice the
// picture repeats on, or a frieze repeated in one direction) and CF::Size (a fixed frame) fix the
// bounds and the picture's size before the first shape; the borders; the pixel format's settings.
struct PictureSettings {
  bool tiled = false;      // a lattice in both directions
  int frieze = 0;          // repeated in one direction: 1 along x, 2 along y
  bool sized = false;      // CF::Size
  Affine tile;             // the lattice: CF::Tile's transform without its translation
  int width = 0, height = 0;        // the picture's size when tiling or CF::Size fix it (else 0)
  double borderX = 8, borderY = 8;  // fixed borders, pixels (CF::BorderFixed)
  int colour = -1, alpha = -1;      // CF::Color, CF::Alpha: 0 or 1 when set, else -1
  bool depth16 = false;             // CF::ColorDepth 16
};

struct Expansion {
  // In drawing order: z, then the order they were made. A deque: a million shapes grow it without
  // copying (or holding twice) what is there; in huge pages, without a fault for every 4 KiB.
  std::deque<FinishedShape, support::HugePageAllocator<FinishedShape>> shapes;
  // The finished shapes' device colours (Context Free's HSB → RGB, not premultiplied), each kept
  // once: most designs use a few colours over millions of shapes (a deque: a design whose every
  // shape has a colour of its own grows it without copying it).
  std::deque<std::array<double, 4>> colours;
  std::deque<FinishedPath> paths;      // the paths among them (FinishedShape::path)
  const __cf_Design* design = nullptr; // what was expanded, its rand_static() values and the frame's
  std::vector<double> statics;         // time (ftime(), frame()): a path's body runs again to be drawn
  double frameTime = 0, frame = 0;
  // The parameters of shape values made in the run (`foo(0.5)` for a parameter of type shape),
  // by a value's index (ShapeValue): a path that takes one draws it again.
  std::deque<std::vector<double>> bound;
  Bounds bounds;
  uint64_t expanded = 0;               // rule shapes expanded
  double background[4] = {0, 0, 1, 1}; // HSBA: white, changed by CF::Background
  std::string error;                   // a runtime error that stopped the run ("" if none)
  std::string errorAt;                 // where in the design, "file:line:col", when known
  // Why the run stopped before the design was finished, when a limit stopped it (the shape or
  // memory limit, an interrupt): the shapes made so far are kept, and drawn.
  std::string stopped;
  bool shapeLimit = false;  // it was the shape limit (-m, CF::MaxShapes): an end, not a failure
  PictureSettings picture;
  // Tiled and frieze designs (and with ExpandOptions::keepTimes): each finished shape's box (world
  // units, unstroked by the border), by its order - 1 (FILL's invalid), from which its copies
  // around the lattice are found (and a zoomed animation's frames their bounds).
  std::deque<Bounds> boxes;
  // The time the shapes span (from the start shape's), the picture's area when the design has no
  // time terms; with ExpandOptions::keepTimes each finished shape's time, by its order - 1.
  TimeSpan timeBounds;
  std::deque<TimeSpan> times;
  // With ExpandOptions::profile: by rule (its index in design->rules), how many times its body
  // ran (produced and ran: a rule always applies) and the time it took, its own: a path finished
  // by a body is the path's rule's time, not the body's.
  std::vector<runtime::RuleCounts> ruleRuns;
};

// A design's time settings (CF::Time, CF::FrameTime, CF::Frame), read as Context Free reads them
// before the run.
struct DesignTiming {
  bool hasTime = false, hasFrameTime = false, hasFrame = false;
  TimeSpan time;
  double timeScale = 1;
  std::string timeAt;
  double frameTime = 0, frame = 0;
};
DesignTiming timingOf(const __cf_Design& design);

// A shape value: the shape, and its parameters bound by the run (null for none). The value is
// shape + kBoundStride · (index + 1) for bound parameters, the shape's number without.
constexpr double kBoundStride = 1048576.0;
struct ShapeValue {
  int shape = -1;
  const double* params = nullptr;
};
// What `value` holds, or shape -1 when it is no shape of `design`.
ShapeValue shapeValue(const __cf_Design& design, const std::deque<std::vector<double>>& bound, double value);

// Expands `design` with `options`. `statics` are its rand_static() values.
Expansion expand(const __cf_Design& design, const ExpandOptions& options, const std::vector<double>& statics);

// The picture: each shape's transform to pixels (y up, as AGG draws), and which shapes are drawn
// (those not under the minimum size once the final scale is known).
struct Framing {
  int width = 0, height = 0;
  Fit fit;
  double offsetX = 0, offsetY = 0;  // the fitted block's place in the picture
  Affine toPixels;                  // world → picture pixels, y up
  // Tiled and frieze designs: the lattice in pixels, and its inverse (a frieze's: per axis).
  int tiling = 0;                   // 0 none, 1 tiled, 2 frieze
  Affine lattice, latticeInverse;
  // A frame of an animation drawn from one expansion: only shapes whose time (Expansion::times)
  // overlaps the window are drawn.
  const std::deque<TimeSpan>* times = nullptr;
  TimeSpan window{-kForever, kForever};
};
// `fitTo`: other bounds to fit (a zoomed animation's frame), else the expansion's.
Framing frame(const Expansion& expansion, const ExpandOptions& options, const Bounds* fitTo = nullptr);
bool drawn(const FinishedShape& shape, const Framing& framing, const ExpandOptions& options);

// Context Free's `-V` picture: SVG with each shape's matrix (8 significant digits) and colour.
std::string svgOf(const Expansion& expansion, const Framing& framing, const ExpandOptions& options);

// Device colour of an HSBA colour (Context Free's HSB → RGB), doubles in [0, 1].
void rgbOf(const double hsba[4], double rgba[4]);

// The functions compiled designs call, by name, for the JIT to link them.
std::vector<std::pair<std::string, void*>> hostSymbols();

// The random generator: xorshift64*, its step and a 52-bit double.
inline uint64_t stepSeed(uint64_t s) {
  s ^= s >> 12;
  s ^= s << 25;
  s ^= s >> 27;
  return s;
}
inline double drawDouble(uint64_t& s) {
  uint64_t out = s * 2685821657736338717ull;
  s = stepSeed(s);
  return double(out & 0xFFFFFFFFFFFFFull) * (1.0 / 4503599627370496.0);
}
constexpr uint64_t kSeedBase = 0x3DF41234ABCD330Eull;
// A variation code as Context Free reads one: a number, or letters in bijective base 26
// (A = 1, Z = 26, AA = 27 …). 0 when it is neither.
uint64_t variationOf(const std::string& code);
std::string variationName(uint64_t variation);

}  // namespace lcjit::runtime::cfdg
