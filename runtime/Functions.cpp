// Parsers for lpfg's function files and the sampled B-spline evaluation behind
// func/pfunc/tfunc/val. Numerics follow lpfg (lpfg/function.h, function.cpp).
#include "runtime/Functions.h"

#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/Path.h>

#include "support/InputFile.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <cstdio>
#include <cstring>
#include <optional>

namespace lcjit::runtime {
// Named (not anonymous) because FunctionFileParser, a friend of FunctionStore
// and so not file-local, holds these types.
namespace functions_detail {

struct Token {
  std::string_view text;
  unsigned col;  // 1-based
};

struct Line {
  std::string_view text;
  unsigned no = 0;  // 1-based; 0 = nothing read yet

  std::vector<Token> tokens() const {
    std::vector<Token> out;
    size_t i = 0;
    while (i < text.size()) {
      while (i < text.size() && llvm::isSpace(text[i])) ++i;
      size_t b = i;
      while (i < text.size() && !llvm::isSpace(text[i])) ++i;
      if (i > b)
        out.push_back({text.substr(b, i - b), static_cast<unsigned>(b + 1)});
    }
    return out;
  }
};

}  // namespace functions_detail
using functions_detail::Line;
using functions_detail::Token;

namespace {

// lpfg clamps a file's "samples:" into this range.
constexpr int kMinSamples = 10;
constexpr int kMaxSamples = 1000;
// Old "range:" files carry no sample count; funcedit assumes 10.
constexpr int kDefaultSamples = 10;
// Bounds that only exist so hostile input cannot exhaust memory.
constexpr long kMaxPoints = 100000;
constexpr int kMaxMultiplicity = 1000;

std::string_view trim(std::string_view s) {
  while (!s.empty() && llvm::isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && llvm::isSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::string toUpper(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = llvm::toUpper(c);
  return r;
}

// Whole-token number parsing: the editors write plain decimals, so anything
// else in a point or count is a damaged file worth reporting. Values lpfg keeps
// as float are read straight into float (lpfg uses stof and sscanf's %f): going
// through double first could round twice.
template <class T = double>
std::optional<T> parseReal(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  T v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v))
    return std::nullopt;
  return v;
}

std::optional<long> parseInt(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

// lpfg's function curve: a cubic B-spline over the clamped uniform knots
// 0,0,0,0,1,2,...,m-3,m-3,m-3,m-3 (m control points), parameter d in [0,1]
// scaled onto [0, m-3]. Everything follows lpfg's arithmetic (function.h), since
// the tables it fills are what func() returns bit for bit: the basis functions
// come from the Cox-de Boor recursion evaluated in float with integer knots,
// and the point is the float sum over all control points. At d = 1 the
// half-open degree-0 basis functions all vanish, so the point is (0,0), as in
// lpfg (the tabulation below never asks for d = 1).
class BSpline {
public:
  BSpline(std::vector<float> xs, std::vector<float> ys)
      : x_(std::move(xs)), y_(std::move(ys)),
        m_(static_cast<int>(x_.size())) {}

  void point(float d, float& X, float& Y) const {
    const float u = d * static_cast<float>(m_ - 3);
    float sx = 0.0f, sy = 0.0f;
    // Only the four basis functions whose support holds u can be non-zero;
    // lpfg adds the others too, but they are signed zeros, which leave a
    // float sum that starts at +0 unchanged.
    const int first = firstSupported(u);
    for (int k = first; k < first + 4 && k < m_; ++k) {
      const float w = basis(k, 4, u);
      sx += x_[k] * w;
      sy += y_[k] * w;
    }
    X = sx;
    Y = sy;
  }

  // dP/du (not d/dd): lpfg's derivative weights (order-1)/(knot span) are
  // doubles, so each control point's weight is summed in double and rounded
  // to float twice, once per term.
  void tangent(float d, float& X, float& Y) const {
    const float u = d * static_cast<float>(m_ - 3);
    float sx = 0.0f, sy = 0.0f;
    const int first = firstSupported(u);
    for (int k = first; k < first + 4 && k < m_; ++k) {
      float w = 0.0f;
      if (const int span = knot(k + 3) - knot(k); span > 0)
        w = static_cast<float>(w + 3.0 / span * basis(k, 3, u));
      if (const int span = knot(k + 4) - knot(k + 1); span > 0)
        w = static_cast<float>(w - 3.0 / span * basis(k + 1, 3, u));
      sx += x_[k] * w;
      sy += y_[k] * w;
    }
    X = sx;
    Y = sy;
  }

private:
  int knot(int j) const {
    if (j < 4) return 0;
    if (j > m_ - 1) return m_ - 3;
    return j - 3;
  }

  // The lowest k whose basis function of order 4 may be non-zero at u.
  int firstSupported(float u) const {
    int s = u > 0.0f ? static_cast<int>(u) : 0;
    return std::clamp(s, 0, std::max(m_ - 4, 0));
  }

  // Order `order` (degree order-1) basis function k at u, in lpfg's float
  // operation order: ((u - knot) / span) * lower-order basis.
  float basis(int k, int order, float u) const {
    if (order == 1)
      return static_cast<float>(knot(k)) <= u && u < static_cast<float>(knot(k + 1))
                 ? 1.0f
                 : 0.0f;
    float sum = 0.0f;
    const int a = knot(k);
    if (const int span = knot(k + order - 1) - a; span != 0)
      sum = (u - static_cast<float>(a)) / static_cast<float>(span) *
            basis(k, order - 1, u);
    const int b = knot(k + order);
    if (const int span = b - knot(k + 1); span != 0)
      sum += (static_cast<float>(b) - u) / static_cast<float>(span) *
             basis(k + 1, order - 1, u);
    return sum;
  }

  std::vector<float> x_, y_;
  int m_;
};

// lpfg tabulates y (and the tangent) at x = i/(n-1). It finds each x by
// bisecting the curve parameter in float and stops as soon as
// |x(t) - target| <= 0.01/n, so the stored values belong to a slightly-off x;
// the same search is repeated here so the table matches lpfg's, not the exact
// curve. The iteration cap replaces lpfg's endless loop when the last control
// point's x is below 1.
void tabulate(const BSpline& s, int n, std::vector<float>& values,
              std::vector<std::array<float, 2>>& tangents) {
  values.assign(n, 0.0f);
  tangents.assign(n, {0.0f, 0.0f});
  const float maxError = 0.01f / static_cast<float>(n);
  for (int i = 0; i < n; ++i) {
    const float target = static_cast<float>(i) / static_cast<float>(n - 1);
    float low = 0.0f, high = 1.0f, check = 0.5f;
    float X = 0, Y = 0;
    for (int iter = 0; iter < 100; ++iter) {
      check = (low + high) / 2.0f;
      s.point(check, X, Y);
      if (X > target)
        high = check;
      else
        low = check;
      if (std::fabs(X - target) <= maxError) break;
    }
    values[i] = Y;  // the point at the last `check`
    s.tangent(check, tangents[i][0], tangents[i][1]);
  }
}

}  // namespace

// Line-oriented reader shared by all four formats. Blank lines are skipped
// everywhere (lpfg does not, but the editors never write meaningful ones).
class FunctionFileParser {
public:
  using Entry = FunctionStore::Entry;

