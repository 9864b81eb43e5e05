// Function and contour files for the editors (CurveFiles.h). The formats are the vlab tools
// manual's (§7.4 contours, §8.4-8.5 functions, §9.2 galleries); which lines hold the points is
// all this reader needs to know, the model's readers check the rest.
#include "runtime/files/CurveFiles.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "support/ReplacingFile.h"
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {
namespace {

using textfile::fail;
using textfile::trim;
using textfile::words;

// Lines with their '\r' kept: a CRLF file must come back as CRLF.
std::vector<std::string_view> rawLines(std::string_view text, bool& finalNewline) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  finalNewline = text.empty() || text.back() == '\n';
  while (start < text.size()) {
    size_t nl = text.find('\n', start);
    if (nl == std::string_view::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  return lines;
}

std::string_view clean(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return trim(line);
}

// "key: rest" (the words after the key), or nothing.
bool keyed(std::string_view line, std::string_view key, std::vector<std::string_view>* rest = nullptr) {
  line = clean(line);
  if (line.substr(0, key.size()) != key) return false;
  if (rest) *rest = words(line.substr(key.size()));
  return true;
}

bool toLong(std::string_view s, long* out) {
  std::string t(s);
  char* end = nullptr;
  long v = std::strtol(t.c_str(), &end, 10);
  if (t.empty() || *end) return false;
  *out = v;
  return true;
}

bool toDouble(std::string_view s, double* out) {
  std::string t(s);
  char* end = nullptr;
  double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end) return false;
  *out = v;
  return true;
}

std::string stemOf(const std::string& path) {
  std::string stem = std::filesystem::path(path).filename().string();
  return stem.substr(0, stem.find('.'));
}

class Reader {
 public:
  Reader(std::string_view text, const std::string& file) : file_(file) { lines_ = rawLines(text, finalNewline); }

  std::vector<std::string_view> lines_;
  bool finalNewline = true;
  size_t at = 0;
  const std::string& file_;

  bool done() const { return at >= lines_.size(); }
  llvm::Error error(const std::string& what) const { return fail(file_, std::min(at, lines_.size()) + (done() ? 0 : 1), what); }

  // Blank lines before a header belong to it.
  void skipBlanks(std::vector<std::string>& into) {
    while (!done() && clean(lines_[at]).empty()) into.emplace_back(lines_[at++]);
  }

  llvm::Error points(Curve& c, long count) {
    if (count < 0 || count > 1000000) return error("bad number of points");
    for (long i = 0; i < count; ++i, ++at) {
      if (done()) return error("the file ends before point " + std::to_string(i + 1) + " of " + std::to_string(count));
      std::vector<std::string_view> w = words(clean(lines_[at]));
      CurvePoint p;
      if (w.size() < 2 || !toDouble(w[0], &p.x) || !toDouble(w[1], &p.y))
        return error("expected a control point 'x y …'");
      p.line = std::string(lines_[at]);
      c.points.push_back(std::move(p));
    }
    return llvm::Error::success();
  }

  // One funcedit function: `fver 1 1` … `points: n`, or 1.0's `range:` … `points: n`.
  llvm::Error function(Curve& c) {
    skipBlanks(c.header);
    if (done()) return error("expected a function");
    if (!keyed(lines_[at], "fver") && !keyed(lines_[at], "range:")) return error("expected 'fver 1 1' or 'range:'");
    c.name = stemOf(file_);
    c.multiplicityWord = 2;
    for (; !done(); ++at) {
      std::vector<std::string_view> rest;
      c.header.emplace_back(lines_[at]);
      if (keyed(lines_[at], "name:", &rest)) c.name = std::string(clean(clean(lines_[at]).substr(5)));
      if (keyed(lines_[at], "points:", &rest)) {
        long n = 0;
        if (rest.size() != 1 || !toLong(rest[0], &n)) return error("expected 'points: n'");
        c.countLine = int(c.header.size() - 1);
        ++at;
        return points(c, n);
      }
    }
    return error("expected 'points:'");
  }

  // One cuspy contour: `cver 1 x` or `version: 1.4` and keyed lines, then the points (the first
  // number of `points:`); or 1.0's `n dim closed|open` then n points.
  llvm::Error contour(Curve& c) {
    skipBlanks(c.header);
    if (done()) return error("expected a contour");
    c.name = stemOf(file_);
    std::vector<std::string_view> first = words(clean(lines_[at]));
    long n = 0;
    if (first.size() == 3 && toLong(first[0], &n)) {
      c.countLine = int(c.header.size());
      c.header.emplace_back(lines_[at++]);
      c.closed = first[2] == "closed";
      return points(c, n);
    }
    if (!keyed(lines_[at], "cver") && !keyed(lines_[at], "version:")) return error("expected 'cver 1 3'");
    c.header.emplace_back(lines_[at++]);
    c.multiplicityWord = 3;
    bool counted = false;
    while (!done()) {
      std::string_view l = clean(lines_[at]);
      std::vector<std::string_view> w = words(l);
      if (w.empty() || w[0].back() != ':') break;  // the first point
      std::vector<std::string_view> rest(w.begin() + 1, w.end());
      if (w[0] == "name:") c.name = std::string(trim(l.substr(5)));
      if (w[0] == "points:") {
        counted = !rest.empty() && toLong(rest[0], &n);
        c.countLine = int(c.header.size());
      }
      if (w[0] == "type:" && !rest.empty()) c.closed = rest[0] == "closed" || rest[0] == "cr" || rest[0] == "ce";
      c.header.emplace_back(lines_[at++]);
    }
    if (!counted) return error("expected 'points: n'");
    return points(c, n);
  }

  llvm::Error item(CurveFile::Kind kind, Curve& c) { return kind == CurveFile::Kind::Function ? function(c) : contour(c); }
};

}  // namespace

llvm::Expected<CurveFile> parseCurveFile(std::string_view text, CurveFile::Kind kind, const std::string& fileName) {
  Reader r(text, fileName);
  CurveFile f;
  f.kind = kind;
  f.finalNewline = r.finalNewline;
  std::vector<std::string> blanks;
  r.skipBlanks(blanks);
  const char* gallery = kind == CurveFile::Kind::Function ? "funcgalleryver" : "contourgalleryver";
  long items = 1;
  if (!r.done() && keyed(r.lines_[r.at], gallery)) {
    f.set = true;
    f.preamble = std::move(blanks);
    blanks.clear();
    f.preamble.emplace_back(r.lines_[r.at++]);
    r.skipBlanks(f.preamble);
    std::vector<std::string_view> rest;
    if (r.done() || !keyed(r.lines_[r.at], "items:", &rest) || rest.size() != 1 || !toLong(rest[0], &items) || items < 0)
      return r.error("expected 'items: n'");
    f.preamble.emplace_back(r.lines_[r.at++]);
  }
  for (long i = 0; i < items; ++i) {
    Curve c;
    c.header = std::move(blanks);
    blanks.clear();
    if (auto e = r.item(kind, c)) return e;
    f.curves.push_back(std::move(c));
  }
  for (; !r.done(); ++r.at) f.trailer.emplace_back(r.lines_[r.at]);
  return f;
}

llvm::Expected<CurveFile> readCurveFile(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  CurveFile::Kind kind;
  if (ext == ".func" || ext == ".fset") kind = CurveFile::Kind::Function;
  else if (ext == ".con" || ext == ".cset") kind = CurveFile::Kind::Contour;
  else return fail(path, 0, "not a function (.func, .fset) or contour (.con, .cset) file");
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  return parseCurveFile((*buf)->getBuffer(), kind, path);
}

namespace {

// A moved point's line: x and y as the editors print them, the point's other words as they were.
std::string pointLine(const CurvePoint& p, const std::string& model) {
  char xy[96];
  std::snprintf(xy, sizeof xy, "%f %f", p.x, p.y);
  std::string out = xy;
  std::string_view m = model;
  const bool cr = !m.empty() && m.back() == '\r';
  std::vector<std::string_view> w = words(clean(m));
  for (size_t k = 2; k < w.size(); ++k) out += " " + std::string(w[k]);
  if (cr) out += '\r';
  return out;
}

long multiplicity(const Curve& c, const CurvePoint& p) {
  std::vector<std::string_view> w = words(clean(p.line));
  long m = 1;
  if (c.multiplicityWord >= 0 && size_t(c.multiplicityWord) < w.size() && !toLong(w[c.multiplicityWord], &m)) m = 1;
  return m;
}

// The count line after points were added or removed: its numbers replaced (a contour's second
// one is the points counted with their multiplicities), its other words kept.
std::string countLine(const Curve& c, const std::string& line) {
  std::string_view l = line;
  const bool cr = !l.empty() && l.back() == '\r';
  std::vector<std::string_view> w = words(clean(l));
  long total = 0;
  for (const CurvePoint& p : c.points) total += multiplicity(c, p);
  const int counts = c.multiplicityWord == 3 ? 2 : 1;  // a 1.0 contour's second number is its dimension
  std::string out;
  int numbers = 0;
  for (std::string_view word : w) {
    long ignored = 0;
    std::string piece(word);
    if (toLong(word, &ignored) && numbers < counts) piece = std::to_string(numbers++ == 0 ? long(c.points.size()) : total);
    out += (out.empty() ? "" : " ") + piece;
  }
  if (cr) out += '\r';
  return out;
}

void appendCurve(const Curve& c, std::vector<std::string>& lines) {
  const size_t start = lines.size();
  lines.insert(lines.end(), c.header.begin(), c.header.end());
  if (c.recount && c.countLine >= 0 && size_t(c.countLine) < c.header.size())
    lines[start + c.countLine] = countLine(c, c.header[c.countLine]);
  // A moved point follows the shape of its own old line, else of the file's first point.
  std::string model = c.points.empty() ? std::string() : c.points.front().line;
  for (const CurvePoint& p : c.points) {
    if (!p.line.empty()) model = p.line;
    lines.push_back(p.line.empty() ? pointLine(p, model) : p.line);
  }
}

std::string joined(const std::vector<std::string>& lines, bool finalNewline) {
  std::string out;
  for (size_t i = 0; i < lines.size(); ++i) {
    out += lines[i];
    if (i + 1 < lines.size() || finalNewline) out += '\n';
  }
  return out;
}

}  // namespace

std::string curveFileText(const CurveFile& file) {
  std::vector<std::string> lines = file.preamble;
  for (const Curve& c : file.curves) appendCurve(c, lines);
  lines.insert(lines.end(), file.trailer.begin(), file.trailer.end());
  return joined(lines, file.finalNewline);
}

std::string curveText(const Curve& curve) {
  std::vector<std::string> lines;
  appendCurve(curve, lines);
  return joined(lines, true);
}

void movePoint(Curve& curve, size_t index, double x, double y) {
  if (index >= curve.points.size()) return;
  CurvePoint& p = curve.points[index];
  if (p.x == x && p.y == y) return;
  p.x = x;
  p.y = y;
  if (!p.line.empty()) p.line = pointLine(p, p.line);
}

void insertPoint(Curve& curve, size_t index, double x, double y) {
  index = std::min(index, curve.points.size());
  CurvePoint p{x, y, ""};
  if (!curve.points.empty()) {
    // The neighbour's line is the new one's model: its z and the like, multiplicity 1.
    const CurvePoint& model = curve.points[index < curve.points.size() ? index : index - 1];
    std::vector<std::string_view> w = words(clean(model.line));
    std::string line = "0 0";
    for (size_t k = 2; k < w.size(); ++k) line += " " + (int(k) == curve.multiplicityWord ? std::string("1") : std::string(w[k]));
    if (!model.line.empty() && model.line.back() == '\r') line += '\r';
    p.line = pointLine(p, line);
  }
  curve.points.insert(curve.points.begin() + long(index), std::move(p));
  curve.recount = true;
}

void removePoint(Curve& curve, size_t index) {
  if (index >= curve.points.size()) return;
  curve.points.erase(curve.points.begin() + long(index));
  curve.recount = true;
}

llvm::Error writeCurveFile(const CurveFile& file, const std::string& path) {
  return support::writeWholeFile(path, curveFileText(file));
}

}  // namespace lcjit::runtime
