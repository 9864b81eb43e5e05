// The shape-expansion engine (Expander.h): the run (its queue, rule choice, finishing primitives,
// bounds), and the functions compiled designs call into it (lcjit/cfdg.h) to replace, start and
// configure shapes, with the table of every host function a design is linked against. The other
// functions designs call are in Adjustments.cpp and DesignFunctions.cpp; framing a finished
// expansion is in Framing.cpp.
#include "runtime/cfdg/Expander.h"

#include "runtime/ModelGuard.h"
#include "runtime/cfdg/ExpanderImpl.h"
#include "support/Elapsed.h"
#include "runtime/cfdg/Paths.h"
#include "runtime/cfdg/Symmetry.h"
#include "runtime/cfdg/Tiling.h"
#include "runtime/cfdg/UnfinishedShapes.h"

#include <agg_conv_stroke.h>
#include <agg_conv_transform.h>
#include <agg_bounding_rect.h>
#include <agg_path_storage.h>
#include <agg_trans_affine.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>

namespace lcjit::runtime::cfdg {
using runtime::Fault;
using runtime::FaultKind;
using runtime::ModelGuard;

// ---------------------------------------------------------------------------------------------
// The run
// ---------------------------------------------------------------------------------------------

void Bounds::merge(const Bounds& b) {
  if (!b.valid())
    return;
  if (!valid()) {
    *this = b;
    return;
  }
  minX = std::min(minX, b.minX);
  minY = std::min(minY, b.minY);
  maxX = std::max(maxX, b.maxX);
  maxY = std::max(maxY, b.maxY);
}

Bounds Bounds::dilated(double d) const {
  double cx = (minX + maxX) * 0.5, cy = (minY + maxY) * 0.5;
  return {d * (minX - cx) + cx, d * (minY - cy) + cy, d * (maxX - cx) + cx, d * (maxY - cy) + cy};
}

Fit fitBounds(const Bounds& b, int width, int height, double border, bool exact) {
  return fitBounds(b, width, height, border, border, exact);
}

Fit fitBounds(const Bounds& b, int width, int height, double borderX, double borderY, bool exact) {
  double vw = b.maxX - b.minX, vh = b.maxY - b.minY;
  if (!b.valid())
    vw = vh = 1.0;
  double tw = width - 2.0 * borderX, th = height - 2.0 * borderY;
  Fit f;
  f.width = width;
  f.height = height;
  if (vw / tw > vh / th) {
    f.scale = tw / vw;
    f.height = int(std::floor(f.scale * vh + 2.0 * borderY + 0.5));
    if (!exact) f.height += (f.height ^ height) & 1;
  } else {
    f.scale = th / vh;
    f.width = int(std::floor(f.scale * vw + 2.0 * borderX + 0.5));
    if (!exact) f.width += (f.width ^ width) & 1;
  }
  double ox = f.scale * (b.maxX + b.minX) / 2.0 - f.width / 2.0;
  double oy = f.scale * (b.maxY + b.minY) / 2.0 - f.height / 2.0;
  f.toBlock = Affine::scaling(f.scale, f.scale);
  f.toBlock.multiply(Affine::translation(-ox, -oy));
  return f;
}

namespace {

// The unit primitives' outlines, as paths (CIRCLE by eight points: its bounds are an octagon's).
agg::path_storage primitivePath(int shape) {
  agg::path_storage p;
  const double h = 0.5 / std::cos(kPi / 6.0), t = std::sqrt(2.0) / 4.0;
  std::vector<std::pair<double, double>> v;
  if (shape == 0) v = {{0.5, 0}, {t, t}, {0, 0.5}, {-t, t}, {-0.5, 0}, {-t, -t}, {0, -0.5}, {t, -t}};
  if (shape == 1) v = {{0.5, 0.5}, {-0.5, 0.5}, {-0.5, -0.5}, {0.5, -0.5}};
  if (shape == 2) v = {{0, h}, {-0.5, -h / 2.0}, {0.5, -h / 2.0}};
  p.move_to(v[0].first, v[0].second);
  for (size_t i = 1; i < v.size(); ++i) p.line_to(v[i].first, v[i].second);
  p.end_poly(agg::path_flags_close);
  return p;
}

// The points of a primitive's outline stroked 0.1 wide with miter joins and butt caps, in its own
// units, as AGG's stroker makes them: the outer contour first, then the inner. Only round joins
// and caps depend on the approximation scale; these inner joins are inside the outer outline, so
// the box of any transform of these points is the box Context Free measures.
struct StrokedOutline {
  std::vector<std::pair<double, double>> points;
  size_t outer = 0;  // the outer contour's points, first in `points`
};
StrokedOutline strokedOutline(int shape) {
  agg::path_storage path = primitivePath(shape);
  agg::conv_stroke<agg::path_storage> stroke(path);
  stroke.width(0.1);
  stroke.line_join(agg::miter_join);
  stroke.line_cap(agg::butt_cap);
  stroke.miter_limit(4.0);
  stroke.inner_join(agg::inner_round);
  StrokedOutline out;
  stroke.rewind(0);
  double x, y;
  for (unsigned cmd; !agg::is_stop(cmd = stroke.vertex(&x, &y));) {
    if (agg::is_vertex(cmd)) out.points.emplace_back(x, y);
    if (agg::is_end_poly(cmd) && out.outer == 0) out.outer = out.points.size();
  }
  return out;
}

// Whether the inner contour of a stroked outline can be left out of its box under this linear
// part: an inner point is 0.1 inside the outer contour, so in any direction its coordinate is
// short of the outer extreme by a tenth of the scale, far beyond rounding, unless a coefficient
// is so small (subnormal products) that rounding is no longer relative.
bool outerContourSuffices(const __cf_State& s) {
  for (double v : {s.sx, s.shy, s.shx, s.sy})
    if (v != 0.0 && !(std::fabs(v) >= 1e-280 && std::fabs(v) <= 1e280)) return false;
  return true;
}

// Expansion::colours as it is filled: a colour equal (to the bit) to one of the last few kept is
// not kept again. Most designs repeat a few colours over millions of shapes; a design whose shapes
// all differ keeps a colour per shape, as before there was a table. A table of recent colours by
// hash, not a complete index: looking up millions of colours in a large map cost more than it saved.
class ColourTable {
 public:
  explicit ColourTable(std::deque<std::array<double, 4>>& colours) : colours_(colours) {}
  uint32_t of(const std::array<double, 4>& rgba) {
    const Bits key = std::bit_cast<Bits>(rgba);
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint64_t v : key) h = (h ^ v) * 0xFF51AFD7ED558CCDull;
    // The colour is compared with the table's copy: the table stays in cache, the kept colours
    // of a design with millions of them do not.
    Recent& recent = recent_[(h >> 54) & (kRecent - 1)];
    if (recent.index != UINT32_MAX && recent.key == key) return recent.index;
    colours_.push_back(rgba);
    recent.key = key;
    return recent.index = uint32_t(colours_.size() - 1);
  }

