// The animation file (.a, manual §8.1). Keywords, defaults and tolerance follow lpfg's AnimParam
// (animparam.cpp, configfile.cpp): a keyword is matched as a prefix of the line, numbers are read
// the way sscanf("%d") reads them, flags are exactly `on` or `off` followed only by blanks.
#include "runtime/files/AnimationFile.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

#include "support/InputFile.h"
#include "runtime/files/TextLines.h"

namespace lcjit::runtime {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

enum class Cmd {
  FirstFrame, LastFrame, SwapInterval, Step, DoubleBuffer, ClearBF, HCenterBF, ScaleBF, NewViewBF,
  DisplayOnRequest, FrameNumbers, FrameDumpPath
};

struct Command {
  const char* label;
  Cmd cmd;
};
// lpfg's label table (animparam.cpp); no label is a prefix of another.
constexpr Command kCommands[] = {
    {"first frame:", Cmd::FirstFrame},
    {"last frame:", Cmd::LastFrame},
    {"swap interval:", Cmd::SwapInterval},
    {"step:", Cmd::Step},
    {"double buffer:", Cmd::DoubleBuffer},
    {"clear between frames:", Cmd::ClearBF},
    {"hcenter between frames:", Cmd::HCenterBF},
    {"scale between frames:", Cmd::ScaleBF},
    {"new view between frames:", Cmd::NewViewBF},
    {"display on request:", Cmd::DisplayOnRequest},
    {"frame numbers:", Cmd::FrameNumbers},
    {"frame dump path:", Cmd::FrameDumpPath},
};

class Parser {
 public:
  Parser(AnimationSettings& as, std::vector<ViewFileWarning>& warnings, const std::string& file)
      : as_(as), warnings_(warnings), file_(file) {}

  void run(std::string_view text) {
    for (std::string_view raw : textfile::splitLines(text)) {
      ++line_;
      handleLine(raw);
    }
    // lpfg (animparam.cpp, after loading): with clear between frames off, double buffering is
    // switched off too.
    if (!as_.clearBetweenFrames && as_.doubleBuffer) {
      warnings_.push_back({file_, clearOffLine_, 1,
                           "'clear between frames' is off but 'double buffer' is on: double buffering turned off"});
      as_.doubleBuffer = false;
    }
  }

 private:
  AnimationSettings& as_;
  std::vector<ViewFileWarning>& warnings_;
  std::string file_;
  int line_ = 0;
  int clearOffLine_ = 0;
  std::string text_;   // current line, leading blanks removed, trailing blanks removed
  size_t indent_ = 0;  // leading blanks removed (for columns)

  void warn(const char* at, const std::string& message) {
    int column = 1;
    if (at && at >= text_.c_str() && at <= text_.c_str() + text_.size())
      column = int(at - text_.c_str() + indent_) + 1;
    warnings_.push_back({file_, line_, column, message});
  }

  static const char* skipBlanks(const char* p) {
    while (isBlank(*p)) ++p;
    return p;
  }

  // GNU cpp line markers `# N "file" flags…` / `#line N "file"`: the next line is line N.
  // Other directives (#pragma …) are ignored.
  void lineMarker(const char* p) { textfile::lineMarker(p, file_, line_); }

  void handleLine(std::string_view raw) {
    size_t b = 0;
    while (b < raw.size() && isBlank(raw[b])) ++b;
    indent_ = b;
    text_ = std::string(textfile::trim(raw.substr(b)));
    // A NUL inside the line would end lpfg's C string there; do the same.
    if (size_t z = text_.find('\0'); z != std::string::npos) text_.resize(z);
    if (text_.empty()) return;
    const char* s = text_.c_str();
    if (*s == '#') {
      lineMarker(s);
      return;
    }
    for (const auto& c : kCommands) {
      size_t len = std::strlen(c.label);
      if (std::strncmp(s, c.label, len) == 0) {
        dispatch(c.cmd, s + len);
        return;
      }
    }
    std::string shown = text_.size() > 60 ? text_.substr(0, 60) + "..." : text_;
    warn(s, "unrecognized command: " + shown);
  }

  // sscanf("%d"): blanks, an optional sign, digits; the rest of the line is ignored by lpfg
  // (warned about here).
  bool readInt(const char* arg, int& v, const char* what) {
    const char* p = skipBlanks(arg);
    errno = 0;
    char* end = nullptr;
    long x = std::strtol(p, &end, 10);
    if (end == p) {
      warn(p, std::string(what) + " needs an integer");
      return false;
    }
    if (errno == ERANGE || x > INT_MAX || x < INT_MIN) x = x < 0 ? INT_MIN : INT_MAX;
    v = int(x);
    const char* rest = skipBlanks(end);
    if (*rest) warn(rest, std::string("text after the ") + what + " value ignored: '" + rest + "'");
    return true;
  }

  void onOff(const char* arg, bool& flag, const char* what) {
    const char* p = skipBlanks(arg);
    std::string v = p;
    if (v == "on" || v == "off") {
      flag = v == "on";
      return;
    }
    warn(p, std::string(what) + " must be 'on' or 'off', not '" + v + "'");
  }

