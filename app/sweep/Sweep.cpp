#include "app/sweep/Sweep.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include <llvm/ADT/StringExtras.h>
#include <llvm/Support/BLAKE3.h>
#include <llvm/Support/Program.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "app/session/Languages.h"
#include "support/InputFile.h"
#include "support/ReplacingFile.h"

extern char** environ;

namespace lcjit::app {
namespace {

namespace fs = std::filesystem;
// Ordered: the records' keys keep their order, which the table's columns follow.
using Json = nlohmann::ordered_json;

llvm::Error failure(const std::string& message) {
  return llvm::createStringError(llvm::inconvertibleErrorCode(), message);
}

// A run's id names its folder too; six digits sort as numbers do.
constexpr size_t kMostRuns = 999999;

std::string runId(size_t index) {
  char id[16];
  std::snprintf(id, sizeof id, "%06zu", index + 1);
  return id;
}

// Values a sweep computes (ranges, draws) are written with 12 significant digits: 0.1 steps give
// 0.3, not 0.30000000000000004, and the text is what the model gets and the table shows.
std::string numberText(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.12g", v);
  return text;
}

std::string blake3Hex(const std::string& text) {
  auto hash = llvm::BLAKE3::hash<32>(llvm::ArrayRef<uint8_t>((const uint8_t*)text.data(), text.size()));
  return llvm::toHex(hash, true);
}

llvm::Expected<std::string> readText(const fs::path& file) {
  auto in = support::readInputFile(file.string(), /*nullTerminated=*/false);
  if (!in) return failure(file.string() + ": error: cannot read it: " + in.getError().message());
  return (*in)->getBuffer().str();
}

// --- The sweep file -----------------------------------------------------------------------------

// Reads a YAML text's events for what yaml-cpp's nodes lose: a key given twice in one map (YAML
// says a map's keys are unique; yaml-cpp keeps both, node["key"] finds the first, and iterating
// gives both), and a key that is a list or a map. Events, not nodes: an alias is one event, not a
// copy of what it names to walk again.
class KeyChecker : public YAML::EventHandler {
 public:
  // The first problem: where, and what.
  std::optional<std::pair<YAML::Mark, std::string>> found;
  YAML::Mark document;  // where the last document read starts

  void OnDocumentStart(const YAML::Mark& mark) override { document = mark; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { scalar(mark, anchor, "~"); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string& value) override {
    scalar(mark, anchor, value);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    auto named = anchored_.find(anchor);
    begin(mark, named == anchored_.end() ? std::optional<std::string>("*") : named->second);
    end();
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    collection(mark, anchor, false);
  }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    collection(mark, anchor, true);
  }
  void OnSequenceEnd() override {
    levels_.pop_back();
    end();
  }
  void OnMapEnd() override {
    levels_.pop_back();
    end();
  }

 private:
  struct Level {
    bool map;
    bool atKey = true;  // in a map: the next node is a key (else its value)
    std::set<std::string> keys;
  };
  std::vector<Level> levels_;
  std::map<YAML::anchor_t, std::optional<std::string>> anchored_;  // a scalar's text; none: a collection

  void scalar(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& text) {
    if (anchor != YAML::NullAnchor) anchored_[anchor] = text;
    begin(mark, text);
    end();
  }
  void collection(const YAML::Mark& mark, YAML::anchor_t anchor, bool map) {
    if (anchor != YAML::NullAnchor) anchored_[anchor] = std::nullopt;
    begin(mark, std::nullopt);
    levels_.push_back({map});
  }
  // A node starts: `text` is a scalar's, none for a list or a map.
  void begin(const YAML::Mark& mark, const std::optional<std::string>& text) {
    if (found || levels_.empty() || !levels_.back().map || !levels_.back().atKey) return;
    if (!text) found = {mark, "a key must be a single value (a name), not a list or a map"};
    else if (!levels_.back().keys.insert(*text).second) found = {mark, *text + " is given twice"};
  }
  // A node ended: in a map, keys and values take turns.
  void end() {
    if (!levels_.empty() && levels_.back().map) levels_.back().atKey = !levels_.back().atKey;
  }
};

class SweepReader {
 public:
  explicit SweepReader(std::string file) : file_(std::move(file)) {}

  llvm::Error error(const YAML::Node& at, const std::string& what) const { return error(at.Mark(), what); }
  llvm::Error error(const YAML::Mark& at, const std::string& what) const {
    if (at.is_null()) return failure(file_ + ": error: " + what);
    return failure(file_ + ":" + std::to_string(at.line + 1) + ":" + std::to_string(at.column + 1) + ": error: " + what);
  }

  llvm::Expected<std::string> scalar(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) return error(node, what + " must be a single value");
    return node.Scalar();
  }

  llvm::Expected<double> number(const YAML::Node& node, const std::string& what) const {
    auto text = scalar(node, what);
    if (!text) return text.takeError();
    char* end = nullptr;
    double v = std::strtod(text->c_str(), &end);
    if (text->empty() || *end || !std::isfinite(v)) return error(node, what + " must be a number, not '" + *text + "'");
    return v;
  }

