// Contours (cuspy's .con files and gallery .cset sets, vlab tools manual §7.4-7.5, §9.2): the
// cross-sections of generalized cylinders (lpfg manual §5.7) and the curves of the curve functions
// (§6.3). Behaviour follows lpfg's own reader:
//
// Numbering (one sequence for CurrentContour/BlendedContour and curveX… alike): id 0 is lpfg's
// default contour, a unit circle named "def_contour"; then the items of the .cset (ids 1..n); then
// the .con files in command-line order. lpfg reads at most one .cset (the last named) and always
// before the .con files, whatever the command-line order. Each contour's name is defined as its id
// for the model's preprocessor (`-Dname=id`, including def_contour=0), as lpfg does.
//
// Sampling: a B-spline contour (uniform cubic B-spline; a closed one wraps around, an open one
// reaches its ends only through multiplicity-3 end points) is evaluated densely (1000 points per
// segment, with lpfg's float matrix products, so the samples are lpfg's bits), then resampled at
// `divisions()` points equally spaced in arc length. The first sample
// is the curve's start; a closed contour's last sample repeats its first (so n samples draw n-1
// sides). Normals are the tangent turned +90° about z: (-ty, tx, 0), i.e. outward for a clockwise
// contour (the default circle, x = sin, y = cos, runs clockwise and its normals are its points).
// Normals are linearly interpolated, not renormalised, as in lpfg.
//
// How many samples a generalized cylinder uses (lpfg's _UpdateContourDivisions, see
// drawDivisions()): the ContourSides(n) module's n if one was given; else the file's `samples:`;
// else the view file's `contour sides:` (default 16) plus one. lpfg applies that count to the
// contour itself (setDivisions) whenever CurrentContour/BlendedContour/ContourSides selects it,
// and the curve functions then see the same samples. A contour never drawn keeps its `samples:`
// (8 if the file has none; the default circle also has 8).
//
// Drawing (lpfg's CylinderLineScreenTurtle): sample (x, y, z) is placed at
// position + left·(x·P/2) + up·(y·Q/2) + heading·z, P and Q being the line width times the
// ScaleContour factors; normals are rotated the same way without scaling.
//
// Curve functions: t in [0,1] is the arc-length parameter, clamped; the value is the linear
// interpolation of the current samples at t·(divisions-1). curveGAL is the length of the dense
// curve (0 for the default circle).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

// A contour sampled for drawing: points.size() == normals.size(); a closed contour's last point
// repeats its first.
struct ContourSamples {
  std::vector<V3f> points;
  std::vector<V3f> normals;
  bool closed = true;
};

// lpfg's BlendedContour: a·(1-t) + b·t pointwise (points and normals). t == 0 gives a, t == 1
// gives b exactly. lpfg requires equal sample counts; if they differ, b is linearly resampled at
// a's parameters.
ContourSamples blendContours(const ContourSamples& a, const ContourSamples& b, float t);

class Contour {
 public:
  static constexpr int kMinDivisions = 3, kMaxDivisions = 10000, kDefaultDivisions = 8;

  // lpfg's default contour ("def_contour", id 0): `divisions` points on the unit circle,
  // point i = (sin 2πi/(n-1), cos 2πi/(n-1), 0), the last equal to the first; normal = point.
  static Contour defaultCircle();

  // Reads one contour from `text` starting at line index `*line` (0-based; advanced past the
  // contour). Versions: "cver 1 1|2|3" and the original header-less 1.0 format ("n dim type").
  // `fileName` names the file in errors ("file:line: error: …") and gives a 1.0 contour its name.
  static llvm::Expected<Contour> parse(const std::vector<std::string_view>& lines, size_t* line,
                                       const std::string& fileName);
  static llvm::Expected<Contour> parse(std::string_view text, const std::string& fileName);
  static llvm::Expected<Contour> load(const std::string& path);

