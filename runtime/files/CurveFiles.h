// Function files (.func, .fset: vlab's funcedit and gallery) and contour files (.con, .cset:
// cuspy) as the window's editors see them: control points to move, and every other line of the
// file kept as it was read. Writing a file whose points did not move gives back its bytes; a moved
// point's line gets the new x and y in the editors' "%f" and keeps its other words (z,
// multiplicity) as they were, so a file of any version (fver 1 1, the 1.0 "range:" format, cver
// 1 1..1 3, the 1.4 "version:" contour) stays in its version. The model reads these files with
// its own readers (runtime/Functions, runtime/files/Contours); nothing here samples a curve.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::runtime {

struct CurvePoint {
  double x = 0, y = 0;
  // The point's line in the file: as read until movePoint rewrites its x and y ("": a point made
  // by the editor, written like the curve's other points).
  std::string line;
};

struct Curve {
  std::string name;      // `name:` (a 1.0 file: the file's stem)
  bool closed = false;   // contours: `type: closed/cr/ce`, or a 1.0 file's `closed`
  std::vector<std::string> header;  // the lines before the points, as read
  std::vector<CurvePoint> points;
  // The header line that counts the points (`points: n`, a contour's `points: n total`, a 1.0
  // contour's `n dim type`), rewritten once points were added or removed (`recount`). The word of
  // a point's line that is its multiplicity (-1: none).
  int countLine = -1;
  bool recount = false;
  int multiplicityWord = -1;
};

struct CurveFile {
  enum class Kind { Function, Contour } kind = Kind::Function;
  bool set = false;                   // .fset / .cset: a gallery of curves
  std::vector<std::string> preamble;  // a gallery's lines before its first curve
  std::vector<Curve> curves;
  std::vector<std::string> trailer;   // lines after the last curve
  bool finalNewline = true;           // the file's last line ended with '\n'
};

// The text of a file; `fileName` names it in errors ("file:line: error: …") and gives a 1.0
// function or contour its name.
llvm::Expected<CurveFile> parseCurveFile(std::string_view text, CurveFile::Kind kind, const std::string& fileName);
// By extension: .func/.fset functions, .con/.cset contours.
llvm::Expected<CurveFile> readCurveFile(const std::string& path);
std::string curveFileText(const CurveFile& file);
// One curve of a file as a file of its own (a gallery item as a .func or .con would hold it).
std::string curveText(const Curve& curve);
// Writes to a temporary file beside `path` and renames it over, as vlab's editors save: a reader
// (the file monitor, a model re-reading it) never sees half a file.
llvm::Error writeCurveFile(const CurveFile& file, const std::string& path);

// Moves a point: its line gets x and y in "%f", its other words unchanged. Not moving it (the same
// x and y) leaves the line as it was.
void movePoint(Curve& curve, size_t index, double x, double y);
// Adds a point before `index` (funcedit's and cuspy's Add), with multiplicity 1 and the other
// words (a contour's z) of its neighbour; removes one. The count line follows.
void insertPoint(Curve& curve, size_t index, double x, double y);
void removePoint(Curve& curve, size_t index);

}  // namespace lcjit::runtime