  explicit FunctionFileParser(std::string path) : path_(std::move(path)) {}

  llvm::Error open() {
    if (buf_) return llvm::Error::success();  // given as text
    auto buf = support::readInputFile(path_);
    if (!buf) return llvm::createStringError(path_ + ": error: cannot open file: " + buf.getError().message());
    buf_ = std::move(*buf);
    return llvm::Error::success();
  }

  bool next(Line& out) {
    const std::string_view all = buf_->getBuffer();
    while (pos_ < all.size()) {
      size_t end = all.find('\n', pos_);
      if (end == std::string_view::npos) end = all.size();
      std::string_view text = all.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++lineNo_;
      if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
      if (trim(text).empty()) continue;
      out = {text, lineNo_};
      last_ = out;
      return true;
    }
    return false;
  }

  llvm::Error error(unsigned line, unsigned col, const llvm::Twine& msg) const {
    return llvm::createStringError(
        llvm::Twine(path_ + ":") + llvm::Twine(line) + ":" + llvm::Twine(col) +
        ": error: " + msg);
  }
  llvm::Error error(const Token& t, const Line& l, const llvm::Twine& msg) const {
    return error(l.no, t.col, msg);
  }
  llvm::Error errorAtEnd(const llvm::Twine& what) const {
    if (last_.no == 0) return error(1, 1, "unexpected end of file, expected " + what);
    return error(last_.no, static_cast<unsigned>(last_.text.size() + 1),
                 "unexpected end of file, expected " + what);
  }