 private:
  using Bits = std::array<uint64_t, 4>;
  struct Recent {
    Bits key{};
    uint32_t index = UINT32_MAX;
  };
  static constexpr size_t kRecent = 1024;
  std::deque<std::array<double, 4>>& colours_;
  std::vector<Recent> recent_ = std::vector<Recent>(kRecent);
};

struct Engine {
  const __cf_Design& design;
  const ExpandOptions& options;
  std::vector<double> cumulative;  // per rule: its shape's cumulative weight
  std::vector<std::vector<int>> rulesOf;
  Expansion result;
  double scale = 0, scaleArea = 0, minArea = 0.09, totalArea = 0;
  double fixedBorder = 8, shapeBorder = 2, fixedBorderY = 8;
  uint64_t finishedCount = 0;
  StrokedOutline outlines[3] = {strokedOutline(0), strokedOutline(1), strokedOutline(2)};
  const std::vector<double>& statics;
  PathEngine paths{design, &result.bound};
  ColourTable colours{result.colours};

  Engine(const __cf_Design& d, const ExpandOptions& o, const std::vector<double>& s)
      : design(d), options(o), statics(s) {
    rulesOf.resize(size_t(d.shapeCount));
    cumulative.resize(size_t(d.ruleCount));
    for (int i = 0; i < d.ruleCount; ++i) rulesOf[size_t(d.rules[i].shape)].push_back(i);
    // Weights: ordinary ones share what the % ones leave; the last rule takes exactly 1.
    for (auto& rules : rulesOf) {
      double plain = 0, percent = 0;
      for (int r : rules) (d.rules[r].percent ? percent : plain) += d.rules[r].weight;
      double acc = 0;
      for (size_t k = 0; k < rules.size(); ++k) {
        const __cf_Rule& rule = d.rules[rules[k]];
        acc += rule.percent ? rule.weight : rule.weight / plain * (1.0 - percent);
        cumulative[size_t(rules[k])] = k + 1 == rules.size() ? 1.0 : acc;
      }
    }
    if (o.profile) result.ruleRuns.resize(size_t(d.ruleCount));
    double minSize = o.minimumSize <= 0 ? 0.3 : o.minimumSize;
    minArea = minSize * minSize;
    setBorders(nullptr, nullptr);
  }