  llvm::Expected<long long> integer(const YAML::Node& node, const std::string& what) const {
    auto text = scalar(node, what);
    if (!text) return text.takeError();
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(text->c_str(), &end, 10);
    if (text->empty() || *end || errno) return error(node, what + " must be a whole number, not '" + *text + "'");
    return v;
  }

  llvm::Expected<uint64_t> seed(const YAML::Node& node, const std::string& what) const {
    auto text = scalar(node, what);
    if (!text) return text.takeError();
    if (std::optional<uint64_t> v = seedNumber(*text)) return *v;
    return error(node, what + " must be " + kSeedRange + " (as --seed takes it), not '" + *text + "'");
  }

  // One value or a list of them.
  llvm::Expected<std::vector<std::string>> scalars(const YAML::Node& node, const std::string& what) const {
    std::vector<std::string> out;
    if (node.IsScalar()) return std::vector<std::string>{node.Scalar()};
    if (!node.IsSequence()) return error(node, what + " must be a value or a list of values");
    for (const YAML::Node& item : node) {
      auto v = scalar(item, "each of " + what);
      if (!v) return v.takeError();
      out.push_back(*v);
    }
    return out;
  }

  // A map's keys must be among `known`: a misspelt key would otherwise be silently ignored.
  llvm::Error onlyKeys(const YAML::Node& map, const std::vector<std::string>& known, const std::string& what) const {
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (std::find(known.begin(), known.end(), key) == known.end())
        return error(kv.first, "unknown key '" + key + "' in " + what + " (the keys are " + llvm::join(known, ", ") + ")");
    }
    return llvm::Error::success();
  }

  llvm::Error existing(const YAML::Node& node, const std::string& path, const std::string& folder) const {
    std::error_code ec;
    if (!fs::is_regular_file(fs::path(folder) / path, ec))
      return error(node, path + ": no such file (paths are relative to the sweep file's folder)");
    return llvm::Error::success();
  }

  // {from, to, step}: both ends included; {uniform: [a, b], draws, seed}: draws from a generator
  // of the standard's exact definition, so that the same seed gives the same values everywhere.
  llvm::Expected<std::vector<std::string>> values(const YAML::Node& node, const std::string& name) const {
    const std::string what = "the values of " + name;
    if (!node.IsMap()) {
      auto list = scalars(node, what);
      if (list && list->empty()) return error(node, what + ": the list is empty");
      return list;
    }
    std::vector<std::string> out;
    if (node["uniform"]) {
      if (auto e = onlyKeys(node, {"uniform", "draws", "seed"}, what)) return std::move(e);
      YAML::Node range = node["uniform"];
      if (!range.IsSequence() || range.size() != 2) return error(range, "uniform: give the range as [low, high]");
      auto lo = number(range[0], "uniform's low end"), hi = number(range[1], "uniform's high end");
      if (!lo) return lo.takeError();
      if (!hi) return hi.takeError();
      if (!node["draws"]) return error(node, what + ": give the number of draws (draws: N)");
      if (!node["seed"]) return error(node, what + ": give the draws' seed (seed: N), so that they are the same each time");
      auto draws = integer(node["draws"], "draws");
      auto seed = this->seed(node["seed"], "seed");
      if (!draws) return draws.takeError();
      if (!seed) return seed.takeError();
      if (*draws < 1 || size_t(*draws) > kMostRuns) return error(node["draws"], "draws must be 1 to 999999");
      // low + (high - low) * unit: the difference must be a number, or every draw is inf or nan.
      if (!std::isfinite(*hi - *lo))
        return error(range, "uniform: the range from " + numberText(*lo) + " to " + numberText(*hi) + " is too wide");
      std::mt19937_64 random(*seed);
      for (long long i = 0; i < *draws; ++i) {
        double unit = double(random() >> 11) * 0x1.0p-53;  // [0, 1), 53 random bits
        out.push_back(numberText(*lo + (*hi - *lo) * unit));
      }
      return out;
    }
    if (node["from"] || node["to"]) {
      if (auto e = onlyKeys(node, {"from", "to", "step"}, what)) return std::move(e);
      if (!node["from"] || !node["to"]) return error(node, what + ": a range needs both from and to");
      auto from = number(node["from"], "from"), to = number(node["to"], "to");
      if (!from) return from.takeError();
      if (!to) return to.takeError();
      double step = 1;
      if (node["step"]) {
        auto s = number(node["step"], "step");
        if (!s) return s.takeError();
        step = *s;
      }
      // Signs, not (to - from) * step < 0: that product can round to -0 or 0 and pass.
      if (step == 0 || (*to > *from && step < 0) || (*to < *from && step > 0))
        return error(node["step"] ? node["step"] : node, what + ": the step does not lead from " + numberText(*from) +
                                                             " to " + numberText(*to));
      // The tolerance keeps the end that 0.1 steps reach only up to rounding.
      double count = std::floor((*to - *from) / step + 1e-9) + 1;
      if (count > double(kMostRuns)) return error(node, what + ": more than 999999 values (is the step too small?)");
      for (long long i = 0; i < (long long)count; ++i) out.push_back(numberText(*from + double(i) * step));
      return out;
    }
    return error(node, what + ": give a list of values, a range {from, to, step} or random draws {uniform: [low, "
                              "high], draws, seed}");
  }