  void dispatch(Cmd cmd, const char* arg) {
    const char* at = skipBlanks(arg);
    int n = 0;
    switch (cmd) {
      case Cmd::FirstFrame:
        if (!readInt(arg, n, "first frame")) break;
        if (n < 0) warn(at, "invalid first frame " + std::to_string(n) + ": must not be negative");
        else as_.firstFrame = n;
        break;
      case Cmd::LastFrame:
        if (!readInt(arg, n, "last frame")) break;
        // lpfg ignores a negative value silently (-1 is its "unset").
        if (n < 0) warn(at, "invalid last frame " + std::to_string(n) + ": must not be negative (ignored)");
        else as_.lastFrame = n;
        break;
      case Cmd::SwapInterval:
        if (!readInt(arg, n, "swap interval")) break;
        if (n < 0) warn(at, "invalid swap interval " + std::to_string(n) + ": must not be negative");
        else as_.swapInterval = std::min(n, INT_MAX / 10);
        break;
      case Cmd::Step:
        // lpfg means to reject step < 1 (its check tests the old value, so it never fires);
        // here a step below 1 is rejected and the step stays as it was.
        if (!readInt(arg, n, "step")) break;
        if (n < 1) warn(at, "invalid step " + std::to_string(n) + ": must be at least 1");
        else as_.step = n;
        break;
      case Cmd::DoubleBuffer: onOff(arg, as_.doubleBuffer, "double buffer"); break;
      case Cmd::ClearBF:
        onOff(arg, as_.clearBetweenFrames, "clear between frames");
        if (!as_.clearBetweenFrames) clearOffLine_ = line_;
        break;
      case Cmd::HCenterBF: onOff(arg, as_.hcenterBetweenFrames, "hcenter between frames"); break;
      case Cmd::ScaleBF: onOff(arg, as_.scaleBetweenFrames, "scale between frames"); break;
      case Cmd::NewViewBF: onOff(arg, as_.newViewBetweenFrames, "new view between frames"); break;
      case Cmd::DisplayOnRequest: onOff(arg, as_.displayOnRequest, "display on request"); break;
      case Cmd::FrameNumbers:
        // lpfg compares only the prefix: "consecutive…" / "stepno…".
        if (std::strncmp(at, "consecutive", 11) == 0)
          as_.frameNumbers = AnimationSettings::FrameNumbers::Consecutive;
        else if (std::strncmp(at, "stepno", 6) == 0)
          as_.frameNumbers = AnimationSettings::FrameNumbers::StepNo;
        else
          warn(at, std::string("frame numbers must be 'consecutive' or 'stepno', not '") + at + "'");
        break;
      case Cmd::FrameDumpPath:
        if (!*at) warn(at, "frame dump path: needs a path");
        else as_.frameDumpPath = at;
        break;
    }
  }
};

}  // namespace

AnimationSettings parseAnimationFile(std::string_view preprocessedText, const std::string& fileName,
                                     std::vector<ViewFileWarning>& warnings) {
  AnimationSettings as;
  Parser(as, warnings, fileName).run(preprocessedText);
  return as;
}

AnimationSettings loadAnimationFile(const std::string& path, std::vector<std::string>& warnings) {
  auto text = support::readInputFile(path);
  if (!text) {
    warnings.push_back(path + ": warning: cannot open file: " + text.getError().message() +
                       "; lpfg's animation defaults are used");
    return AnimationSettings();
  }
  std::vector<ViewFileWarning> found;
  AnimationSettings as = parseAnimationFile((*text)->getBuffer(), path, found);
  for (const ViewFileWarning& w : found)
    warnings.push_back(w.file + ":" + std::to_string(w.line) + ":" + std::to_string(w.column) + ": warning: " + w.message);
  return as;
}

// ---- AnimationSchedule ----------------------------------------------------------------------------

AnimationSchedule::AnimationSchedule(const AnimationSettings& s, int derivationLength)
    : first_(std::max(0, s.firstFrame)),
      last_(s.resolvedLastFrame(derivationLength)),
      step_(std::max(1, s.step)),
      onRequest_(s.displayOnRequest),
      current_(first_) {}

int AnimationSchedule::rewind() { return current_ = first_; }

bool AnimationSchedule::stopsAfter(int stepNo, bool displayRequested) const {
  if (stepNo >= last_) return true;  // the last frame is always shown
  if (onRequest_) return displayRequested;
  // stepNo > first_ here in practice (derivation goes forward from the first frame); a step
  // before the first frame never stops (Rewind derives through them without drawing).
  if (stepNo < first_) return false;
  return (stepNo - first_) % step_ == 0;
}

std::optional<int> AnimationSchedule::next(Mode mode) {
  if (atEnd()) {
    if (mode != Mode::Forever) return std::nullopt;
    return rewind();
  }
  // The next step on the grid first + k·step after the current one, or the last frame.
  long long s;
  if (onRequest_ || current_ < first_) {
    s = onRequest_ ? last_ : first_;
  } else {
    long long k = (static_cast<long long>(current_) - first_) / step_ + 1;
    s = first_ + k * step_;
  }
  return current_ = static_cast<int>(std::min<long long>(s, last_));
}

std::vector<int> AnimationSchedule::frames() const {
  AnimationSchedule copy = *this;
  std::vector<int> out{copy.rewind()};
  while (auto f = copy.next(Mode::Run)) out.push_back(*f);
  return out;
}

}  // namespace lcjit::runtime