  // The fixed border (pixels) and the dynamic one (a factor): cfdg's -b, unless the design sets
  // them (CF::BorderFixed, CF::BorderDynamic).
  void setBorders(const double* fixed, const double* dynamic) {
    fixedBorder = fixed ? *fixed : 8.0 * (options.border <= 1.0 ? options.border : 1.0);
    shapeBorder = dynamic ? *dynamic : 1.0 * (options.border <= 1.0 ? 1.0 : options.border);
    if (2 * int(std::fabs(fixedBorder)) >= std::min(options.width, options.height)) fixedBorder = 0;
    if (shapeBorder <= 0) shapeBorder = 1;
    fixedBorderY = fixedBorder;
    result.picture.borderX = result.picture.borderY = fixedBorder;
  }

  // Shape values with bound parameters (ShapeValue), kept in the result: a path drawn again may
  // run a sub-path of one.
  double bind(int shape, const double* params) {
    int n = design.shapes[shape].paramCount;
    if (n == 0) return double(shape);
    result.bound.emplace_back(params, params + n);
    return double(shape) + kBoundStride * double(result.bound.size());
  }
  void replaceValue(__cf_Ctx* c, double value, const __cf_State& s, bool start = false) {
    const ShapeValue v = shapeValue(design, result.bound, value);
    if (v.shape < 0) fail(c, "a shape value that is no shape");
    if (!v.params && design.shapes[v.shape].paramCount > 0)
      fail(c, std::string("shape ") + design.shapes[v.shape].name + " needs parameters");
    process(c, v.shape, s, v.params, start ? c->cur : stepSeed(c->cur));
  }

  bool hasRules(int shape) const { return shape >= 4 && !rulesOf[size_t(shape)].empty(); }

  // libstdc++'s push_heap and pop_heap on the area, ties and all: the order shapes are expanded
  // in decides the picture. The heap holds (area, slot) pairs; the shapes stay in their slots.
  struct Entry {
    double area;
    uint32_t slot;
  };
  std::vector<Entry, support::HugePageAllocator<Entry>> heap;  // a million and more entries
  UnfinishedShapes slots;

  void pushHeap(double area, int shape, uint64_t seed, const __cf_State& s, std::unique_ptr<double[]> params) {
    Entry value{area, slots.add(shape, seed, s, std::move(params))};
    heap.push_back(value);
    siftUp(heap.size() - 1, value);
  }
  // libstdc++'s __push_heap: `value` goes up from `hole` past every parent of smaller area.
  void siftUp(size_t hole, Entry value) {
    while (hole > 0) {
      size_t parent = (hole - 1) / 2;
      if (!(heap[parent].area < value.area)) break;
      heap[hole] = heap[parent];
      hole = parent;
    }
    heap[hole] = value;
  }
  // The largest shape's slot, out of the heap (the caller frees the slot).
  uint32_t popHeap() {
    size_t n = heap.size();
    if (n > 1) {
      Entry value = heap[n - 1];
      heap[n - 1] = heap[0];
      size_t len = n - 1, hole = 0, child = 0;
      while (child < (len - 1) / 2) {
        // The hole goes down to a leaf whatever the areas: the entries three levels below are
        // asked for now, so a large heap's levels arrive together instead of one by one.
        if (8 * child + 14 < len) {
          __builtin_prefetch(&heap[8 * child + 7]);
          __builtin_prefetch(&heap[8 * child + 11]);
          __builtin_prefetch(&heap[8 * child + 14]);
        }
        child = 2 * (child + 1);
        // Without a branch: which child is larger is a coin toss the predictor mostly loses.
        child -= size_t(heap[child].area < heap[child - 1].area);
        heap[hole] = heap[child];
        hole = child;
      }
      if ((len & 1) == 0 && child == (len - 2) / 2) {
        child = 2 * (child + 1);
        heap[hole] = heap[child - 1];
        hole = child - 1;
      }
      siftUp(hole, value);
    }
    uint32_t top = heap.back().slot;
    heap.pop_back();
    return top;
  }