  llvm::Error expectLine(Line& l, const llvm::Twine& what) {
    if (!next(l)) return errorAtEnd(what);
    return llvm::Error::success();
  }

  // If the line starts (after indentation) with `key`, yields the trimmed rest
  // and its column.
  static bool keyed(const Line& l, std::string_view key, Token& rest,
                    bool ignoreCase = false) {
    size_t b = 0;
    while (b < l.text.size() && llvm::isSpace(l.text[b])) ++b;
    std::string_view s = l.text.substr(b);
    if (s.size() < key.size()) return false;
    std::string_view head = s.substr(0, key.size());
    if (ignoreCase ? !llvm::StringRef(head).equals_insensitive(key) : head != key)
      return false;
    size_t v = b + key.size();
    while (v < l.text.size() && llvm::isSpace(l.text[v])) ++v;
    rest = {trim(l.text.substr(v)), static_cast<unsigned>(v + 1)};
    return true;
  }

  llvm::Error expectKeyed(std::string_view key, Line& l, Token& rest) {
    if (auto e = expectLine(l, "'" + llvm::Twine(key) + "'")) return e;
    if (!keyed(l, key, rest))
      return error(l.no, firstCol(l), "expected '" + llvm::Twine(key) + "'");
    return llvm::Error::success();
  }

  llvm::Error intValue(const Line& l, const Token& t, std::string_view key,
                       long& out) {
    std::vector<Token> toks = Line{t.text, 0}.tokens();
    std::optional<long> v;
    if (toks.size() == 1) v = parseInt(toks[0].text);
    if (!v)
      return error(l.no, t.col,
                   "expected an integer after '" + llvm::Twine(key) + "'");
    out = *v;
    return llvm::Error::success();
  }

  static unsigned firstCol(const Line& l) {
    auto t = l.tokens();
    return t.empty() ? 1 : t[0].col;
  }

  // One funcedit function; `header` is its already-read first line.
  llvm::Error parseCurve(const Line& header, std::string_view fallbackName,
                         Entry& e) {
    std::vector<Token> h = header.tokens();
    long samples = kDefaultSamples;
    Line l;
    Token rest;
    if (!h.empty() && h[0].text == "fver") {
      std::optional<long> maj, min;
      if (h.size() == 3) {
        maj = parseInt(h[1].text);
        min = parseInt(h[2].text);
      }
      if (!maj || !min)
        return error(header.no, h[0].col, "malformed version line, expected 'fver 1 1'");
      if (*maj != 1 || *min != 1)
        return error(header.no, h[1].col,
                     "unsupported function file version " + llvm::Twine(*maj) +
                         "." + llvm::Twine(*min) + " (only 'fver 1 1' is known)");
      if (auto err = expectKeyed("name:", l, rest)) return err;
      if (rest.text.empty()) return error(l.no, rest.col, "empty function name");
      e.name = std::string(rest.text);
      if (auto err = expectKeyed("samples:", l, rest)) return err;
      if (auto err = intValue(l, rest, "samples:", samples)) return err;
      samples = std::clamp<long>(samples, kMinSamples, kMaxSamples);
      // Display-only settings precede the points; lpfg ignores them.
      for (;;) {
        if (auto err = expectLine(l, "'points:'")) return err;
        if (keyed(l, "points:", rest)) break;
        if (!keyed(l, "flip:", rest) && !keyed(l, "background:", rest) &&
            !keyed(l, "backgroundXY:", rest))
          return error(l.no, firstCol(l), "expected 'points:'");
      }
    } else if (!h.empty() && h[0].text == "range:") {
      // Version 1.0: no name or sample count (lpfg itself rejects these; they
      // are accepted here the way funcedit reads them).
      e.name = std::string(fallbackName);
      if (auto err = expectKeyed("points:", l, rest)) return err;
    } else {
      return error(header.no, firstCol(header), "expected 'fver 1 1'");
    }

    const Line pointsLine = l;
    long count = 0;
    if (auto err = intValue(l, rest, "points:", count)) return err;
    if (count < 4)
      return error(l.no, rest.col,
                   "a function needs at least 4 control points, got " +
                       llvm::Twine(count));
    if (count > kMaxPoints)
      return error(l.no, rest.col, "too many control points");

    std::vector<float> xs, ys;  // lpfg keeps the points as float
    for (long i = 0; i < count; ++i) {
      if (auto err = expectLine(l, "control point " + llvm::Twine(i + 1) +
                                       " of " + llvm::Twine(count)))
        return err;
      std::vector<Token> t = l.tokens();
      if (t.size() < 2 || t.size() > 3)
        return error(l.no, firstCol(l),
                     "expected a control point 'x y' or 'x y multiplicity'");
      std::optional<float> x = parseReal<float>(t[0].text), y = parseReal<float>(t[1].text);
      if (!x) return error(t[0], l, "invalid number '" + llvm::Twine(t[0].text) + "'");
      if (!y) return error(t[1], l, "invalid number '" + llvm::Twine(t[1].text) + "'");
      long mult = 1;
      if (t.size() == 3) {
        // Written as an integer, but lpfg reads it as a float and truncates.
        std::optional<double> m = parseReal(t[2].text);
        if (!m || *m < 0 || *m > kMaxMultiplicity)
          return error(t[2], l, "invalid multiplicity '" + llvm::Twine(t[2].text) + "'");
        mult = static_cast<long>(*m);
      }
      for (long j = 0; j < mult; ++j) {
        xs.push_back(*x);
        ys.push_back(*y);
      }
    }
    if (xs.size() < 4)
      return error(pointsLine.no, firstCol(pointsLine),
                   "a function needs at least 4 control points after "
                   "multiplicities, got " + llvm::Twine(xs.size()));

    tabulate(BSpline(std::move(xs), std::move(ys)), static_cast<int>(samples),
             e.samples, e.tangents);
    return llvm::Error::success();
  }

