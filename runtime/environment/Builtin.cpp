// The built-in programs and the program side's reading of a record. honda81's rules (its
// specification file, which queries it keeps, the float arithmetic and its order) are the facts
// of vlab's build, measured against it; docs/environment.md lists them.
#include "runtime/environment/Builtin.h"
#include "support/InputFile.h"

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string_view>

namespace lcjit::runtime {

namespace {

// How the program side reads a turtle format: the numbers it holds (`%` conversions, not `%%`,
// at most three) and the characters before the first '%' (skipped on the line).
struct FormatShape {
  int count = 0;
  size_t skip = 0;
};
FormatShape shapeOf(const std::string& format) {
  FormatShape s;
  size_t first = std::string::npos;
  for (size_t i = 0; i < format.size(); ++i) {
    if (format[i] != '%') continue;
    if (i + 1 < format.size() && format[i + 1] == '%') {
      ++i;
      continue;
    }
    if (first == std::string::npos) first = i;
    ++s.count;
  }
  s.count = std::min(s.count, 3);
  s.skip = first == std::string::npos ? 0 : first;
  return s;
}

// honda81: collisions between discs (2D) or spheres (3D) of one radius. A query is answered 0
// when another query of its group with at least its vigor lies within the radius (distance² ≤
// r², in float, ((dx²+dy²)+dz²)), else 1. 2D takes the turtle's x and z. Queries without three
// position numbers or without values get no answer. Nothing is kept between steps.
class Honda81 final : public EnvironmentLink {
 public:
  Honda81(CommSpec spec, float radius2, bool is3d) : spec_(std::move(spec)), radius2_(radius2), is3d_(is3d) {}
  const CommSpec& spec() const override { return spec_; }

  llvm::Expected<std::string> exchange(const std::vector<std::string>& records, int,
                                       const std::function<void()>& poll) override {
    struct Object {
      unsigned long id;
      float p[3];
      float vigor;
      int group;
    };
    std::vector<Object> objects;
    objects.reserve(records.size());
    for (const std::string& r : records) {
      CommunicationQuery q;
      if (!parseQuery(r, spec_, q) || q.position.count < 3 || q.values.empty()) continue;
      Object o;
      o.id = q.id;
      o.p[0] = q.position.v[0];
      o.p[1] = is3d_ ? q.position.v[1] : q.position.v[2];
      o.p[2] = is3d_ ? q.position.v[2] : 0.0f;
      o.vigor = q.values[0];
      // Truncated as cvttss2si does: out of range (or NaN) gives INT_MIN.
      float g = q.values.size() >= 2 ? q.values[1] : 0.0f;
      o.group = g >= -2147483648.0f && g < 2147483648.0f ? int(g) : INT_MIN;
      objects.push_back(o);
    }
    std::string out;
    char line[64];
    for (size_t i = 0; i < objects.size(); ++i) {
      if ((i & 1023) == 0) poll();
      const Object& a = objects[i];
      bool free = true;
      for (size_t j = 0; j < objects.size() && free; ++j) {
        const Object& b = objects[j];
        if (j == i || a.group != b.group || !(a.vigor <= b.vigor)) continue;
        // Each product and sum rounded to float, in this order (vlab's build: scalar SSE, no FMA).
        volatile float dx = a.p[0] - b.p[0], dy = a.p[1] - b.p[1];
        volatile float xx = dx * dx, yy = dy * dy;
        volatile float s = xx + yy;
        if (is3d_) {
          volatile float dz = a.p[2] - b.p[2];
          volatile float zz = dz * dz;
          s = s + zz;
        }
        if (s <= radius2_) free = false;
      }
      std::snprintf(line, sizeof line, "%lu E(%d)\n", a.id, free ? 1 : 0);
      out += line;
    }
    return out;
  }