  void process(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed) {
    ModelGuard::checkpoint();
    double area = std::fabs(s.sx * s.sy - s.shy * s.shx);
    for (double v : {s.sx, s.shy, s.shx, s.sy, s.tx, s.ty})
      if (!std::isfinite(v))
        fail(c, std::string("a shape has undefined or infinite state: ") + design.shapes[shape].name);
    if (s.tbegin > s.tend)
      return;
    if (paths.isPath(shape)) {  // drawn now, as a primitive is: no rule is chosen
      finishSymmetric(c, shape, s, params, seed);
      return;
    }
    if (hasRules(shape)) {
      if (!result.bounds.valid() || area * scaleArea >= minArea) {
        int n = design.shapes[shape].paramCount;
        std::unique_ptr<double[]> block;
        if (n > 0) {
          block.reset(new double[size_t(n)]);
          std::copy(params, params + n, block.get());
        }
        pushHeap(area, shape, seed, s, std::move(block));
      }
      return;
    }
    if (shape >= 4) {
      if (design.shapes[shape].usedAt) {
        result.errorAt = design.shapes[shape].usedAt;
        fail(c, std::string("shape '") + design.shapes[shape].name + "' is not declared (it has no rules)");
      }
      fail(c, std::string("shape with no rules encountered: ") + design.shapes[shape].name);
    }
    finishSymmetric(c, shape, s, params, seed);
  }

  void finish(int shape, const __cf_State& s) {
    if (scale == 0.0)
      scale = (options.width + options.height) / std::sqrt(std::fabs(s.sx * s.sy - s.shy * s.shx));
    FinishedShape f;
    f.shape = uint8_t(shape);
    f.transform = affineOf(s);
    std::array<double, 4> rgba;
    rgbOf(s.colour, rgba.data());
    f.colour = colours.of(rgba);
    f.z = s.ztz;
    f.blend = s.blend;
    if (shape != 3) {
      paths.primitiveMeasured(s.sx * s.sy - s.shy * s.shx);
      // The box of the outline stroked 0.1 wide (miter joins, butt caps), as Context Free
      // measures every shape, filled or not: the stroke is made in the shape's own units, so its
      // points are the same for every shape of a kind (outlines[]), transformed as AGG's
      // conv_transform does; the outer contour's box is the whole's (outerContourSuffices).
      const StrokedOutline& outline = outlines[shape];
      const size_t count = outerContourSuffices(s) ? outline.outer : outline.points.size();
      Bounds b;
      bool first = true;
      for (size_t i = 0; i < count; ++i) {
        const auto& [x0, y0] = outline.points[i];
        double x = x0, y = y0;
        double tmp = x;
        x = tmp * s.sx + y * s.shx + s.tx;
        y = tmp * s.shy + y * s.sy + s.ty;
        if (first) {
          b = {x, y, x, y};
          first = false;
          continue;
        }
        if (x < b.minX) b.minX = x;
        if (y < b.minY) b.minY = y;
        if (x > b.maxX) b.maxX = x;
        if (y > b.maxY) b.maxY = y;
      }
      if (!b.valid())
        return;
      f.boxArea = std::fabs((b.maxX - b.minX) * (b.maxY - b.minY));
      if (!settle(b, f.boxArea))
        return;
      if (keepBoxes) result.boxes.push_back(b);
    } else {
      f.boxArea = 1.0;
      if (keepBoxes) result.boxes.emplace_back();
    }
    f.order = ++finishedCount;
    if (!keepInTime(s))
      return;
    result.shapes.push_back(f);
  }

  // A finished shape's time, as Context Free gives it one: its own when the design has time
  // terms, else from the picture's area so far onward (an animation then shows the shapes in the
  // order they were made). It widens the time the shapes span; a design that uses ftime() or
  // frame() keeps the shape only when its time overlaps the frame's window.
  bool keepInTime(const __cf_State& s) {
    TimeSpan t{s.tbegin, s.tend};
    if (!design.usesTime) t = {totalArea, kForever};
    TimeSpan& all = result.timeBounds;
    if (t.begin < all.begin && std::isfinite(t.begin)) all.begin = t.begin;
    if (t.begin > all.end && std::isfinite(t.begin)) all.end = t.begin;
    if (t.end > all.end && std::isfinite(t.end)) all.end = t.end;
    if (t.end < all.begin && std::isfinite(t.end)) all.begin = t.end;
    if (options.keepTimes) result.times.push_back(t);
    return !design.usesFrameTime || t.overlaps(options.window);
  }

  // A path is finished by running its body, measuring each command's outline; it is drawn by
  // running it again, so it keeps its seed, state and parameters.
  void finishPath(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed) {
    if (scale == 0.0)
      scale = (options.width + options.height) / std::sqrt(std::fabs(s.sx * s.sy - s.shy * s.shx));
    double area = 0;
    Bounds b = options.profile ? measureCounted(c, shape, s, params, seed, area)
                               : paths.measure(c, shape, s, params, seed, scale, area);
    if (!b.valid())
      return;  // it paints nothing
    if (!settle(b, area))
      return;
    if (keepBoxes) result.boxes.push_back(b);
    FinishedShape f;
    f.shape = kPathShape;
    f.colour = colours.of({0, 0, 0, 1});  // unused: a path's commands have their own
    f.transform = affineOf(s);
    f.z = s.ztz;
    f.boxArea = area;
    f.path = int(result.paths.size());
    f.order = ++finishedCount;
    if (!keepInTime(s))
      return;
    FinishedPath p;
    p.shape = shape;
    p.seed = seed;
    p.state = s;
    if (int n = design.shapes[shape].paramCount; n > 0) {
      p.params.reset(new double[size_t(n)]);
      std::copy(params, params + n, p.params.get());
    }
    result.paths.push_back(std::move(p));
    result.shapes.push_back(f);
  }