  llvm::Expected<Sweep> read(const std::string& text) const {
    Sweep s;
    s.file = file_;
    s.folder = fs::path(file_).parent_path().string();
    s.text = text;
    YAML::Node root;
    KeyChecker keys;
    bool moreDocuments = false;
    try {
      root = YAML::Load(text);
      std::istringstream in(text);
      YAML::Parser events(in);
      events.HandleNextDocument(keys);
      moreDocuments = events.HandleNextDocument(keys);
    } catch (const YAML::ParserException& e) {
      return error(e.mark, e.msg);
    }
    if (keys.found) return error(keys.found->first, keys.found->second);
    // YAML::Load reads the first document alone: what comes after a second --- would be ignored.
    if (moreDocuments) return error(keys.document, "a sweep file is one YAML document; this is a second one");
    if (!root.IsMap()) return error(root, "a sweep file is a map of model, files, parameters, seeds, outputs, options");
    if (auto e = onlyKeys(root, {"model", "files", "parameters", "seeds", "outputs", "options"}, "the sweep file"))
      return std::move(e);
    if (!root["model"]) return error(YAML::Mark::null_mark(), "no model: give the L-system file (model: tree.l)");
    auto model = scalar(root["model"], "model");
    if (!model) return model.takeError();
    if (auto e = existing(root["model"], *model, s.folder)) return std::move(e);
    if (!languageOf(*model))
      return error(root["model"], *model + " is not a model file (" + modelExtensions() + ")");
    s.model = *model;
    if (YAML::Node files = root["files"]) {
      auto list = scalars(files, "files");
      if (!list) return list.takeError();
      for (size_t i = 0; i < list->size(); ++i)
        if (auto e = existing(files.IsSequence() ? files[i] : files, (*list)[i], s.folder)) return std::move(e);
      s.files = *list;
    }
    size_t runs = 1;
    if (YAML::Node parameters = root["parameters"]) {
      if (!parameters.IsMap()) return error(parameters, "parameters must be a map: NAME: values");
      for (const auto& kv : parameters) {
        const std::string name = kv.first.Scalar();
        bool identifier = !name.empty() && !std::isdigit((unsigned char)name[0]);
        for (char c : name) identifier = identifier && (std::isalnum((unsigned char)c) || c == '_');
        if (!identifier) return error(kv.first, "'" + name + "' is not a name a -D can define");
        if (name == "seed") return error(kv.first, "'seed' names the runs' seeds (seeds:), not a parameter");
        auto values = this->values(kv.second, name);
        if (!values) return values.takeError();
        for (const std::string& v : *values)
          if (v.find_first_of("\t\n\r") != std::string::npos)
            return error(kv.second, "a value of " + name + " has a tab or a line break, which a -D cannot carry");
        runs *= values->size();
        if (runs > kMostRuns) return error(kv.second, "more than 999999 runs");
        s.parameters.push_back({name, *values});
      }
    }
    if (YAML::Node seeds = root["seeds"]) {
      s.seeded = true;
      if (seeds.IsScalar()) {
        auto n = integer(seeds, "seeds");
        if (!n) return n.takeError();
        if (*n < 1) return error(seeds, "seeds: give at least one run (seeds: N runs with --seed 1 … N)");
        if (size_t(*n) > kMostRuns) return error(seeds, "more than 999999 runs");
        for (uint64_t i = 1; i <= uint64_t(*n); ++i) s.seeds.push_back(i);
      } else if (seeds.IsMap()) {
        if (auto e = onlyKeys(seeds, {"from", "count"}, "seeds")) return std::move(e);
        if (!seeds["from"] || !seeds["count"]) return error(seeds, "seeds: give from and count ({from: 100, count: 5})");
        auto from = seed(seeds["from"], "from");
        auto count = integer(seeds["count"], "count");
        if (!from) return from.takeError();
        if (!count) return count.takeError();
        if (*count < 1 || size_t(*count) > kMostRuns) return error(seeds["count"], "count must be 1 to 999999");
        if (uint64_t(*count - 1) > UINT64_MAX - *from)
          return error(seeds, "seeds: from " + std::to_string(*from) + ", count " + std::to_string(*count) +
                                  " passes the largest seed, " + std::to_string(UINT64_MAX));
        for (uint64_t i = 0; i < uint64_t(*count); ++i) s.seeds.push_back(*from + i);
      } else if (seeds.IsSequence()) {
        for (const YAML::Node& item : seeds) {
          auto n = seed(item, "each seed");
          if (!n) return n.takeError();
          s.seeds.push_back(*n);
        }
        if (s.seeds.empty()) return error(seeds, "seeds: the list is empty");
      } else {
        return error(seeds, "seeds: give a number of runs, {from: F, count: N} or a list of seeds");
      }
      runs *= s.seeds.size();
      if (runs > kMostRuns) return error(seeds, "more than 999999 runs");
    }
    if (YAML::Node outputs = root["outputs"]) {
      static const std::map<std::string, std::string> kinds = {
          {"string", "out.str"}, {"picture", "out.png"}, {"mesh", "out.obj"}};
      auto list = scalars(outputs, "outputs");
      if (!list) return list.takeError();
      for (size_t i = 0; i < list->size(); ++i) {
        auto kind = kinds.find((*list)[i]);
        if (kind == kinds.end())
          return error(outputs.IsSequence() ? outputs[i] : outputs,
                       "unknown output '" + (*list)[i] + "' (the outputs are string, picture, mesh)");
        if (kind->first == "string" && languageOf(s.model)->engine != EngineKind::LSystem)
          return error(outputs.IsSequence() ? outputs[i] : outputs,
                       "a " + std::string(languageOf(s.model)->model) + " has no string (its outputs are picture, mesh)");
        if (std::find(s.outputs.begin(), s.outputs.end(), kind->second) == s.outputs.end())
          s.outputs.push_back(kind->second);
      }
    }
    if (YAML::Node options = root["options"]) {
      auto list = scalars(options, "options");
      if (!list) return list.takeError();
      s.options = *list;
    }
    return s;
  }

