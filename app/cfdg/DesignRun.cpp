// A Context Free design run from the command line (DesignRun.h).
#include "app/cfdg/DesignRun.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <cstdio>
#include <cctype>
#include <random>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/cfdg/DesignProfile.h"
#include "app/cli/Modes.h"
#include "app/cli/Options.h"
#include "app/common/FrameSequence.h"
#include "app/common/RunRecord.h"
#include "app/session/FileMonitor.h"
#include "app/session/Session.h"  // runtimeIncludeDir, prebuiltDir
#include "app/session/Languages.h"
#include "frontend/cfdg/ReadDesign.h"
#include "jit/Compiler.h"
#include "runtime/ModelGuard.h"
#include "runtime/cfdg/DesignGeometry.h"
#include "runtime/cfdg/Expander.h"
#include "runtime/export/Export.h"
#include "runtime/cfdg/Picture.h"
#include "runtime/cfdg/VectorPage.h"
#include "support/Elapsed.h"
#include "support/InputFile.h"
#include "support/ReplacingFile.h"

namespace lcjit::app {
namespace {

int failed(llvm::Error e) {
  std::fprintf(stderr, "%s\n", llvm::toString(std::move(e)).c_str());
  return 1;
}

}  // namespace

DesignRunOptions designRunOptions(const Options& options, const std::string& cacheDir) {
  DesignRunOptions d;
  d.design = modelOf(options.inputs);
  d.outs = options.outs;
  if (options.winSize.size() == 2) d.width = int(options.winSize[0]), d.height = int(options.winSize[1]);
  d.variation = options.variation;
  if (options.optLevel) d.optLevel = *options.optLevel;
  d.emitCpp = options.emitCpp;
  d.quiet = options.quiet;
  d.timing = options.verbose;
  d.watch = options.watch;
  d.defines = options.overrides;
  d.maxMemory = options.maxMemory;
  d.frames = options.frames;
  d.fps = options.fps;
  d.seed = options.seed;
  d.runRecord = options.runRecord;
  d.profile = options.profile;
  d.cacheDir = cacheDir;
  return d;
}

void declareCfdgOptions(CLI::App& c, DesignRunOptions& o) {
  o.cfdgNames = true;
  // cfdg's -h is the height: help is --help only.
  c.set_help_flag("--help", "Context Free's options, as cfdg 3.4 takes them");
  c.add_option("-w", o.width, "width in pixels (default 500)");
  c.add_option("-h", o.height, "height in pixels (default 500)");
  c.add_option_function<std::string>(
      "-s",
      [&o](const std::string& size) {
        // N, or WxH.
        size_t x = size.find('x');
        o.width = std::stoi(size.substr(0, x));
        o.height = x == std::string::npos ? o.width : std::stoi(size.substr(x + 1));
      },
      "size: N (square) or WxH");
  c.add_option("-v", o.variation, "variation code (letters or a number; default: random)");
  c.add_option("-x", o.minimumSize, "minimum size of a shape in pixels (default 0.3)");
  c.add_option("-m", o.maxShapes, "maximum number of shapes");
  c.add_option("-b", o.border, "border: -1 to 2 (default 2)");
  c.add_option("-o", o.outs,
               "output file: %v and %V are the variation (lower, upper case), %f the animation's frame, %% a percent sign");
  c.add_option("-D", o.defines, "NAME=VALUE: a definition read before the design's (its own NAME is dropped)")
      ->allow_extra_args(false);
  c.add_flag("-q", o.quiet, "quiet");
  c.add_flag("-c", o.crop, "crop the picture to the fitted block (not for tiled or frieze designs)");
  c.add_flag("-t", o.timing, "where the time went: parse, compile, expand, draw");
  c.add_flag_callback("--profile", [&o] { o.profile = "-"; },
                      "(lcjit's) how many times each rule ran and the time it took, hottest first, and the shapes "
                      "finished by kind, on stdout");
  c.add_option_function<std::string>(
      "-a",
      [&o](const std::string& value) {
        // N frames, or TIMExFPS (TIME seconds at FPS frames a second).
        size_t x = value.find('x');
        try {
          o.frames = x == std::string::npos ? std::stoi(value) : std::stoi(value.substr(0, x)) * std::stoi(value.substr(x + 1));
        } catch (std::exception&) {
          throw CLI::ValidationError("-a", "expected a number of frames, or TIMExFPS: " + value);
        }
        if (o.frames < 1) throw CLI::ValidationError("-a", "an animation has at least one frame");
      },
      "an animation: NUM frames, or TIMExFPS; one PNG a frame (_%f is added before the extension of the output file)");
  c.add_option("-f", o.frame, "only this frame of the animation (1 …)");
  c.add_flag("-z", o.zoom, "zoom during the animation (each frame fitted to its shapes; not a design using ftime())");
  c.add_option("design", o.design, "the design (.cfdg)")->required();
  c.add_option("output", o.output, "output file (a name as it is: % is no code)");
}

namespace cf = runtime::cfdg;

namespace {

// The front end of the design's language (Languages.h); `lcjit cfdg` reads any file as CFDG, as
// cfdg does.
ReadDesign designFrontEnd(const std::string& path) {
  const Language* language = languageOf(path);
  if (!language || !language->readDesign) language = languageNamed("CFDG");
  return language->readDesign;
}

}  // namespace

llvm::Expected<std::unique_ptr<jit::Compiler>> designCompiler(const std::string& cacheDir) {
  jit::CompilerConfig config;
  config.runtimeHeader = runtimeIncludeDir() + "/lpfgall.h";
  config.cacheDir = cacheDir;
  config.prebuiltDir = prebuiltDir();
  for (auto& [name, address] : cf::hostSymbols()) config.hostSymbols.push_back({name, address});
  return jit::Compiler::create(std::move(config));
}

llvm::Expected<LoadedDesign> loadDesign(jit::Compiler& compiler, const DesignRunOptions& o) {
  const auto start = support::Clock::now();
  auto text = support::readInputFile(o.design, /*nullTerminated=*/false);
  if (!text) return llvm::createStringError("lcjit: " + o.design + ": " + text.getError().message());
  auto unit = designFrontEnd(o.design)((*text)->getBuffer(), o.design, o.defines);
  if (!unit) return unit.takeError();
  LoadedDesign d;
  d.files = {o.design};
  d.files.insert(d.files.end(), unit->imports.begin(), unit->imports.end());
  d.parseMs = support::msSince(start);
  jit::CompileOptions co;
  co.optLevel = o.optLevel;
  co.plainUnit = true;
  co.bufferName = o.design + ".cpp";
  jit::CompileStats stats;
  auto code = compiler.compile(unit->translation.cpp, co, &stats);
  if (!code) return code.takeError();
  auto table = (*code)->lookup("__cf_design");
  if (!table) return table.takeError();
  d.code = std::move(*code);
  d.table = static_cast<const __cf_Design*>(*table);
  if (d.table->abiVersion != __cf_AbiVersion) return llvm::createStringError("internal error: design ABI version mismatch");
  d.unit = std::move(unit->translation);
  d.variables = std::move(unit->variables);
  d.compileMs = support::msSince(start) - d.parseMs;
  d.fromCache = stats.object != jit::CompileStats::ObjectFrom::Compiled;
  return d;
}

uint64_t chooseVariation(const std::string& code) {
  if (!code.empty()) return cf::variationOf(code);
  std::random_device device;
  return std::uniform_int_distribution<uint64_t>(1, 321272406)(device);
}

namespace {

// The expansion's options: the command line's and the design's settings, merged as cfdg merges
// them.
cf::ExpandOptions expandOptions(const LoadedDesign& d, const DesignRunOptions& o, uint64_t variation) {
  cf::ExpandOptions eo;
  eo.width = o.width;
  eo.height = o.height;
  eo.minimumSize = d.unit.settings.minimumSize > 0 ? d.unit.settings.minimumSize : o.minimumSize;
  eo.border = o.border;
  // -m wins over CF::MaxShapes, which counts when above 1 (as in cfdg).
  if (o.maxShapes > 0) eo.maxShapes = o.maxShapes;
  else if (d.unit.settings.maxShapes > 1) eo.maxShapes = uint64_t(d.unit.settings.maxShapes);
  eo.maxMemory = o.maxMemory;
  eo.variation = variation;
  eo.profile = !o.profile.empty();
  // CF::FrameTime and CF::Frame are what ftime() and frame() give outside an animation (Context
  // Free reads them before it works one out from the other, so a design that sets only one gets 0
  // from the other function).
  const cf::DesignTiming timing = cf::timingOf(*d.table);
  if (timing.hasFrameTime) eo.frameTime = timing.frameTime;
  if (timing.hasFrame) eo.frame = timing.frame;
  return eo;
}

std::vector<double> staticsOf(const LoadedDesign& d, uint64_t variation) {
  // rand_static(): drawn once, before the run, from the variation.
  std::vector<double> statics;
  uint64_t s = variation;
  for (int k = 0; k < d.unit.randStaticCount; ++k) statics.push_back(cf::drawDouble(s));
  return statics;
}

}  // namespace

DesignExpansion expandDesign(const LoadedDesign& d, const DesignRunOptions& o, uint64_t variation) {
  DesignExpansion x;
  x.options = expandOptions(d, o, variation);
  x.expansion = cf::expand(*d.table, x.options, staticsOf(d, variation));
  return x;
}

namespace {

// --run-record (docs/sweeps.md): a design's run as one row of a sweep's table. Its identity as an
// L-system run's (lcjit's version, the design and the files it imports with their BLAKE3, the -D
// values, the seed: the variation), how it ended, and what it made: the shapes drawn, the rules
// expanded, the variation's code and the shapes' bounding box.
void writeRecord(const DesignRunOptions& o, const std::vector<std::string>& imports, uint64_t variation,
                 const cf::Expansion* e, const std::string& error) {
  if (o.runRecord.empty() || o.watch) return;
  ModelFiles files;
  files.lsystem = o.design;
  files.other = imports;
  for (const std::string& d : o.defines) {
    const size_t eq = d.find('=');
    files.overrides.emplace_back(d.substr(0, eq), eq == std::string::npos ? "" : d.substr(eq + 1));
  }
  nlohmann::ordered_json r;
  addRunIdentity(r, files, nullptr, o.seed);
  r["status"] = error.empty() ? "ok" : "error";
  if (!error.empty()) r["error"] = error;
  r["steps"] = e ? 1 : 0;
  if (e && error.empty()) {
    nlohmann::ordered_json m;
    m["variation"] = cf::variationName(variation);
    m["shapes"] = e->shapes.size();
    m["expanded"] = e->expanded;
    if (e->bounds.valid()) m["bbox"] = {e->bounds.minX, e->bounds.minY, 0.0, e->bounds.maxX, e->bounds.maxY, 0.0};
    r["measures"] = m;
  }
  if (auto err = support::writeWholeFile(o.runRecord, r.dump(2) + "\n"))
    std::fprintf(stderr, "%s\n", llvm::toString(std::move(err)).c_str());
}

// An output name as cfdg makes one from a template: %v / %V the variation in lower / upper case,
// %f the animation's frame (zero-padded to the digits of the frame count; 0 for one picture), %%
// a percent sign; another code is written as cfdg writes it.
std::string outputName(const std::string& form, int frame, int frames, uint64_t variation) {
  int digits = 0;
  for (int n = frames; n > 0; n /= 10) ++digits;
  std::string named;
  for (size_t i = 0; i < form.size(); ++i) {
    if (form[i] != '%' || i + 1 == form.size()) {
      named += form[i];
      continue;
    }
    char c = form[++i];
    std::string v = cf::variationName(variation);
    if (c == 'V') named += v;
    else if (c == 'v') for (char ch : v) named += char(std::tolower(static_cast<unsigned char>(ch)));
    else if (c == 'f') {
      std::string number = std::to_string(frame);
      named += std::string(number.size() < size_t(digits) ? size_t(digits) - number.size() : 0, '0') + number;
    } else if (c == '%') named += '%';
    else named += std::string("_Unknown_format_code_") + c + "_";
  }
  return named;
}

bool endsWith(const std::string& s, const char* tail) {
  const size_t n = std::strlen(tail);
  return s.size() > n && s.compare(s.size() - n, n, tail) == 0;
}

}  // namespace

std::optional<cf::PageFormat> pageFormatFor(const std::string& path) {
  if (endsWith(path, ".pdf")) return cf::PageFormat::Pdf;
  if (endsWith(path, ".ps") || endsWith(path, ".eps")) return cf::PageFormat::PostScript;
  return std::nullopt;
}

namespace {

// Writes one expansion's pictures to `outs` (names made). 0, or 1 after printing why.
int writePictures(const LoadedDesign& d, const DesignRunOptions& o, const cf::Expansion& e, const cf::Framing& f,
                  const cf::ExpandOptions& eo, const std::vector<std::string>& outs) {
  // -c: the fitted block alone, as cfdg crops: the SVG is the block's size, the PNG the block's
  // rows counted from the picture's top by the block's offset from its bottom (as cfdg reads them).
  const bool crop = o.crop && !e.picture.tiled && !e.picture.frieze;
  cf::Framing cropped = f;
  cropped.width = f.fit.width, cropped.height = f.fit.height;
  const cf::PixelRect block{int(f.offsetX), f.height - f.fit.height - int(f.offsetY), f.fit.width, f.fit.height};
  for (const std::string& out : outs) {
    if (endsWith(out, ".svg")) {
      if (auto err = support::writeWholeFile(out, cf::svgOf(e, crop ? cropped : f, eo))) return failed(std::move(err));
    } else if (endsWith(out, ".png")) {
      cf::Canvas canvas = cf::drawExpansion(*d.table, e, f, eo);
      if (auto err = cf::writePng(canvas, out, crop ? std::optional<cf::PixelRect>(block) : std::nullopt))
        return failed(std::move(err));
    } else if (auto page = pageFormatFor(out)) {
      if (auto err = support::writeWholeFile(out, cf::vectorPage(*d.table, e, crop ? cropped : f, eo, *page)))
        return failed(std::move(err));
    } else if (auto format = runtime::exportFormatFor(out)) {
      // The other formats lcjit exports: the shapes as flat coloured triangles.
      runtime::Geometry geometry = cf::geometryOf(e, f, eo);
      runtime::ExportInput in;
      in.geometry = &geometry;
      in.width = f.width;
      in.height = f.height;
      if (auto err = runtime::exportGeometry(out, *format, in)) return failed(std::move(err));
    } else {
      std::fprintf(stderr, "lcjit: %s: not a picture or export lcjit writes\n", out.c_str());
      return 1;
    }
  }
  return 0;
}

// A run's error in the design's terms ("" when it had none).
std::string errorOf(const cf::Expansion& e, const DesignRunOptions& o) {
  return e.error.empty() ? "" : (e.errorAt.empty() ? o.design : e.errorAt) + ": error: " + e.error;
}
// A run that failed prints its error (0 when it did not).
int runError(const cf::Expansion& e, const DesignRunOptions& o) {
  if (e.error.empty()) return 0;
  std::fprintf(stderr, "%s\n", errorOf(e, o).c_str());
  return 1;
}

// -a: an animation's frames, as cfdg makes them. The frames divide the animation's time (CF::Time,
// else the time the shapes span, else the picture's area: the shapes then appear in the order they
// were made) into equal windows; a frame draws the shapes whose time overlaps its window. A design
// that uses ftime() or frame() is expanded again for each frame, with ftime() the window's middle
// and frame() its place (0 … 1), and keeps only those shapes; another is expanded once. With -f K
// only frame K is made, and its window starts where the animation starts (as in cfdg). lcjit's own
// command line (--frames) also writes numbered files (frame%03d.png) and videos, one frame each.
int animateDesign(const LoadedDesign& d, const DesignRunOptions& o, cf::ExpandOptions eo, const cf::DesignTiming& timing,
                  const std::vector<double>& statics, uint64_t variation) {
  const bool perFrame = d.table->usesFrameTime != 0;
  eo.animation = true;
  cf::TimeSpan time = timing.hasTime ? timing.time : cf::TimeSpan{};
  cf::Expansion once;
  cf::Framing onceFraming;
  if (!perFrame) {
    eo.keepTimes = true;
    once = cf::expand(*d.table, eo, statics);
    if (runError(once, o)) return 1;
    if (!timing.hasTime) time = once.timeBounds;
    onceFraming = cf::frame(once, eo);
  }
  // lcjit's own outputs of many frames (not cfdg's names): numbered files and videos.
  std::vector<std::unique_ptr<FrameSequence>> sequences(o.outs.size());
  for (size_t i = 0; i < o.outs.size(); ++i) {
    if (o.cfdgNames || !isFrameSequence(o.outs[i])) continue;
    auto sequence = FrameSequence::open(o.outs[i], o.fps);
    if (!sequence) return failed(sequence.takeError());
    sequences[i] = std::move(*sequence);
  }
  const double step = (time.end - time.begin) / o.frames;
  // -z (a design expanded once): each frame fitted to the boxes of the shapes whose time reaches
  // into it, smoothed backwards in time (each frame's bounds move 0.5^(1/10) of the way to the next
  // one's); a frame without such bounds keeps the framing before it (as cfdg's OutputBounds).
  std::vector<cf::Bounds> zoom;
  if (o.zoom && !perFrame) {
    zoom.resize(size_t(o.frames));
    const double perTime = double(o.frames) / (time.end - time.begin);
    for (const cf::FinishedShape& s : once.shapes) {
      const cf::TimeSpan& t = once.times[size_t(s.order - 1)];
      const double b = (t.begin - time.begin) * perTime, e = (t.end - time.begin) * perTime;
      int first = b < o.frames ? int(std::floor(b)) : o.frames - 1, last = e < o.frames ? int(std::floor(e)) : o.frames - 1;
      first = std::max(first, 0), last = std::max(last, 0);
      for (int k = first; k <= last; ++k) zoom[size_t(k)].merge(once.boxes[size_t(s.order - 1)]);
    }
    const double alpha = std::pow(0.5, 1.0 / 10.0), beta = 1.0 - alpha;
    for (size_t k = zoom.size() - 1; k-- > 0;) {
      const cf::Bounds now = zoom[k], next = zoom[k + 1];
      zoom[k] = now.valid() && next.valid() ? cf::Bounds{beta * now.minX + alpha * next.minX, beta * now.minY + alpha * next.minY,
                                                          beta * now.maxX + alpha * next.maxX, beta * now.maxY + alpha * next.maxY}
                                            : cf::Bounds{};
    }
  }
  double windowEnd = time.begin;
  int written = 0;
  size_t shapes = 0;
  for (int k = 1; k <= o.frames; ++k) {
    if (o.frame && k != o.frame) continue;
    const cf::TimeSpan window{windowEnd, time.begin + step * k};
    windowEnd = window.end;
    ++written;
    cf::Expansion frameRun;
    const cf::Expansion* e = &once;
    cf::Framing f = onceFraming;
    if (perFrame) {
      eo.frameTime = (window.begin + window.end) * 0.5;
      eo.frame = (k - 1.0) / (o.frames - 1.0);
      eo.window = window;
      frameRun = cf::expand(*d.table, eo, statics);
      if (runError(frameRun, o)) return 1;
      if (!timing.hasTime) time = frameRun.timeBounds;
      e = &frameRun;
      f = cf::frame(frameRun, eo);
      shapes += frameRun.shapes.size();
    } else {
      if (!zoom.empty() && zoom[size_t(k - 1)].valid()) onceFraming = cf::frame(once, eo, &zoom[size_t(k - 1)]);
      f = onceFraming;
      f.times = &once.times;
      f.window = window;
      shapes = once.shapes.size();
    }
    for (size_t i = 0; i < o.outs.size(); ++i) {
      if (!sequences[i]) {
        if (writePictures(d, o, *e, f, eo, {outputName(o.outs[i], written, o.frames, variation)})) return 1;
        continue;
      }
      FrameSource source;
      source.writeFile = [&](const std::string& path) -> llvm::Error {
        if (writePictures(d, o, *e, f, eo, {path})) return llvm::createStringError("lcjit: " + path + ": not written");
        return llvm::Error::success();
      };
      source.picture = [&]() -> llvm::Expected<runtime::Image> {
        return cf::imageOf(cf::drawExpansion(*d.table, *e, f, eo));
      };
      if (auto err = sequences[i]->add(written, source)) return failed(std::move(err));
    }
  }
  for (auto& sequence : sequences)
    if (sequence)
      if (auto err = sequence->finish()) return failed(std::move(err));
  if (!o.quiet)
    std::fprintf(stderr, "lcjit: %s: variation %s, %d frame%s, %zu shapes%s\n", o.design.c_str(),
                 cf::variationName(variation).c_str(), written, written == 1 ? "" : "s", shapes,
                 perFrame ? " in all" : "");
  return 0;
}

// --profile: the counted expansion's rules as a table on stdout ("-"), or as JSON in a file. 0, or 1
// after printing why.
int writeProfile(const LoadedDesign& d, const DesignRunOptions& o, const cf::Expansion& e, uint64_t variation,
                 double expandMs) {
  if (o.profile.empty()) return 0;
  if (o.profile == "-") {
    std::fputs(designProfileTable(*d.table, e).c_str(), stdout);
    std::fflush(stdout);
    return 0;
  }
  if (auto err = support::writeWholeFile(o.profile, designProfileJson(*d.table, e, o.design, variation, expandMs))) {
    llvm::consumeError(std::move(err));
    std::fprintf(stderr, "%s: error: cannot write the profile\n", o.profile.c_str());
    return 1;
  }
  return 0;
}

// Expands a loaded design and writes the pictures. 0, or 1 after printing why.
int drawDesign(const LoadedDesign& d, const DesignRunOptions& o, uint64_t variation) {
  const auto start = support::Clock::now();
  const std::vector<std::string> imports(d.files.begin() + 1, d.files.end());
  cf::ExpandOptions eo = expandOptions(d, o, variation);
  const std::vector<double> statics = staticsOf(d, variation);
  // CF::Time must be a time that passes.
  const cf::DesignTiming timing = cf::timingOf(*d.table);
  if (timing.hasTime && !(timing.time.end > timing.time.begin && std::isfinite(timing.time.begin) &&
                          std::isfinite(timing.time.end) && std::isfinite(timing.timeScale))) {
    const std::string why = timing.timeAt + ": error: Illegal CF::Time specification";
    std::fprintf(stderr, "%s\n", why.c_str());
    writeRecord(o, imports, variation, nullptr, why);
    return 1;
  }
  if (o.frames > 0) {
    if (!o.profile.empty()) std::fprintf(stderr, "lcjit: --profile counts a single picture's expansion, not an animation's\n");
    const int status = animateDesign(d, o, eo, timing, statics, variation);
    writeRecord(o, imports, variation, nullptr, status ? "the animation was not written" : "");
    return status;
  }


  cf::Expansion e = cf::expand(*d.table, eo, statics);
  const double expandMs = support::msSince(start);
  if (runError(e, o)) {
    writeRecord(o, imports, variation, &e, errorOf(e, o));
    return 1;
  }
  if (!e.stopped.empty())
    std::fprintf(stderr, "lcjit: %s: stopped: %s; drawing the %zu shapes made so far\n", o.design.c_str(),
                 e.stopped.c_str(), e.shapes.size());
  if (writeProfile(d, o, e, variation, expandMs)) {
    writeRecord(o, imports, variation, &e, "the profile was not written");
    return 1;
  }
  cf::Framing f = cf::frame(e, eo);
  std::vector<std::string> names;
  for (const std::string& out : o.outs) names.push_back(outputName(out, 0, 0, variation));
  if (writePictures(d, o, e, f, eo, names)) {
    writeRecord(o, imports, variation, &e, "the pictures were not written");
    return 1;
  }
  if (!o.quiet)
    std::fprintf(stderr, "lcjit: %s: variation %s, %zu shapes\n", o.design.c_str(), cf::variationName(eo.variation).c_str(),
                 e.shapes.size());
  // A limit of memory or an interrupt cut the design short: its picture is written, and the run
  // fails; the shape limit is an end the user chose (as in Context Free).
  const int status = !e.stopped.empty() && !e.shapeLimit ? 1 : 0;
  writeRecord(o, imports, variation, &e, status ? "stopped: " + e.stopped : "");
  if (o.timing)
    std::fprintf(stderr,
                 "lcjit: parse and translate %.1f ms, compile %.1f ms (%s), expand %.1f ms (%llu rules run), "
                 "draw and write %.1f ms\n",
                 d.parseMs, d.compileMs, d.fromCache ? "from the cache" : "compiled", expandMs,
                 static_cast<unsigned long long>(e.expanded), support::msSince(start) - expandMs);
  return status;
}

}  // namespace

int runDesign(const DesignRunOptions& given) {
  DesignRunOptions o = given;
  runtime::interruptModelCodeOnSigint();  // Ctrl-C stops the expansion, and the shapes made are drawn
  // cfdg's checks of an animation's options, with its words.
  const char* wrong = o.frames && o.crop                ? "Animation cannot output cropped files."
                      : !o.frames && o.frame            ? "Animation frame can only be rendered when animating."
                      : !o.frames && o.zoom             ? "Zoomed output is only available when animating."
                      : o.frames && o.frame < 0         ? "Animation frame must be a positive integer."
                      : o.frames && o.frame > o.frames  ? "Animation frame is after the end of the animation."
                      : !o.output.empty() && !o.outs.empty() ? "Two output files specified."
                                                              : nullptr;
  for (const std::string& out : o.outs)
    if (o.frames && !endsWith(out, ".png") && (o.cfdgNames || !isFrameSequence(out)))
      wrong = o.cfdgNames ? "Animation cannot output to SVG files: an animation is written as PNG frames."
                          : "--frames writes PNG files, numbered files (frame%03d.svg) or a video (movie.mp4)";
  if (!o.output.empty() && o.frames && !endsWith(o.output, ".png"))
    wrong = "Animation cannot output to SVG files: an animation is written as PNG frames.";
  if (wrong) {
    std::fprintf(stderr, "lcjit: %s\n", wrong);
    return 1;
  }
  if (!o.output.empty()) {
    // cfdg's output file: its name as it is; in an animation (not one frame) the frame's number
    // goes before the extension.
    std::string form;
    for (char c : o.output) form.append(c == '%' ? 2 : 1, c);
    if (o.frames && !o.frame) {
      const size_t dot = form.find_last_of('.'), slash = form.find_last_of('/');
      if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) form.insert(dot, "_%f");
      else form += "_%f";
    }
    o.outs.push_back(form);
  }
  if (o.outs.empty()) {  // as lcjit does for a model without a display: the picture beside it
    std::string beside;
    for (char c : (std::filesystem::path(o.design).parent_path() / std::filesystem::path(o.design).stem()).string())
      beside.append(c == '%' ? 2 : 1, c);
    o.outs = {beside + (o.frames && !o.frame ? "_%f.png" : ".png")};
    if (!o.quiet) std::fprintf(stderr, "lcjit: writing %s\n", o.outs[0].c_str());
  }
  if (o.seed && !o.variation.empty()) {
    std::fprintf(stderr, "lcjit: give --variation or --seed, not both (--seed N is variation N)\n");
    return 1;
  }
  if (o.seed && *o.seed == 0) {
    std::fprintf(stderr, "lcjit: --seed 0: a design's variations are numbered from 1\n");
    return 1;
  }
  const uint64_t variation = o.seed ? *o.seed : chooseVariation(o.variation);
  if (variation == 0) {
    std::fprintf(stderr, "lcjit: '%s' is not a variation (letters, or a number)\n", o.variation.c_str());
    return 1;
  }
  if (o.emitCpp) {
    auto text = support::readInputFile(o.design, /*nullTerminated=*/false);
    if (!text) return failed(llvm::createStringError("lcjit: " + o.design + ": " + text.getError().message()));
    auto unit = designFrontEnd(o.design)((*text)->getBuffer(), o.design, o.defines);
    if (!unit) return failed(unit.takeError());
    std::fputs(unit->translation.cpp.c_str(), stdout);
    return 0;
  }