  // -------------------------------------------------------------------------------------------
  // Picture settings: CF::Tile, CF::Size, CF::Symmetry, the borders (Context Free's init and
  // initBounds), then the background.
  // -------------------------------------------------------------------------------------------

  std::vector<Affine> symmetry;  // CF::Symmetry: each finished shape once per transform
  double friezeSize = 0;         // half the frieze's period
  double startX = 0, startY = 0; // CF::Tile's or CF::Size's translation: the start shape's offset
  bool keepBoxes = false;        // tiled and frieze designs keep each shape's box

  [[noreturn]] void failAt(const std::string& at, const std::string& message) {
    result.errorAt = at;
    fail(nullptr, message);
  }

  void configure(__cf_Ctx* c, const __cf_Settings& set) {
    PictureSettings& p = result.picture;
    setBorders(set.hasBorderFixed ? &set.borderFixed : nullptr, set.hasBorderDynamic ? &set.borderDynamic : nullptr);
    if (set.hasColour) p.colour = set.colour != 0.0;
    if (set.hasAlpha) p.alpha = set.alpha != 0.0;
    p.depth16 = set.hasColourDepth && std::floor(set.colourDepth) == 16.0;

    // The lattice: both sides (tiled), or one (a frieze along the other's axis).
    Affine tile = affineOf(set.tile);
    tile.tx = tile.ty = 0.0;
    if (set.hasTile) {
      p.tile = tile;
      p.tiled = tile.sx != 0.0 && tile.sy != 0.0;
      if (!p.tiled && (tile.sx != 0.0 || tile.sy != 0.0)) p.frieze = tile.sx == 0.0 ? 2 : 1;
      startX = set.tile.tx, startY = set.tile.ty;
    }
    try {
      symmetry = symmetryTransforms(set.symmetry, set.symmetryCount, p.tiled, set.hasTile ? tile : Affine());
    } catch (SettingError& e) {
      failAt(e.at, e.message);
    }
    background(c);

    double tileX = 0, tileY = 0;
    if (p.tiled || p.frieze) {
      // The lattice's sides must lie along the axes (a tile's one of them), pointing up and right.
      const double ux = tile.sx, uy = tile.shy, vx = tile.shx, vy = tile.sy;
      const bool off = p.tiled ? std::fabs(uy) >= 0.0001 && std::fabs(vx) >= 0.0001
                               : std::fabs(uy) >= 0.0001 || std::fabs(vx) >= 0.0001;
      const char* what = p.tiled ? "Tile" : "Frieze";
      if (off)
        failAt(set.tileAt, std::string(what) + (p.tiled ? " must be aligned with the X or Y axis." : " must be aligned with the X and Y axis."));
      if (ux < 0.0 || vy < 0.0) failAt(set.tileAt, std::string(what) + " must be in the positive X/Y quadrant.");
      tileX = ux, tileY = vy;
    }
    if (set.hasSize) {
      p.sized = true;
      tileX = set.size.sx, tileY = set.size.sy;
      if (set.size.shx != 0.0 || set.size.shy != 0.0) failAt(set.sizeAt, "Size specification must not be rotated or skewed.");
      startX = set.size.tx, startY = set.size.ty;
    }
    if (p.tiled || p.sized) {
      // A fixed frame, the picture's size fitted to it at once.
      fixedBorder = shapeBorder = 0.0;
      fixedBorderY = 0.0;
      result.bounds.maxX = tileX / 2.0;
      result.bounds.minX = -result.bounds.maxX;
      result.bounds.maxY = tileY / 2.0;
      result.bounds.minY = -result.bounds.maxY;
      Fit f = fitBounds(result.bounds, options.width, options.height, 0.0, 0.0, true);
      p.width = f.width, p.height = f.height;
      scaleArea = f.scale * f.scale;
    }
    if (p.frieze == 1) friezeSize = tileX / 2.0;
    if (p.frieze == 2) friezeSize = tileY / 2.0;
    if (p.frieze == 2) fixedBorderY = 0.0;
    if (p.frieze == 1) fixedBorder = 0.0;
    p.borderX = fixedBorder, p.borderY = fixedBorderY;
    keepBoxes = p.tiled || p.frieze || options.keepTimes;  // and an animation's frames zoomed to theirs
  }