  const std::string& name() const { return name_; }  // the `name:` word (at most 30 chars)
  bool closed() const { return closed_; }
  bool isDefaultCircle() const { return cpts_.empty(); }
  bool endPointInterpolating() const { return endPoint_; }  // cver 1.2/1.3 types oe/ce
  std::optional<int> fileSamples() const { return fileSamples_; }  // `samples:`, clamped 3..10000

  // The sample count a generalized cylinder uses (see the top of this file). turtleSides: the
  // last valid ContourSides argument (lpfg ignores values < 3 and caps at 10000), or 0 if none.
  int drawDivisions(int turtleSides, int viewContourSides = 16) const;

  // Current samples (what lpfg's contour holds; curve functions read these).
  int divisions() const { return divisions_; }
  void setDivisions(int n);  // clamped to 3..10000; resamples if it changed (lpfg SetDivisions)
  const std::vector<V3f>& points() const { return vertex_; }
  const std::vector<V3f>& normals() const { return normal_; }
  ContourSamples samples() const { return {vertex_, normal_, closed_}; }
  ContourSamples sampled(int n) const;  // samples at n points, leaving this contour unchanged

  // The extent of the samples the contour had when it was read (lpfg's contour bounding box,
  // which its view volume uses for generalized cylinders): x and y only, ±1 for the default
  // circle. Later changes (setDivisions, curveScale …) do not update it, as in lpfg.
  V3f extentMin() const { return extentMin_; }
  V3f extentMax() const { return extentMax_; }

  // Curve functions (§6.3). t is clamped to [0,1].
  V3f pointAt(float t) const;   // curveX/Y/Z/XY/XYZ
  V3f normalAt(float t) const;  // curveNormal; (0,0,0) for an end-point contour, as in lpfg
  float arcLength() const { return arcLen_; }  // curveGAL

  // Control points as lpfg indexes them for curveSetPoint: multiplicities expanded, and for a
  // closed (regular) contour the last three points repeated in front, so the file's k-th point
  // (counting multiplicity) is index k+3. Setting a point does not update those copies.
  const std::vector<V3f>& controlPoints() const { return cpts_; }
  bool setControlPoint(int index, V3f p);  // false if index is out of range; no recalculation
  void scale(V3f s);   // curveScale: scales the control points and recalculates
  void recalculate();  // curveRecalculate
  void reset();        // curveReset: restores the file's control points; like lpfg, does not
                       // recalculate (call recalculate() for the curve to follow)

 private:
  void compute();
  void computeRegular();
  void computeEndPoint();
  void computeDefault();

  std::string name_;
  bool closed_ = true;
  bool endPoint_ = false;
  std::optional<int> fileSamples_;
  int divisions_ = kDefaultDivisions;
  std::vector<V3f> cpts_, origCpts_;
  std::vector<V3f> vertex_, normal_;
  float arcLen_ = 0;
  V3f extentMin_{-1, -1, 0}, extentMax_{1, 1, 0};
};

class ContourStore {
 public:
  ContourStore();  // only id 0, the default circle

  // Command-line files in their order: the last .cset first, then each .con in order (lpfg's
  // order; other extensions are ignored). Continues past failures and returns them all joined:
  // a .con that fails still takes its id (as the default circle, as lpfg does); a failing .cset
  // keeps the items read before the bad one.
  llvm::Error loadFiles(const std::vector<std::string>& paths);
  // Lower level: loadSet replaces everything but id 0 with the set's items; loadContour appends.
  llvm::Error loadSet(const std::string& path);
  llvm::Error loadSetText(std::string_view text, const std::string& fileName);
  llvm::Error loadContour(const std::string& path);
  void add(Contour c) { contours_.push_back(std::move(c)); }
  void clear();

  int size() const { return static_cast<int>(contours_.size()); }
  bool valid(int id) const { return id >= 0 && id < size(); }
  Contour* get(int id) { return valid(id) ? &contours_[id] : nullptr; }
  const Contour* get(int id) const { return valid(id) ? &contours_[id] : nullptr; }
  const std::string& nameOf(int id) const;  // "" if invalid

 private:
  std::vector<Contour> contours_;
};

}  // namespace lcjit::runtime