 private:
  CommSpec spec_;
  float radius2_;
  bool is3d_;
};

// honda81's specification file: `radius: r`, `3d case: on`, `verbose: on`. The keyword is the
// line's first token up to a tab or colon, exactly; the value is the next token, split at blanks,
// `x`, `,`, `;` and `:` (so `0x10` reads 0). r is atof's, as a float; r² is a float product.
// `3d case` and `verbose` can only be switched on.
llvm::Expected<std::unique_ptr<EnvironmentLink>> startHonda81(const CommSpec& spec) {
  std::vector<std::string> argv = environmentArguments(spec);
  size_t a = 1;
  while (a + 1 < argv.size() && argv[a][0] == '-') a += 2;  // -e FILE (and the like), as the library reads them
  if (a >= argv.size())
    return spec.error("honda81 needs a specification file (radius, 3d case) after its options (line " +
                          std::to_string(spec.executableLine) + ")");
  const std::string& specFile = argv[a];
  auto file = support::readInputFile(specFile);
  if (!file)
    return spec.error("honda81 cannot open its specification file '" + specFile + "': " + file.getError().message());
  std::istringstream in((*file)->getBuffer().str());
  float radius = 0;
  bool is3d = false;
  std::string line;
  while (std::getline(in, line)) {
    size_t k = line.find_first_not_of("\t:");
    if (k == std::string::npos) continue;
    size_t end = line.find_first_of("\t:", k);
    std::string key = line.substr(k, end == std::string::npos ? std::string::npos : end - k);
    if (end == std::string::npos) continue;
    const char* delims = "x,; \t:\n";
    size_t v = line.find_first_not_of(delims, end);
    if (v == std::string::npos) continue;
    std::string value = line.substr(v, line.find_first_of(delims, v) - v);
    if (key == "radius") radius = float(std::atof(value.c_str()));
    else if (key == "3d case" && value == "on") is3d = true;
  }
  volatile float r2 = radius * radius;
  return std::unique_ptr<EnvironmentLink>(std::make_unique<Honda81>(spec, r2, is3d));
}

// The programs built in, by the name a .e file calls them.
using BuiltinStart = llvm::Expected<std::unique_ptr<EnvironmentLink>> (*)(const CommSpec&);
BuiltinStart builtin(const std::string& name) { return name == "honda81" ? startHonda81 : nullptr; }

}  // namespace

bool parseQuery(const std::string& record, const CommSpec& spec, CommunicationQuery& out) {
  size_t lineEnd = record.find('\n');
  std::string head = record.substr(0, lineEnd);
  if (std::sscanf(head.c_str(), "%lu", &out.id) != 1) return false;
  size_t e = head.find('E');
  if (e == std::string::npos) return false;
  out.values.clear();
  size_t open = e + 1;
  // The module's symbol is one character; its values follow in parentheses, if at all.
  if (open < head.size() && head[open] == '(') {
    size_t close = head.find(')', open);
    out.values = communicationValues(
        std::string_view(head).substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1), 20);
  }
  size_t pos = lineEnd == std::string::npos ? record.size() : lineEnd + 1;
  auto read = [&](const std::string& format, CommunicationQuery::Vector& v) {
    if (format.empty()) return;
    FormatShape shape = shapeOf(format);
    size_t end = record.find('\n', pos);
    std::string line = record.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? record.size() : end + 1;
    if (shape.count == 0) return;
    const char* p = line.c_str() + std::min(shape.skip, line.size());
    v.count = shape.count;
    std::sscanf(p, "%f %f %f", &v.v[0], &v.v[1], &v.v[2]);
  };
  read(spec.position, out.position);
  read(spec.heading, out.heading);
  read(spec.left, out.left);
  read(spec.up, out.up);
  read(spec.lineWidth, out.lineWidth);
  read(spec.scaleFactor, out.scaleFactor);
  return true;
}

llvm::Expected<std::unique_ptr<EnvironmentLink>> startBuiltinProgram(const std::string& name, const CommSpec& spec) {
  if (BuiltinStart start = builtin(name)) return start(spec);
  return spec.error("lcjit has no built-in environmental program '" + name + "'");
}

llvm::Expected<std::unique_ptr<EnvironmentLink>> startEnvironment(const CommSpec& spec,
                                                                  const ChildProgramOptions& options) {
  std::vector<std::string> argv = environmentArguments(spec);
  if (!argv.empty() && argv[0].find('/') == std::string::npos && findProgram(argv[0]).empty())
    if (BuiltinStart start = builtin(argv[0])) {
      if (options.log) options.log(argv[0] + " is not on PATH: lcjit's built-in " + argv[0] + " answers");
      return start(spec);
    }
  return startChildProgram(spec, options);
}

}  // namespace lcjit::runtime