  void background(__cf_Ctx* c) {
    if (!design.background) return;
    __cf_State white;
    __cf_identity(&white);
    white.colour[2] = 1, white.colour[3] = 1;
    white.target[3] = 1;
    design.background(c, &white);
    for (int k = 0; k < 4; ++k) result.background[k] = white.colour[k];
  }

  // A primitive or a path finished once per symmetry transform (applied after its own), FILL once.
  void finishSymmetric(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed) {
    auto one = [&](const __cf_State& state) {
      if (paths.isPath(shape)) finishPath(c, shape, state, params, seed);
      else finish(shape, state);
    };
    if (symmetry.empty() || shape == 3) {
      one(s);
      return;
    }
    for (const Affine& op : symmetry) {
      __cf_State copy = s;
      Affine a = affineOf(s);
      a.multiply(op);
      setAffine(copy, a);
      one(copy);
    }
  }

  // A finished shape's box (world units) and its area: a shape outside CF::Size's frame is
  // dropped (false); unless the frame is fixed the bounds grow by the box, dilated by the
  // dynamic border (a frieze's across its period only), and the scale follows them.
  bool settle(const Bounds& b, double area) {
    const PictureSettings& p = result.picture;
    if (p.sized && (b.minX > result.bounds.maxX || b.maxX < result.bounds.minX || b.minY > result.bounds.maxY ||
                    b.maxY < result.bounds.minY))
      return false;
    totalArea += area;
    if (p.tiled || p.sized)
      return true;
    Bounds before = result.bounds;
    result.bounds.merge(b.dilated(shapeBorder));
    if (p.frieze == 1) result.bounds.minX = -(result.bounds.maxX = friezeSize);
    if (p.frieze == 2) result.bounds.minY = -(result.bounds.maxY = friezeSize);
    // The scale follows the bounds: worked out again only when they grew.
    if (!before.valid() || before.minX != result.bounds.minX || before.minY != result.bounds.minY ||
        before.maxX != result.bounds.maxX || before.maxY != result.bounds.maxY) {
      scale = fitBounds(result.bounds, options.width, options.height, fixedBorder, fixedBorderY, false).scale;
      scaleArea = scale * scale;
    }
    return true;
  }

  // The start shape, moved by CF::Tile's or CF::Size's translation. Its time is where the time
  // the shapes span starts.
  __cf_State startState(const __cf_State& s) {
    result.timeBounds = {s.tbegin, s.tend};
    __cf_State moved = s;
    moved.tx += startX;
    moved.ty += startY;
    return moved;
  }

  // Where the largest tables' memory comes from while `reserve` lives (HugePages.h).
  void feedFrom(support::HugePageReserve* reserve) {
    slots.feedFrom(reserve);
    heap.get_allocator().arena().feedFrom(reserve);
    result.shapes.get_allocator().arena().feedFrom(reserve);
  }

  void run() {
    result.design = &design;
    result.statics = statics;
    __cf_Ctx ctx{};
    ctx.cur = stepSeed(options.variation == 0 ? kSeedBase : options.variation);
    ctx.engine = this;
    ctx.statics = statics.data();
    ctx.time[0] = result.frameTime = options.frameTime;
    ctx.time[1] = result.frame = options.frame;
    design.start(&ctx);
    while (!heap.empty()) {
      ModelGuard::checkpoint();
      if (std::max<uint64_t>(finishedCount, heap.size()) >= options.maxShapes) {
        result.stopped = "the shape limit (" + std::to_string(options.maxShapes) + ") was reached";
        result.shapeLimit = true;
        break;
      }
      uint32_t slot = popHeap();
      UnfinishedShapes::Shape& u = slots[slot];
      // The next shape to expand is likely the heap's top now, and the one after that one of the
      // two below it: their slots are somewhere in a large pool, so ask for them while this body
      // runs (a body is shorter than a trip to memory: the top alone arrives too late).
      if (!heap.empty()) slots.prefetch(heap[0].slot);
      if (heap.size() > 2) {
        slots.prefetch(heap[1].slot);
        slots.prefetch(heap[2].slot);
      }
      __cf_State state;
      slots.state(slot, state);
      double d = drawDouble(u.seed);
      const auto& rules = rulesOf[size_t(u.shape)];
      int chosen = rules.back();
      for (int r : rules)
        if (cumulative[size_t(r)] >= d) {
          chosen = r;
          break;
        }
      ctx.cur = u.seed;
      ctx.frame = &state;
      ++result.expanded;
      if (options.profile) runCounted(chosen, &ctx, u.params.get());
      else design.rules[chosen].body(&ctx, u.params.get());
      slots.release(slot);
    }
    if (!design.usesTime) result.timeBounds = {0.0, totalArea};
  }