  llvm::Error parseItemsCount(long& items) {
    Line l;
    Token rest;
    if (auto err = expectKeyed("items:", l, rest)) return err;
    if (auto err = intValue(l, rest, "items:", items)) return err;
    if (items < 0) return error(l.no, rest.col, "negative item count");
    return llvm::Error::success();
  }

  llvm::Error parseGallery(std::vector<Entry>& out) {
    long items = 0;
    if (auto err = parseItemsCount(items)) return err;
    for (long i = 0; i < items; ++i) {
      Line h;
      if (auto err = expectLine(h, "function " + llvm::Twine(i + 1) + " of " +
                                       llvm::Twine(items)))
        return err;
      Entry e;
      if (auto err = parseCurve(h, stem(), e)) return err;
      out.push_back(std::move(e));
    }
    return llvm::Error::success();
  }

  llvm::Error parseTimeline(std::vector<Entry>& out) {
    long items = 0;
    if (auto err = parseItemsCount(items)) return err;
    for (long i = 0; i < items; ++i) {
      Line l;
      Token rest;
      Entry e;
      if (auto err = expectKeyed("start:", l, rest)) return err;
      std::optional<float> start = parseReal<float>(rest.text);
      if (!start) return error(l.no, rest.col, "expected a number after 'start:'");
      if (auto err = expectKeyed("end:", l, rest)) return err;
      std::optional<float> end = parseReal<float>(rest.text);
      if (!end) return error(l.no, rest.col, "expected a number after 'end:'");
      if (auto err = expectKeyed("name:", l, rest)) return err;
      std::string timelineName(rest.text);
      // Colour and labels only matter to the timeline editor. The manual spells
      // the labels in lower case, the editor writes camel case.
      for (;;) {
        if (auto err = expectLine(l, "'timelineFunceditFileStart:'")) return err;
        if (keyed(l, "timelineFunceditFileStart:", rest)) break;
        if (!keyed(l, "color:", rest) && !keyed(l, "startLabel:", rest, true) &&
            !keyed(l, "endLabel:", rest, true))
          return error(l.no, firstCol(l), "expected 'timelineFunceditFileStart:'");
      }
      Line h;
      if (auto err = expectLine(h, "'fver 1 1'")) return err;
      if (auto err = parseCurve(h, timelineName, e)) return err;
      if (auto err = expectKeyed("timelineFunceditFileEnd:", l, rest)) return err;
      e.low = *start;
      e.up = *end;
      e.isTimeline = true;
      // lpfg names the function by its funcedit name; the timeline's own name
      // is what users see in the editor, so it resolves too.
      if (timelineName != e.name) e.alias = std::move(timelineName);
      out.push_back(std::move(e));
    }
    return llvm::Error::success();
  }