  auto compiler = designCompiler(o.cacheDir);
  if (!compiler) return failed(compiler.takeError());

  auto loaded = loadDesign(**compiler, o);
  int status = 1;
  std::vector<std::string> watched = {o.design};
  if (loaded) {
    if (o.loaded) o.loaded(loaded->files);
    status = drawDesign(*loaded, o, variation);
    watched = loaded->files;
  } else {
    const std::string why = llvm::toString(loaded.takeError());
    std::fprintf(stderr, "%s\n", why.c_str());
    writeRecord(o, {}, variation, nullptr, why);
  }
  if (!o.watch) return status;

  // --watch: a saved edit of the design (or of a file it imports) draws again; a broken one is
  // reported and the last good pictures stay.
  FileMonitor monitor;
  if (!monitor.watch(watched)) std::fprintf(stderr, "lcjit: file monitoring: %s\n", monitor.error().c_str());
  if (!o.quiet) std::fprintf(stderr, "lcjit: watching %s\n", o.design.c_str());
  for (int reload = 1;; ++reload) {
    std::vector<std::string> changed = monitor.poll(-1);
    if (changed.empty()) {
      --reload;
      continue;
    }
    auto next = loadDesign(**compiler, o);
    if (!next) {
      std::fprintf(stderr, "%s\n", llvm::toString(next.takeError()).c_str());
      std::fprintf(stderr, "lcjit: reload %d failed; the last good picture stays\n", reload);
      continue;
    }
    if (drawDesign(*next, o, variation) != 0) {
      std::fprintf(stderr, "lcjit: reload %d failed; the last good picture stays\n", reload);
      continue;
    }
    std::fprintf(stderr, "lcjit: reload %d: drawn again\n", reload);
    if (next->files != watched) {
      watched = next->files;
      monitor.watch(watched);
    }
  }
}

}  // namespace lcjit::app