 private:
  std::string file_;
};

// --- The plan: DIR/sweep.json (what it was made from), DIR/tasks.tsv, DIR/ids --------------------

// What a task needs of the sweep, fixed when planned: a sweep file edited later changes no run.
struct Plan {
  fs::path dir;
  Json json;
  std::vector<std::string> parameterNames() const { return json["parameters"].get<std::vector<std::string>>(); }
};

fs::path absolutePath(const std::string& name) { return fs::absolute(name).lexically_normal(); }

std::string defaultDir(const std::string& file) {
  fs::path p = absolutePath(file);
  return (p.parent_path() / (p.stem().string() + "-runs")).string();
}

// The plan's folder of plan, run and slurm: --out, or beside the sweep file.
std::string planDir(const SweepCommand& c) { return c.dir.empty() ? defaultDir(c.file) : c.dir; }

bool hasControlCharacter(const std::string& text) {
  return std::any_of(text.begin(), text.end(), [](unsigned char ch) { return ch < 0x20 || ch == 0x7f; });
}

// A name as an error message shows it: control characters as \n, \t, \r or \xHH, so that a name
// with a line break in it reads as one line.
std::string shownName(const std::string& name) {
  std::string shown;
  for (unsigned char ch : name) {
    if (ch == '\n') shown += "\\n";
    else if (ch == '\t') shown += "\\t";
    else if (ch == '\r') shown += "\\r";
    else if (ch < 0x20 || ch == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", ch);
      shown += hex;
    } else {
      shown += char(ch);
    }
  }
  return shown;
}

llvm::Expected<Plan> loadPlan(const std::string& dirName) {
  Plan plan;
  plan.dir = absolutePath(dirName);
  fs::path file = plan.dir / "sweep.json";
  std::error_code ec;
  if (!fs::exists(file, ec))
    return failure(dirName + ": error: no sweep was planned here (no sweep.json): lcjit sweep plan FILE --out " + dirName);
  auto text = readText(file);
  if (!text) return text.takeError();
  plan.json = Json::parse(*text, nullptr, false);
  if (plan.json.is_discarded() || !plan.json.is_object() || !plan.json.contains("hash"))
    return failure(file.string() + ": error: not a sweep plan lcjit wrote");
  return plan;
}

std::string tasksLine(const SweepRun& run, const fs::path& dir) {
  std::string line = run.id + "\t" + (dir / "runs" / run.id).string();
  for (const auto& [name, value] : run.values) line += "\t" + name + "=" + value;
  if (run.seed) line += "\tseed=" + std::to_string(*run.seed);
  return line + "\n";
}

// Plans the sweep into `dirName`, or finds it planned there from the same text. Returns the plan
// and whether it was made now.
llvm::Expected<std::pair<Plan, bool>> plan(const Sweep& sweep, const std::string& dirName, const std::string& version) {
  fs::path dir = absolutePath(dirName);
  // tasks.tsv is a line a run, tab-separated, and the run's folder is one of its fields.
  if (hasControlCharacter(dir.string()))
    return failure(shownName(dir.string()) + ": error: the plan's folder has a line break, a tab or another control "
                                             "character in its name, which tasks.tsv cannot carry: plan it "
                                             "elsewhere with --out DIR");
  const std::string hash = blake3Hex(sweep.text);
  std::error_code ec;
  if (fs::exists(dir / "sweep.json", ec)) {
    auto existing = loadPlan(dirName);
    if (!existing) return existing.takeError();
    if (existing->json["hash"] != hash)
      return failure("lcjit sweep: error: " + dirName + " was planned from another sweep file (" +
                     existing->json.value("sweep", std::string("?")) + " as it was then): use another --out or remove it");
    return std::make_pair(std::move(*existing), false);
  }
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
    return failure(dirName + ": error: the folder exists and holds no sweep plan (sweep.json): use another --out or "
                             "remove it");
  fs::create_directories(dir / "runs", ec);
  if (ec) return failure(dirName + ": error: cannot make the folder: " + ec.message());
  std::string tasks, ids;
  const std::vector<SweepRun> runs = sweepRuns(sweep);
  for (const SweepRun& run : runs) {
    tasks += tasksLine(run, dir);
    ids += run.id + "\n";
  }
  Plan p;
  p.dir = dir;
  std::vector<std::string> names;
  for (const auto& parameter : sweep.parameters) names.push_back(parameter.name);
  p.json = Json{{"lcjit", version},
                {"sweep", sweep.file},
                {"hash", hash},
                {"folder", sweep.folder},
                {"model", sweep.model},
                {"files", sweep.files},
                {"parameters", names},
                {"seeded", sweep.seeded},
                {"outputs", sweep.outputs},
                {"options", sweep.options},
                {"runs", runs.size()},
                {"text", sweep.text}};
  // sweep.json last: its presence says the plan is whole.
  if (auto e = support::writeWholeFile((dir / "tasks.tsv").string(), tasks)) return std::move(e);
  if (auto e = support::writeWholeFile((dir / "ids").string(), ids)) return std::move(e);
  if (auto e = support::writeWholeFile((dir / "sweep.json").string(), p.json.dump(2) + "\n")) return std::move(e);
  return std::make_pair(std::move(p), true);
}