  // .vset: "#define NAME VALUE" per line; extra tokens are ignored, as lpfg does.
  llvm::Error parseParameters(std::vector<Entry>& out) {
    Line l;
    while (next(l)) {
      std::vector<Token> t = l.tokens();
      if (t[0].text != "#define")
        return error(t[0], l, "expected '#define NAME VALUE'");
      if (t.size() < 3)
        return error(l.no, static_cast<unsigned>(l.text.size() + 1),
                     "expected '#define NAME VALUE'");
      std::string value(t[2].text);
      char* endp = nullptr;
      float v = std::strtof(value.c_str(), &endp);
      // Models #include their .vset too, so the whole value must be a number: what follows it
      // would be expanded into the model. A C float suffix is fine.
      if (endp != value.c_str() && (*endp == 'f' || *endp == 'F')) ++endp;
      if (endp == value.c_str() || *endp != '\0' || !std::isfinite(v)) {
        std::string shown;
        llvm::raw_string_ostream(shown).write_escaped(t[2].text, /*UseHexEscapes=*/true);
        return error(t[2], l, "invalid number '" + llvm::Twine(shown) + "'");
      }
      Entry e;
      e.name = std::string(t[1].text);
      e.isParameter = true;
      e.value = v;
      out.push_back(std::move(e));
    }
    return llvm::Error::success();
  }

  std::string stem() const { return llvm::sys::path::stem(path_).str(); }

