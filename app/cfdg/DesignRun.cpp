// A Context Free design run from the command line (DesignRun.h).
#include "app/cfdg/DesignRun.h"

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <cctype>
#include <random>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/cli/Modes.h"
#include "app/cli/Options.h"
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
  d.seed = options.seed;
  d.runRecord = options.runRecord;
  d.cacheDir = cacheDir;
  return d;
}

void declareCfdgOptions(CLI::App& c, DesignRunOptions& o) {
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
  c.add_option("-o", o.outs, "output file: %v and %V are the variation (lower, upper case), %% a percent sign");
  c.add_option("-D", o.defines, "NAME=VALUE: a definition read before the design's (its own NAME is dropped)")
      ->allow_extra_args(false);
  c.add_flag("-q", o.quiet, "quiet");
  c.add_flag("-c", o.crop, "crop the picture to the fitted block (not for tiled or frieze designs)");
  c.add_flag("-t", o.timing, "where the time went: parse, compile, expand, draw");
  c.add_option("design", o.design, "the design (.cfdg)")->required();
  c.add_option("output", o.outs, "output file");
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

DesignExpansion expandDesign(const LoadedDesign& d, const DesignRunOptions& o, uint64_t variation) {
  DesignExpansion x;
  cf::ExpandOptions& eo = x.options;
  eo.width = o.width;
  eo.height = o.height;
  eo.minimumSize = d.unit.settings.minimumSize > 0 ? d.unit.settings.minimumSize : o.minimumSize;
  eo.border = o.border;
  // -m wins over CF::MaxShapes, which counts when above 1 (as in cfdg).
  if (o.maxShapes > 0) eo.maxShapes = o.maxShapes;
  else if (d.unit.settings.maxShapes > 1) eo.maxShapes = uint64_t(d.unit.settings.maxShapes);
  eo.maxMemory = o.maxMemory;
  eo.variation = variation;
  // rand_static(): drawn once, before the run, from the variation.
  std::vector<double> statics;
  uint64_t s = eo.variation;
  for (int k = 0; k < d.unit.randStaticCount; ++k) statics.push_back(cf::drawDouble(s));
  x.expansion = cf::expand(*d.table, eo, statics);
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

// Expands a loaded design and writes the pictures. 0, or 1 after printing why.
int drawDesign(const LoadedDesign& d, const DesignRunOptions& o, uint64_t variation) {
  const auto start = support::Clock::now();
  DesignExpansion x = expandDesign(d, o, variation);
  const cf::ExpandOptions& eo = x.options;
  const cf::Expansion& e = x.expansion;
  const double expandMs = support::msSince(start);
  const std::vector<std::string> imports(d.files.begin() + 1, d.files.end());
  auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "%s\n", why.c_str());
    writeRecord(o, imports, variation, &e, why);
    return 1;
  };
  if (!e.error.empty()) return fail((e.errorAt.empty() ? o.design : e.errorAt) + ": error: " + e.error);
  if (!e.stopped.empty())
    std::fprintf(stderr, "lcjit: %s: stopped: %s; drawing the %zu shapes made so far\n", o.design.c_str(),
                 e.stopped.c_str(), e.shapes.size());
  cf::Framing f = cf::frame(e, eo);
  // -c: the fitted block alone, as cfdg crops: the SVG is the block's size, the PNG the block's
  // rows counted from the picture's top by the block's offset from its bottom (as cfdg reads them).
  const bool crop = o.crop && !e.picture.tiled && !e.picture.frieze;
  cf::Framing cropped = f;
  cropped.width = f.fit.width, cropped.height = f.fit.height;
  const cf::PixelRect block{int(f.offsetX), f.height - f.fit.height - int(f.offsetY), f.fit.width, f.fit.height};
  for (const std::string& out : o.outs) {
    if (out.size() > 4 && out.substr(out.size() - 4) == ".svg") {
      if (auto err = support::writeWholeFile(out, cf::svgOf(e, crop ? cropped : f, eo))) return fail(llvm::toString(std::move(err)));
    } else if (out.size() > 4 && out.substr(out.size() - 4) == ".png") {
      cf::Canvas canvas = cf::drawExpansion(*d.table, e, f, eo);
      if (auto err = cf::writePng(canvas, out, crop ? std::optional<cf::PixelRect>(block) : std::nullopt))
        return fail(llvm::toString(std::move(err)));
    } else if (auto format = runtime::exportFormatFor(out)) {
      // The other formats lcjit exports: the shapes as flat coloured triangles.
      runtime::Geometry geometry = cf::geometryOf(e, f, eo);
      runtime::ExportInput in;
      in.geometry = &geometry;
      in.width = f.width;
      in.height = f.height;
      if (auto err = runtime::exportGeometry(out, *format, in)) return fail(llvm::toString(std::move(err)));
    } else {
      return fail("lcjit: " + out + ": not a picture or export lcjit writes");
    }
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
  if (o.outs.empty()) {  // as lcjit does for a model without a display: the picture beside it
    o.outs = {(std::filesystem::path(o.design).parent_path() / std::filesystem::path(o.design).stem()).string() + ".png"};
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
  // Output names as cfdg's -o takes them: %v / %V the variation in lower / upper case.
  for (std::string& out : o.outs) {
    std::string named;
    for (size_t i = 0; i < out.size(); ++i) {
      if (out[i] != '%' || i + 1 == out.size()) {
        named += out[i];
        continue;
      }
      char c = out[++i];
      std::string v = cf::variationName(variation);
      if (c == 'V') named += v;
      else if (c == 'v') for (char ch : v) named += char(std::tolower(static_cast<unsigned char>(ch)));
      else if (c == '%') named += '%';
      else named += std::string("%") + c;
    }
    out = named;
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