struct Task {
  std::string id;
  std::vector<std::pair<std::string, std::string>> values;
  std::optional<uint64_t> seed;
};

llvm::Expected<std::vector<Task>> loadTasks(const Plan& plan) {
  auto text = readText(plan.dir / "tasks.tsv");
  if (!text) return text.takeError();
  std::vector<Task> tasks;
  std::istringstream lines(*text);
  for (std::string line; std::getline(lines, line);) {
    llvm::SmallVector<llvm::StringRef, 8> fields;
    llvm::StringRef(line).split(fields, '\t');
    if (fields.size() < 2) return failure((plan.dir / "tasks.tsv").string() + ": error: a line without a run's folder");
    Task t;
    t.id = fields[0].str();
    for (size_t i = 2; i < fields.size(); ++i) {
      auto [name, value] = fields[i].split('=');
      // A parameter is never called seed (readSweep).
      if (name != "seed") t.values.emplace_back(name.str(), value.str());
      else if (!(t.seed = seedNumber(value.str())))
        return failure((plan.dir / "tasks.tsv").string() + ": error: run " + t.id + ": not a seed: " + value.str());
    }
    tasks.push_back(std::move(t));
  }
  return tasks;
}

// --- Child processes ------------------------------------------------------------------------------

std::string thisProgram() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("lcjit") : exe.string();
}

// Runs `args` and waits for it; the wait status. With `folder`, it works there, reads nothing and
// writes its output to the two files; without, it shares this process's.
struct Redirect {
  std::string folder, out, err;
};
llvm::Expected<int> runChild(const std::vector<std::string>& args, const std::optional<Redirect>& redirect) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (redirect) {
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, redirect->out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, redirect->err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addchdir_np(&actions, redirect->folder.c_str());
  }
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  int failed = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (failed) return failure(args[0] + ": error: cannot start it: " + std::strerror(failed));
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return failure(args[0] + ": error: lost the child process: " + std::strerror(errno));
  return status;
}

// The end of what a child said, on one line: its last three lines that say something (a usage
// error is two lines, the second the less telling), at most 500 characters. Only the file's last
// 4 KB are read: a run may have printed gigabytes before it died, and `sweep run -j N` has N of
// these at once.
std::string lastWords(const fs::path& file) {
  constexpr std::streamoff kTail = 4096;
  constexpr size_t kMostWords = 500;
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  const std::streamoff size = in ? std::streamoff(in.tellg()) : -1;
  if (size <= 0) return "";
  const std::streamoff start = std::max<std::streamoff>(0, size - kTail);
  std::string text(size_t(size - start), '\0');
  in.seekg(start);
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(in.gcount()));
  llvm::SmallVector<llvm::StringRef, 16> lines;
  llvm::StringRef(text).split(lines, '\n', -1, false);
  // Zero bytes are blank too: what a file extended by ftruncate holds, not words.
  const llvm::StringRef blank(" \t\n\v\f\r\0", 7);
  std::vector<std::string> last;
  bool cut = false;  // a line taken is the tail's first, the end of a longer one
  for (size_t i = lines.size(); i-- > 0 && last.size() < 3;) {
    llvm::StringRef line = lines[i].trim(blank);
    if (line.empty()) continue;
    last.insert(last.begin(), line.str());
    cut = start > 0 && i == 0;
  }
  std::string words = llvm::join(last, " | ");
  if (words.size() > kMostWords) return "..." + words.substr(words.size() - kMostWords);
  return cut ? "..." + words : words;
}

// --- The verbs ------------------------------------------------------------------------------------

int report(llvm::Error e) {
  std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  return 1;
}