  enum class FileKind { Function, Set, Parameters };
  static llvm::Error parseFile(const std::string& path, FileKind kind,
                               std::vector<Entry>& out, const std::string_view* text = nullptr);

private:
  std::string path_;
  std::unique_ptr<llvm::MemoryBuffer> buf_;
  size_t pos_ = 0;
  unsigned lineNo_ = 0;
  Line last_;
};

// lpfg decides between gallery and timeline by the header line, not by the
// file name, so either set loader accepts either set.
llvm::Error FunctionFileParser::parseFile(const std::string& path, FileKind kind,
                                          std::vector<Entry>& out, const std::string_view* text) {
  FunctionFileParser p(path);
  if (text) p.buf_ = llvm::MemoryBuffer::getMemBufferCopy(llvm::StringRef(text->data(), text->size()), path);
  if (auto err = p.open()) return err;
  if (kind == FileKind::Parameters) return p.parseParameters(out);

  Line h;
  const char* expected = kind == FileKind::Function ? "'fver 1 1'"
                                                    : "'funcgalleryver 1 1' or 'timeEdit 1 2'";
  if (!p.next(h)) return p.errorAtEnd(expected);
  if (kind == FileKind::Function) {
    FunctionStore::Entry e;
    if (auto err = p.parseCurve(h, p.stem(), e)) return err;
    out.push_back(std::move(e));
    return llvm::Error::success();
  }

  std::vector<Token> t = h.tokens();
  if (t.size() == 3 && (t[0].text == "funcgalleryver" || t[0].text == "timeEdit")) {
    const bool gallery = t[0].text == "funcgalleryver";
    std::optional<long> maj = parseInt(t[1].text), min = parseInt(t[2].text);
    if (!maj || !min) return p.error(t[1], h, "malformed version line");
    const long want = gallery ? 1 : 2;
    if (*maj != 1 || *min != want)
      return p.error(t[1], h,
                     "unsupported " + llvm::Twine(gallery ? "function set" : "timeline") +
                         " version " + llvm::Twine(*maj) + "." + llvm::Twine(*min));
    return gallery ? p.parseGallery(out) : p.parseTimeline(out);
  }
  return p.error(h.no, FunctionFileParser::firstCol(h),
                 llvm::Twine("expected ") + expected);
}

namespace {
using FileKind = FunctionFileParser::FileKind;
}  // namespace

llvm::Error FunctionStore::loadFunction(const std::string& path) {
  std::vector<Entry> added;
  if (auto err = FunctionFileParser::parseFile(path, FileKind::Function, added)) return err;
  commit(std::move(added));
  return llvm::Error::success();
}

llvm::Error FunctionStore::loadFunctionText(std::string_view text, const std::string& path) {
  std::vector<Entry> added;
  if (auto err = FunctionFileParser::parseFile(path, FileKind::Function, added, &text)) return err;
  commit(std::move(added));
  return llvm::Error::success();
}

llvm::Error FunctionStore::loadFunctionSet(const std::string& path) {
  std::vector<Entry> added;
  if (auto err = FunctionFileParser::parseFile(path, FileKind::Set, added)) return err;
  commit(std::move(added));
  return llvm::Error::success();
}

llvm::Error FunctionStore::loadTimeline(const std::string& path) {
  return loadFunctionSet(path);
}

llvm::Error FunctionStore::loadParameters(const std::string& path) {
  std::vector<Entry> added;
  if (auto err = FunctionFileParser::parseFile(path, FileKind::Parameters, added)) return err;
  commit(std::move(added));
  return llvm::Error::success();
}

void FunctionStore::commit(std::vector<Entry> added) {
  for (Entry& e : added) {
    const int id = static_cast<int>(entries_.size()) + 1;
    if (!e.alias.empty()) {
      exact_[e.alias] = id;
      upper_[toUpper(e.alias)] = id;
    }
    exact_[e.name] = id;
    upper_[toUpper(e.name)] = id;
    entries_.push_back(std::move(e));
  }
}

void FunctionStore::clear() {
  entries_.clear();
  exact_.clear();
  upper_.clear();
}

std::vector<FunctionStore::TimelineRange> FunctionStore::timelines() const {
  std::vector<TimelineRange> out;
  for (const Entry& e : entries_)
    if (e.isTimeline) out.push_back({e.alias.empty() ? e.name : e.alias, e.low, e.up});
  return out;
}

bool FunctionStore::setTimeline(std::string_view name, float start, float end) {
  for (Entry& e : entries_)
    if (e.isTimeline && (e.alias.empty() ? e.name : e.alias) == name) {
      e.low = start;
      e.up = end;
      return true;
    }
  return false;
}

llvm::Expected<std::string> timelineText(std::string_view text, std::string_view name, float start, float end,
                                         const std::string& file) {
  // A timeline's block: start:, end:, then its own name: (the name: lines of the funcedit
  // description inside it come after timelineFunceditFileStart:).
  std::string out(text);
  std::vector<std::pair<size_t, size_t>> lines;  // [begin, end) of each line in `out`
  for (size_t b = 0; b < out.size();) {
    size_t e = out.find('\n', b);
    if (e == std::string::npos) e = out.size();
    lines.emplace_back(b, e);
    b = e + 1;
  }
  auto value = [&](size_t k, const char* key) -> std::optional<std::pair<size_t, size_t>> {
    std::string_view l(out.data() + lines[k].first, lines[k].second - lines[k].first);
    size_t at = l.find_first_not_of(" \t");
    if (at == std::string_view::npos || l.substr(at, std::strlen(key)) != key) return std::nullopt;
    size_t v = l.find_first_not_of(" \t", at + std::strlen(key));
    if (v == std::string_view::npos) v = l.size();
    size_t ve = l.find_first_of(" \t\r", v);
    if (ve == std::string_view::npos) ve = l.size();
    return std::make_pair(lines[k].first + v, lines[k].first + ve);
  };
  for (size_t k = 0; k + 2 < lines.size(); ++k) {
    auto s = value(k, "start:"), e = value(k + 1, "end:"), n = value(k + 2, "name:");
    if (!s || !e || !n || std::string_view(out.data() + n->first, n->second - n->first) != name) continue;
    char sv[32], ev[32];
    std::snprintf(sv, sizeof sv, "%g", double(start));
    std::snprintf(ev, sizeof ev, "%g", double(end));
    out.replace(e->first, e->second - e->first, ev);  // the later one first: offsets stay right
    out.replace(s->first, s->second - s->first, sv);
    return out;
  }
  return llvm::createStringError(file + ": error: no timeline '" + std::string(name) + "'");
}

int FunctionStore::idOf(std::string_view name) const {
  llvm::StringRef key(name.data(), name.size());
  if (auto it = exact_.find(key); it != exact_.end()) return it->second;
  if (auto it = upper_.find(key); it != upper_.end()) return it->second;
  return 0;
}

std::string_view FunctionStore::nameOf(int id) const {
  if (id < 1 || id > size()) return {};
  return entries_[id - 1].name;
}

const FunctionStore::Entry* FunctionStore::curve(int id) const {
  if (id < 1 || id > size()) return nullptr;
  const Entry& e = entries_[id - 1];
  return e.isParameter ? nullptr : &e;
}

namespace {
// lpfg's argument clamp; NaN goes to 0 (lpfg's behaviour is undefined there).
float clampUnit(float v) {
  if (!(v >= 0.0f)) return 0.0f;
  return v > 1.0f ? 1.0f : v;
}

// Linear interpolation at v in [0,1] in one of lpfg's tables, with lpfg's float arithmetic:
// `mix(w1, i, w2, i + 1)` weighs entries i and i+1; the last entry at the end.
template <class Table, class Mix>
auto interpolate(const Table& table, float v, Mix mix) -> std::decay_t<decltype(table[0])> {
  const size_t n = table.size();
  const float index = v * static_cast<float>(n - 1);
  const size_t i = static_cast<size_t>(index);
  if (i >= n - 1) return table[n - 1];
  const float w1 = 1 - index + static_cast<float>(i);
  const float w2 = index - static_cast<float>(i);
  return mix(w1, table[i], w2, table[i + 1]);
}
}  // namespace

float FunctionStore::evalCurve(const Entry& e, float v) {
  return interpolate(e.samples, clampUnit(v), [](float w1, float a, float w2, float b) { return w1 * a + w2 * b; });
}

// The range that tfunc and funcTangent map through. pfunc overwrites it (lpfg's side effect);
// relaxed atomics keep concurrent evaluations defined, as lpfg's plain floats are not.
float FunctionStore::toUnit(const Entry& e, float x) {
  const float low = std::atomic_ref<float>(e.low).load(std::memory_order_relaxed);
  const float up = std::atomic_ref<float>(e.up).load(std::memory_order_relaxed);
  return (x - low) / (up - low);
}

std::array<float, 2> FunctionStore::funcTangent(int id, float x) const {
  const Entry* e = curve(id);
  if (!e) return {0.0f, 0.0f};
  using T = std::array<float, 2>;
  return interpolate(e->tangents, clampUnit(toUnit(*e, x)), [](float w1, const T& a, float w2, const T& b) {
    return T{w1 * a[0] + w2 * b[0], w1 * a[1] + w2 * b[1]};
  });
}

float FunctionStore::func(int id, float x) const {
  const Entry* e = curve(id);
  return e ? evalCurve(*e, x) : 0.0f;
}

float FunctionStore::func(std::string_view name, float x) const {
  return func(idOf(name), x);
}

float FunctionStore::pfunc(int id, float x, float min, float max) const {
  const Entry* e = curve(id);
  if (!e) return 0.0f;
  std::atomic_ref<float>(e->low).store(min, std::memory_order_relaxed);
  std::atomic_ref<float>(e->up).store(max, std::memory_order_relaxed);
  return evalCurve(*e, (x - min) / (max - min));
}

float FunctionStore::pfunc(std::string_view name, float x, float min,
                           float max) const {
  return pfunc(idOf(name), x, min, max);
}

float FunctionStore::tfunc(int id, float x) const {
  const Entry* e = curve(id);
  return e ? evalCurve(*e, toUnit(*e, x)) : 0.0f;
}

float FunctionStore::tfunc(std::string_view name, float x) const {
  return tfunc(idOf(name), x);
}

float FunctionStore::val(int id) const {
  if (id < 1 || id > size()) return 0.0f;
  const Entry& e = entries_[id - 1];
  return e.isParameter ? e.value : 0.0f;
}

float FunctionStore::val(std::string_view name) const { return val(idOf(name)); }

bool FunctionStore::isParameter(int id) const { return id >= 1 && id <= size() && entries_[id - 1].isParameter; }

bool FunctionStore::setParameter(std::string_view name, float value) {
  int id = idOf(name);
  if (!isParameter(id)) return false;
  entries_[id - 1].value = value;
  return true;
}

}  // namespace lcjit::runtime
