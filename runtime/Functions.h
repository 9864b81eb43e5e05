// lpfg's external functions: readers for .func/.fset/.tset/.vset files and the
// func/pfunc/tfunc/val evaluators that L+C productions call.
#pragma once

#include <llvm/ADT/StringMap.h>
#include <llvm/Support/Error.h>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace lcjit::runtime {

// Every entry (curve or .vset parameter) gets the next id, starting at 1, in the
// order loaded: lpfg numbers them in one sequence and its preprocessor defines
// each name as its id, so val(NAME) and func(NAME, x) are id lookups there. To
// reproduce lpfg's ids, load in lpfg's order: the .fset, then the .tset, then
// the .vset, then the .func files in command-line order.
//
// A failed load leaves the store as it was before that call. Evaluation is
// const and lock-free, so it may run from several threads at once.
// A .tset's text with the timeline `name`'s start: and end: values set (only their characters
// change); an error naming `file` if it has no such timeline.
llvm::Expected<std::string> timelineText(std::string_view text, std::string_view name, float start, float end,
                                         const std::string& file);

class FunctionStore {
public:
  llvm::Error loadFunction(const std::string& path);     // .func (one function)
  llvm::Error loadFunctionSet(const std::string& path);  // .fset (several)
  llvm::Error loadTimeline(const std::string& path);     // .tset
  llvm::Error loadParameters(const std::string& path);   // .vset
  // A .func file's text (an editor's curve before it is saved); `path` names it in errors and
  // gives a 1.0 file its name.
  llvm::Error loadFunctionText(std::string_view text, const std::string& path);

  // Unknown id/name, or an id naming a .vset parameter, gives 0. x outside the
  // domain is clamped to its ends, as lpfg does.
  float func(int id, float x) const;
  float func(std::string_view name, float x) const;
  // x in [min,max] is mapped onto [0,1]. Like lpfg's, pfunc also makes
  // [min,max] the function's stored range: later tfunc and funcTangent calls
  // map through it (until the files are loaded again).
  float pfunc(int id, float x, float min, float max) const;
  float pfunc(std::string_view name, float x, float min, float max) const;
  // x in the timeline's [start,end] is mapped onto [0,1]; functions that did
  // not come from a .tset have the range [0,1].
  float tfunc(int id, float x) const;
  float tfunc(std::string_view name, float x) const;

  // lpfg's funcTangent: the curve's tangent (dx/du, dy/du for the spline
  // parameter u in [0, points-3]) at x, tabulated and interpolated like func.
  // x is mapped through the function's range first, as tfunc does. Unknown id
  // or a parameter: (0,0).
  std::array<float, 2> funcTangent(int id, float x) const;

  float val(std::string_view name) const;  // unknown → 0
  float val(int id) const;                 // unknown or not a parameter → 0
  bool isParameter(int id) const;          // a .vset entry
  // Gives a .vset parameter a new value (the REPL's :set); false if `name` is not one. Not while
  // a derivation reads the store.
  bool setParameter(std::string_view name, float value);

  // The .tset timelines (by the timeline's own name) and the range tfunc maps onto each: the
  // window's Parameters panel moves them as the timeline editor does its endpoints. Like
  // setParameter, not while a derivation reads the store.
  struct TimelineRange {
    std::string name;
    float start = 0, end = 1;
  };
  std::vector<TimelineRange> timelines() const;
  bool setTimeline(std::string_view name, float start, float end);

  // Name resolution as lpfg's preprocessor does it: the exact name, else the
  // all-caps form of a name; a later definition of a name wins. 0 if unknown.
  // Lets a compiler resolve names once instead of per call.
  int idOf(std::string_view name) const;
  std::string_view nameOf(int id) const;  // "" if unknown
  int size() const { return static_cast<int>(entries_.size()); }

  void clear();

private:
  struct Entry {
    std::string name;
    std::string alias;            // a .tset timeline's own name, if different
    bool isParameter = false;
    bool isTimeline = false;      // from a .tset
    float value = 0.0f;           // .vset value
    mutable float low = 0.0f, up = 1.0f;  // tfunc domain; pfunc sets it (atomically)
    std::vector<float> samples;   // curve y at x = i/(n-1), n >= 10
    std::vector<std::array<float, 2>> tangents;  // the tangent at the same points
  };
  friend class FunctionFileParser;

  void commit(std::vector<Entry> added);
  const Entry* curve(int id) const;
  static float evalCurve(const Entry& e, float x);
  static float toUnit(const Entry& e, float x);

  std::vector<Entry> entries_;
  llvm::StringMap<int> exact_;
  llvm::StringMap<int> upper_;
};

}  // namespace lcjit::runtime