int runTask(const SweepCommand& c) {
  auto plan = loadPlan(c.dir);
  if (!plan) return report(plan.takeError());
  auto tasks = loadTasks(*plan);
  if (!tasks) return report(tasks.takeError());
  auto task = std::find_if(tasks->begin(), tasks->end(), [&](const Task& t) { return t.id == c.id; });
  if (task == tasks->end())
    return report(failure((plan->dir / "tasks.tsv").string() + ": error: no run " + c.id));
  const Json& j = plan->json;
  const fs::path runDir = plan->dir / "runs" / task->id, record = runDir / "record.json";
  std::error_code ec;
  fs::create_directories(runDir, ec);
  if (ec) return report(failure(runDir.string() + ": error: cannot make the run's folder: " + ec.message()));
  // What an earlier try left must not pass for this one's.
  fs::remove(record, ec);
  for (const std::string& out : j["outputs"].get<std::vector<std::string>>()) fs::remove(runDir / out, ec);

  std::vector<std::string> args = {thisProgram(), "-b"};
  for (const auto& [name, value] : task->values) args.insert(args.end(), {"-D", name + "=" + value});
  if (task->seed) args.insert(args.end(), {"--seed", std::to_string(*task->seed)});
  args.insert(args.end(), {"--run-record", record.string()});
  for (const std::string& out : j["outputs"].get<std::vector<std::string>>())
    args.insert(args.end(), {"-out", (runDir / out).string()});
  for (const std::string& option : j["options"].get<std::vector<std::string>>()) args.push_back(option);
  args.push_back(j["model"].get<std::string>());
  for (const std::string& file : j["files"].get<std::vector<std::string>>()) args.push_back(file);

  const fs::path err = runDir / "stderr.txt";
  auto status = runChild(args, Redirect{j["folder"].get<std::string>(), (runDir / "stdout.txt").string(), err.string()});
  if (!status) return report(status.takeError());

  std::string why;
  if (fs::exists(record, ec)) {
    auto text = readText(record);
    Json r = text ? Json::parse(*text, nullptr, false) : Json();
    if (!text) llvm::consumeError(text.takeError());
    if (r.is_object() && r.contains("status")) return r["status"] == "ok" ? 0 : 1;
    why = "its record.json is not a whole JSON object; ";
  }
  // The child died before it could say how (a kill, a crash of lcjit itself, a usage error):
  // the run is still a row of the table, with the reason.
  if (WIFSIGNALED(*status))
    why += "lcjit was killed by signal " + std::to_string(WTERMSIG(*status)) + " (" + strsignal(WTERMSIG(*status)) +
           ") and wrote no record";
  else
    why += "lcjit exited with status " + std::to_string(WEXITSTATUS(*status)) + " and wrote no record";
  if (std::string last = lastWords(err); !last.empty()) why += "; it said: " + last;
  Json overrides = Json::object();
  for (const auto& [name, value] : task->values) overrides[name] = value;
  Json r = {{"lcjit", c.version},
            {"model", j["model"]},
            {"overrides", overrides},
            {"seed", task->seed ? Json(*task->seed) : Json()},
            {"status", "error"},
            {"error", why}};
  if (auto e = support::writeWholeFile(record.string(), r.dump(2) + "\n")) return report(std::move(e));
  return 1;
}

// --- collect: DIR/results.csv ---------------------------------------------------------------------

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char ch : text) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

