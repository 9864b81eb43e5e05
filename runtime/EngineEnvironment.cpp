// The environmental pass at the start of a step (manual §5.10; lpfg's InterpretForEnvironment):
// one interpretation of the string that fills the query modules (GetPos & co.) and writes each
// communication module (E1, E2, EA20) the turtle meets, with its turtle lines, for the
// environmental program; its answers then overwrite the modules' parameters.
//
// Sections, in order (each begins with a `// ----` rule): The pass (environmentPass) · Requests
// (communicate) · Answers (applyAnswers).
#include <algorithm>
#include <cstdio>
#include <cstring>

#include "runtime/EngineInternal.h"

namespace lcjit::runtime {

// ---------------------------------------------------------------------------------------------
// The pass

// lpfg's InterpretForEnvironment: one interpretation of the string (view group 0), which fills
// GetPos & co. and sends E1/E2/EA20; NoEnvironment() skips both.
void Engine::environmentPass() {
  if (ignoreEnvironment_ || (!hasQueries_ && !environment_)) return;
  Turtle& turtle = acquireTurtle();
  turtle.reset(turtleSetup_, nullptr, &queryTropisms_);
  communication_.records.clear();
  communication_.sent.clear();
  communicating_ = environment_ != nullptr;
  expand(__lc_Interpretation, string_.data(), string_.size(), interpretationDepth_,
         ruleTableKey(__lc_Interpretation, group_, 0), nullptr, &turtle, nullptr);
  communicating_ = false;
  --turtlesInUse_;
  // As in lpfg, a pass that met no communication module does not wake the program.
  if (!environment_ || communication_.records.empty()) return;
  auto answers = environment_->exchange(communication_.records, step_ + 1, [] { ModelGuard::checkpoint(); });
  if (!answers) throw Fault{FaultKind::Environment, llvm::toString(answers.takeError())};
  applyAnswers(*answers);
}

// ---------------------------------------------------------------------------------------------
// Requests

namespace {
bool isCommunication(__lc_ModuleId id) { return id == __lc_id_E1 || id == __lc_id_E2 || id == __lc_id_EA20; }
// How many floats a communication module carries.
size_t valueCount(__lc_ModuleId id) { return id == __lc_id_E1 ? 1 : id == __lc_id_E2 ? 2 : 20; }
// Where a communication module's floats start in its record (E2's two and EA20's twenty follow).
size_t parameterOffset(__lc_ModuleId id) {
  return id == __lc_id_E1 ? offsetof(__lc_R_E1, p0) : id == __lc_id_E2 ? offsetof(__lc_R_E2, p0) : offsetof(__lc_R_EA20, p0);
}

void appendTurtleLine(std::string& out, const std::string& format, double x, double y, double z) {
  if (format.empty()) return;
  char buf[512];
  // The format was checked when the .e file was read: at most three floating-point conversions.
  int n = std::snprintf(buf, sizeof buf, format.c_str(), x, y, z);
  if (n > 0) out.append(buf, std::min<size_t>(size_t(n), sizeof buf - 1));
  out += '\n';
}
}  // namespace

// One communication module met by the environmental pass: `ID E(v,…)` with lpfg's %f values,
// the module after it in the same string when `following module:` asks, then the turtle lines.
// The id is the module's byte offset in the string; a module an interpretation rule produced
// is not in the string, so it gets an id past the string's end and its answer goes nowhere.
void Engine::communicate(const char* src, size_t pos, size_t n, const Turtle& turtle) {
  const __lc_ModuleId id = ModuleTable::idAt(src + pos);
  if (!isCommunication(id)) return;
  const CommSpec& spec = environment_->spec();
  const bool inString = src == string_.data();
  const size_t sentId = inString ? pos : string_.size() + communication_.records.size();
  if (inString) communication_.sent[pos] = id;
  std::string& out = communication_.records.emplace_back();
  char buf[64];
  std::snprintf(buf, sizeof buf, "%zu E(", sentId);
  out += buf;
  const char* p = src + pos + parameterOffset(id);
  for (size_t i = 0; i < valueCount(id); ++i) {
    float v;
    std::memcpy(&v, p + i * sizeof(float), sizeof v);
    std::snprintf(buf, sizeof buf, i ? ",%f" : "%f", double(v));
    out += buf;
  }
  out += ')';
  size_t next = modules_.next(src, pos);
  if (spec.followingModule && next < n) modules_.format(src + next, out);
  out += '\n';
  const TurtleState& t = turtle.state();
  appendTurtleLine(out, spec.position, t.position.x, t.position.y, t.position.z);
  appendTurtleLine(out, spec.heading, t.heading.x, t.heading.y, t.heading.z);
  appendTurtleLine(out, spec.left, t.left.x, t.left.y, t.left.z);
  appendTurtleLine(out, spec.up, t.up.x, t.up.y, t.up.z);
  appendTurtleLine(out, spec.lineWidth, t.width, t.width, t.width);
  appendTurtleLine(out, spec.scaleFactor, t.csScale, t.csScale, t.csScale);
}

// ---------------------------------------------------------------------------------------------
// Answers

// The answers, as lpfg takes them: `ID E(v,…)` for a module sent this step; E1 takes exactly one
// value, E2 two, EA20 one to twenty (the rest kept, or zeroed with -cleanEA20). Anything else is
// a warning and changes nothing; modules without an answer keep their values.
void Engine::applyAnswers(const std::string& answers) {
  const std::string& file = environment_->spec().file;
  size_t start = 0;
  while (start < answers.size()) {
    size_t end = answers.find('\n', start);
    if (end == std::string::npos) end = answers.size();
    std::string line = answers.substr(start, end - start);
    start = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const char* c = line.c_str();
    char* after = nullptr;
    unsigned long long at = std::strtoull(c, &after, 10);
    size_t open = line.find('(');
    if (after == c || open == std::string::npos) {
      warn(file + ": warning: the environmental program's answer '" + line.substr(0, 80) +
           "' is not 'ID E(values)': ignored");
      continue;
    }
    size_t close = line.find(')', open);
    const std::vector<float> values = communicationValues(
        std::string_view(line).substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1));
    auto sent = communication_.sent.find(size_t(at));
    const bool known = sent != communication_.sent.end();
    const __lc_ModuleId module = known ? sent->second : __lc_id_E1;
    const char* name = known ? modules_.info(module).name : nullptr;
    const size_t want = valueCount(module);
    const bool fits = module == __lc_id_EA20 ? values.size() <= want : values.size() == want;
    if (!known || !fits) {
      warn(file + ": warning: invalid answer from the environmental program for position " + std::to_string(at) +
           (name ? std::string(" (") + name + ", " + std::to_string(values.size()) + " values)" : std::string(" (no such module was sent)")) +
           ": ignored");
      continue;
    }
    char* p = string_.data() + at + parameterOffset(module);
    for (size_t i = 0; i < want; ++i) {
      if (i >= values.size() && !cleanEA20_) break;
      float v = i < values.size() ? values[i] : 0.0f;
      std::memcpy(p + i * sizeof(float), &v, sizeof v);
    }
  }
}

}  // namespace lcjit::runtime