  // -------------------------------------------------------------------------------------------
  // Profiling (ExpandOptions::profile): each rule's runs and its body's own time; a path finished
  // inside a body is the path's time (pathNs: what the paths took so far), not the body's.
  // -------------------------------------------------------------------------------------------

  uint64_t pathNs = 0;
  void runCounted(int rule, __cf_Ctx* c, const double* params) {
    const uint64_t paths0 = pathNs;
    const auto start = support::Clock::now();
    design.rules[rule].body(c, params);
    result.ruleRuns[size_t(rule)].add({1, 1, support::nsSince(start) - (pathNs - paths0)});
  }
  Bounds measureCounted(__cf_Ctx* c, int shape, const __cf_State& s, const double* params, uint64_t seed, double& area) {
    const auto start = support::Clock::now();
    Bounds b = paths.measure(c, shape, s, params, seed, scale, area);
    const uint64_t ns = support::nsSince(start);
    result.ruleRuns[size_t(rulesOf[size_t(shape)].front())].add({1, 1, ns});
    pathNs += ns;
    return b;
  }

  void sortForDrawing() {
    // Shapes are made in order: only a design that moves some in z needs sorting.
    bool flat = std::all_of(result.shapes.begin(), result.shapes.end(), [&](const FinishedShape& f) {
      return f.z == result.shapes.front().z;
    });
    if (!flat)
      std::sort(result.shapes.begin(), result.shapes.end(), [](const FinishedShape& a, const FinishedShape& b) {
        return a.z == b.z ? a.order < b.order : a.z < b.z;
      });
  }
};

Engine& engineOf(__cf_Ctx* c) { return *static_cast<Engine*>(c->engine); }


}  // namespace

ShapeValue shapeValue(const __cf_Design& design, const std::deque<std::vector<double>>& bound, double value) {
  const double index = std::floor(value / kBoundStride);
  const int shape = int(value - index * kBoundStride);
  if (!(value >= 0) || shape >= design.shapeCount || index > double(bound.size())) return {};
  return {shape, index > 0 ? bound[size_t(index) - 1].data() : nullptr};
}

Expansion expand(const __cf_Design& design, const ExpandOptions& options, const std::vector<double>& statics) {
  Engine engine(design, options, statics);
  // The fresh memory the run fills, faulted in on another core while this one expands.
  std::optional<support::HugePageReserve> reserve;
  try {
    if (std::thread::hardware_concurrency() > 1) reserve.emplace(16);
  } catch (const std::system_error&) {  // no thread to be had (a sandbox's limit): without one
  }
  engine.feedFrom(reserve ? &*reserve : nullptr);
  // Design code runs behind the fault guard: a crash or an exception in it is an error, not the
  // end of lcjit; the memory limit and Ctrl-C stop the run, keeping what it has made.
  ModelGuard guard;
  guard.setLimits({0, options.maxMemory ? options.maxMemory : defaultMemoryLimit()});
  Fault fault = guard.run([&] {
    try {
      engine.run();
    } catch (Stop& stop) {
      engine.result.error = stop.message;
    }
  });
  if (fault.kind == FaultKind::MemoryLimit || fault.kind == FaultKind::Interrupted || fault.kind == FaultKind::TimeLimit)
    engine.result.stopped = fault.what;
  else if (fault)
    engine.result.error = "the design's code failed: " + fault.what;
  engine.feedFrom(nullptr);
  if (engine.result.error.empty()) engine.sortForDrawing();
  return std::move(engine.result);
}

DesignTiming timingOf(const __cf_Design& design) {
  DesignTiming t;
  if (!design.timing) return t;
  __cf_Timing read{};
  __cf_Ctx ctx{};
  design.timing(&ctx, &read);
  t.hasTime = read.hasTime, t.hasFrameTime = read.hasFrameTime, t.hasFrame = read.hasFrame;
  t.time = {read.timeBegin, read.timeEnd};
  t.timeScale = read.timeScale;
  t.timeAt = read.timeAt ? read.timeAt : "";
  t.frameTime = read.frameTime, t.frame = read.frame;
  return t;
}

}  // namespace lcjit::runtime::cfdg

// ---------------------------------------------------------------------------------------------
// The functions compiled designs call (lcjit/cfdg.h)
// ---------------------------------------------------------------------------------------------
using namespace lcjit::runtime::cfdg;