std::string cellText(const Json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

// The measures as columns: nested keys joined with dots; the bounding box's six numbers named.
void flatten(const std::string& key, const Json& v, std::vector<std::pair<std::string, std::string>>& out) {
  static const char* box[] = {"xmin", "ymin", "zmin", "xmax", "ymax", "zmax"};
  const std::string prefix = key.empty() ? "" : key + ".";
  if (v.is_object()) {
    for (const auto& [k, item] : v.items()) flatten(prefix + k, item, out);
  } else if (v.is_array()) {
    const bool named = key == "bbox" && v.size() == 6;
    for (size_t i = 0; i < v.size(); ++i) flatten(prefix + (named ? box[i] : std::to_string(i)), v[i], out);
  } else {
    out.emplace_back(key, cellText(v));
  }
}

// A column first seen in a later run goes beside its kind (modules.X after the other modules),
// so that the table reads the same whichever run had it first.
void addColumn(std::vector<std::string>& columns, const std::string& key) {
  if (std::find(columns.begin(), columns.end(), key) != columns.end()) return;
  const std::string group = key.substr(0, key.find('.'));
  auto last = std::find_if(columns.rbegin(), columns.rend(),
                           [&](const std::string& c) { return c.substr(0, c.find('.')) == group; });
  columns.insert(last == columns.rend() ? columns.end() : last.base(), key);
}

struct CollectCounts {
  size_t ok = 0, error = 0, missing = 0;
};

llvm::Expected<CollectCounts> collect(const Plan& plan) {
  auto tasks = loadTasks(plan);
  if (!tasks) return tasks.takeError();
  struct Row {
    std::string status, error, steps;
    std::map<std::string, std::string> measures;
  };
  std::vector<Row> rows;
  std::vector<std::string> columns;
  CollectCounts counts;
  for (const Task& t : *tasks) {
    Row row;
    const fs::path record = plan.dir / "runs" / t.id / "record.json";
    std::error_code ec;
    if (!fs::exists(record, ec)) {
      row.status = "missing";
      ++counts.missing;
      rows.push_back(std::move(row));
      continue;
    }
    auto text = readText(record);
    if (!text) return text.takeError();
    Json r = Json::parse(*text, nullptr, false);
    if (!r.is_object()) {
      row.status = "error";
      row.error = "record.json is not a JSON object";
    } else {
      row.status = cellText(r.value("status", Json("error")));
      row.error = cellText(r.value("error", Json()));
      row.steps = cellText(r.value("steps", Json()));
      std::vector<std::pair<std::string, std::string>> measures;
      if (r.contains("measures")) flatten("", r["measures"], measures);
      for (auto& [key, value] : measures) {
        addColumn(columns, key);
        row.measures[key] = value;
      }
    }
    (row.status == "ok" ? counts.ok : counts.error)++;
    rows.push_back(std::move(row));
  }
  std::vector<std::string> header = {"id"};
  const std::vector<std::string> names = plan.parameterNames();
  header.insert(header.end(), names.begin(), names.end());
  header.insert(header.end(), {"seed", "status", "error", "steps"});
  header.insert(header.end(), columns.begin(), columns.end());
  auto line = [](const std::vector<std::string>& cells) {
    std::string text;
    for (size_t i = 0; i < cells.size(); ++i) text += (i ? "," : "") + csvField(cells[i]);
    return text + "\r\n";  // RFC 4180's line end
  };
  std::string csv = line(header);
  for (size_t i = 0; i < rows.size(); ++i) {
    const Task& t = (*tasks)[i];
    std::vector<std::string> cells = {t.id};
    for (const auto& [name, value] : t.values) cells.push_back(value);
    cells.push_back(t.seed ? std::to_string(*t.seed) : "");
    cells.insert(cells.end(), {rows[i].status, rows[i].error, rows[i].steps});
    for (const std::string& c : columns) {
      auto v = rows[i].measures.find(c);
      cells.push_back(v == rows[i].measures.end() ? "" : v->second);
    }
    csv += line(cells);
  }
  if (auto e = support::writeWholeFile((plan.dir / "results.csv").string(), csv)) return std::move(e);
  return counts;
}

// Writes the table and says what is in it. `complete`: a run without a record makes the status 1.
int collectAndSay(const Plan& plan, bool complete) {
  auto counts = collect(plan);
  if (!counts) return report(counts.takeError());
  std::printf("%s: %zu runs: %zu ok, %zu failed, %zu missing\n", (plan.dir / "results.csv").c_str(),
              counts->ok + counts->error + counts->missing, counts->ok, counts->error, counts->missing);
  return complete && counts->missing ? 1 : 0;
}

// --- plan, run, slurm: each plans first ---------------------------------------------------------------

llvm::Expected<Plan> planned(const SweepCommand& c) {
  auto sweep = readSweep(c.file);
  if (!sweep) return sweep.takeError();
  auto made = plan(*sweep, planDir(c), c.version);
  if (!made) return made.takeError();
  std::printf("%s: %zu runs%s\n", made->first.dir.c_str(), made->first.json["runs"].get<size_t>(),
              made->second ? " planned" : " (planned before)");
  return std::move(made->first);
}

int runWithParallel(const SweepCommand& c) {
  auto p = planned(c);
  if (!p) return report(p.takeError());
  auto parallel = llvm::sys::findProgramByName("parallel");
  if (!parallel)
    return report(failure("lcjit sweep run: error: GNU parallel is not on PATH; install Debian's parallel "
                          "(apt-get install parallel), or run the tasks another way (docs/sweeps.md)"));
  const std::string dir = p->dir.string();
  // --resume: the joblog says which runs were done (ok or not), so a stopped sweep goes on where it
  // stopped and a finished one runs nothing. -q: the paths reach the task as they are, unparsed by a shell.
  std::vector<std::string> args = {*parallel, "--joblog", dir + "/joblog", "--resume", "-j", std::to_string(c.jobs)};
  if (isatty(2)) args.push_back("--bar");
  args.insert(args.end(), {"-q", thisProgram(), "sweep", "task", dir, "{}", "::::", dir + "/ids"});
  auto status = runChild(args, std::nullopt);
  if (!status) return report(status.takeError());
  // parallel's status is the number of failed tasks: failed runs are rows of the table, not a
  // failed sweep; a parallel that could not run is.
  if (WIFSIGNALED(*status) || WEXITSTATUS(*status) > 101)
    std::fprintf(stderr, "lcjit sweep run: warning: GNU parallel stopped early (%s); run the sweep again to go on\n",
                 WIFSIGNALED(*status) ? strsignal(WTERMSIG(*status)) : ("status " + std::to_string(WEXITSTATUS(*status))).c_str());
  return collectAndSay(*p, true);
}

std::string shellQuoted(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

// An #SBATCH line's argument as sbatch reads it (Slurm's src/sbatch/opt.c, get_argument): in double
// quotes spaces and # are text, and a backslash takes the next character as it is.
std::string slurmQuoted(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') q += '\\';
    q += ch;
  }
  return q + "\"";
}

int writeSlurm(const SweepCommand& c) {
  if (c.chunk < 1) return report(failure("lcjit sweep slurm: error: --chunk must be at least 1"));
  // The script names the sweep file and the plan's folder in comments and #SBATCH lines, which end
  // at a line break: bash would run what follows one. Refused before anything is written; the
  // plan's folder has no control characters either (plan refuses them).
  const std::string sweepFile = absolutePath(c.file).string(), dir = absolutePath(planDir(c)).string();
  if (hasControlCharacter(sweepFile))
    return report(failure(shownName(sweepFile) + ": error: the sweep file has a line break, a tab or another control "
                                                 "character in its name, which a Slurm script cannot carry: rename it"));
  // Slurm's --output reads a backslash as "no %A or %a here" and drops it.
  if (dir.find('\\') != std::string::npos)
    return report(failure(shownName(dir) + ": error: the plan's folder has a backslash in its name, which Slurm's --output "
                                "cannot carry: plan it elsewhere with --out DIR"));
  std::string outputPattern;  // % is Slurm's: %% is one
  for (char ch : dir) outputPattern += ch == '%' ? std::string("%%") : std::string(1, ch);
  auto p = planned(c);
  if (!p) return report(p.takeError());
  const size_t runs = p->json["runs"].get<size_t>();
  const size_t arrayTasks = (runs + c.chunk - 1) / c.chunk;
  std::error_code ec;
  fs::create_directories(p->dir / "slurm", ec);
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Slurm job array of the sweep " << sweepFile << ", written by lcjit sweep slurm\n"
    << "# (docs/sweeps.md). Array task T runs the ids on lines T*" << c.chunk << "+1 to (T+1)*" << c.chunk
    << " of ids with GNU parallel on its\n"
    << "# CPUs; submitted again, a task skips the runs its joblog has. Then: lcjit sweep collect DIR.\n"
    << "#SBATCH --job-name=" << slurmQuoted("lcjit-" + fs::path(sweepFile).stem().string()) << "\n"
    << "#SBATCH --array=0-" << arrayTasks - 1 << "\n"
    << "#SBATCH --ntasks=1\n"
    << "#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << slurmQuoted(outputPattern + "/slurm/%A_%a.out") << "\n"
    << "set -eu\n"
    << "dir=" << shellQuoted(dir) << "\n"
    << "first=$((SLURM_ARRAY_TASK_ID * " << c.chunk << " + 1))\n"
    << "sed -n \"${first},$((first + " << c.chunk - 1 << "))p\" \"$dir/ids\" |\n"
    << "  parallel --joblog \"$dir/joblog.$SLURM_ARRAY_TASK_ID\" --resume -j \"${SLURM_CPUS_PER_TASK:-1}\" \\\n"
    << "    -q " << shellQuoted(thisProgram()) << " sweep task \"$dir\" {}\n";
  const fs::path script = p->dir / "sweep.sbatch";
  if (auto e = support::writeWholeFile(script.string(), s.str())) return report(std::move(e));
  std::printf("%s: %zu array tasks of up to %d runs; submit it with:\n  sbatch %s\nand when it is done:\n  %s sweep "
              "collect %s\n",
              script.c_str(), arrayTasks, c.chunk, shellQuoted(script.string()).c_str(), thisProgram().c_str(),
              shellQuoted(dir).c_str());
  return 0;
}

}  // namespace

const char* const kSeedRange = "a whole number from 0 to 18446744073709551615";

std::optional<uint64_t> seedNumber(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  unsigned long long v = 0;
  if (llvm::StringRef(text).getAsInteger(10, v)) return std::nullopt;  // past 2^64 - 1
  return uint64_t(v);
}

llvm::Expected<Sweep> readSweep(const std::string& file) {
  const std::string path = absolutePath(file).string();
  auto text = readText(path);
  if (!text) return text.takeError();
  return SweepReader(path).read(*text);
}

std::vector<SweepRun> sweepRuns(const Sweep& sweep) {
  size_t count = sweep.seeded ? sweep.seeds.size() : 1;
  for (const auto& parameter : sweep.parameters) count *= parameter.values.size();
  std::vector<SweepRun> runs;
  for (size_t index = 0; index < count; ++index) {
    SweepRun run;
    run.id = runId(index);
    // The index in mixed radix, the seed its last digit.
    size_t rest = index;
    if (sweep.seeded) {
      run.seed = sweep.seeds[rest % sweep.seeds.size()];
      rest /= sweep.seeds.size();
    }
    for (size_t i = sweep.parameters.size(); i-- > 0;) {
      const auto& values = sweep.parameters[i].values;
      run.values.emplace_back(sweep.parameters[i].name, values[rest % values.size()]);
      rest /= values.size();
    }
    std::reverse(run.values.begin(), run.values.end());
    runs.push_back(std::move(run));
  }
  return runs;
}

int runSweep(const SweepCommand& c) {
  switch (c.verb) {
    case SweepVerb::Plan: {
      auto p = planned(c);
      return p ? 0 : report(p.takeError());
    }
    case SweepVerb::Task:
      return runTask(c);
    case SweepVerb::Run:
      return runWithParallel(c);
    case SweepVerb::Slurm:
      return writeSlurm(c);
    case SweepVerb::Collect: {
      auto p = loadPlan(c.dir);
      return p ? collectAndSay(*p, false) : report(p.takeError());
    }
  }
  return 1;
}

}  // namespace lcjit::app