extern "C" {

uint64_t __cf_step(uint64_t s) { return stepSeed(s); }
double __cf_draw(__cf_Ctx* c) { return drawDouble(c->cur); }

void __cf_replace(__cf_Ctx* c, int shape, const __cf_State* s, const double* params) {
  engineOf(c).process(c, shape, *s, params, stepSeed(c->cur));
}

double __cf_bind(__cf_Ctx* c, int shape, const double* params) { return engineOf(c).bind(shape, params); }
void __cf_replace_value(__cf_Ctx* c, double value, const __cf_State* s) { engineOf(c).replaceValue(c, value, *s); }
void __cf_start_value(__cf_Ctx* c, double value, const __cf_State* s) {
  Engine& e = engineOf(c);
  e.replaceValue(c, value, e.startState(*s), true);
}

void __cf_start(__cf_Ctx* c, int shape, const __cf_State* s, const double* params) {
  Engine& e = engineOf(c);
  e.process(c, shape, e.startState(*s), params, c->cur);
}

void __cf_configure(__cf_Ctx* c, const __cf_Settings* s) { engineOf(c).configure(c, *s); }

int __cf_symmetry(__cf_Ctx* c, const __cf_SymmetryItem* items, int count, __cf_State* out, int capacity) {
  std::vector<Affine> transforms;
  try {
    transforms = symmetryTransforms(items, count, false, Affine());
  } catch (SettingError& e) {
    engineOf(c).failAt(e.at, e.message);
  }
  for (int i = 0; i < capacity && i < int(transforms.size()); ++i) {
    __cf_identity(&out[i]);
    setAffine(out[i], transforms[size_t(i)]);
  }
  return int(transforms.size());
}

void __cf_fail(__cf_Ctx* c, const char* message) { fail(c, message); }
void __cf_fail_at(__cf_Ctx* c, const char* at, const char* message) { engineOf(c).failAt(at, message); }

}  // extern "C"

namespace lcjit::runtime::cfdg {
std::vector<std::pair<std::string, void*>> hostSymbols() {
  std::vector<std::pair<std::string, void*>> symbols = {
      {"__cf_step", reinterpret_cast<void*>(&__cf_step)},
      {"__cf_draw", reinterpret_cast<void*>(&__cf_draw)},
      {"__cf_identity", reinterpret_cast<void*>(&__cf_identity)},
      {"__cf_apply", reinterpret_cast<void*>(&__cf_apply)},
      {"__cf_fold", reinterpret_cast<void*>(&__cf_fold)},
      {"__cf_term", reinterpret_cast<void*>(&__cf_term)},
      {"__cf_merge", reinterpret_cast<void*>(&__cf_merge)},
      {"__cf_replace", reinterpret_cast<void*>(&__cf_replace)},
      {"__cf_start", reinterpret_cast<void*>(&__cf_start)},
      {"__cf_fn1", reinterpret_cast<void*>(&__cf_fn1)},
      {"__cf_fn2", reinterpret_cast<void*>(&__cf_fn2)},
      {"__cf_rand", reinterpret_cast<void*>(&__cf_rand)},
      {"__cf_randpm", reinterpret_cast<void*>(&__cf_randpm)},
      {"__cf_randint", reinterpret_cast<void*>(&__cf_randint)},
      {"__cf_pow", reinterpret_cast<void*>(&__cf_pow)},
      {"__cf_colour", reinterpret_cast<void*>(&__cf_colour)},
      {"__cf_distribution", reinterpret_cast<void*>(&__cf_distribution)},
      {"__cf_time", reinterpret_cast<void*>(&__cf_time)},
      {"__cf_fail", reinterpret_cast<void*>(&__cf_fail)},
      {"__cf_fail_at", reinterpret_cast<void*>(&__cf_fail_at)},
      {"__cf_bind", reinterpret_cast<void*>(&__cf_bind)},
      {"__cf_replace_value", reinterpret_cast<void*>(&__cf_replace_value)},
      {"__cf_start_value", reinterpret_cast<void*>(&__cf_start_value)},
      {"__cf_seen_transform", reinterpret_cast<void*>(&__cf_seen_transform)},
      {"__cf_transform_by", reinterpret_cast<void*>(&__cf_transform_by)},
      {"__cf_configure", reinterpret_cast<void*>(&__cf_configure)},
      {"__cf_symmetry", reinterpret_cast<void*>(&__cf_symmetry)},
  };
  for (auto& s : pathHostSymbols()) symbols.push_back(std::move(s));
  return symbols;
}
}  // namespace lcjit::runtime::cfdg
