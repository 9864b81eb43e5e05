// A Context Free design run from the command line (DesignRun.h).
#include "app/cfdg/DesignRun.h"

#include <chrono>
#include <cstdio>
#include <random>

#include <CLI/CLI.hpp>

#include "app/cli/Modes.h"
#include "app/cli/Options.h"
#include "app/session/Session.h"  // runtimeIncludeDir, prebuiltDir
#include "frontend/cfdg/Parser.h"
#include "frontend/cfdg/Translate.h"
#include "jit/Compiler.h"
#include "runtime/cfdg/Expander.h"
#include "runtime/cfdg/Picture.h"
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
  c.add_option("-o", o.outs, "output file");
  c.add_flag("-q", o.quiet, "quiet");
  c.add_option("design", o.design, "the design (.cfdg)")->required();
  c.add_option("output", o.outs, "output file");
}

int runDesign(const DesignRunOptions& o) {
  namespace cf = runtime::cfdg;
  auto text = support::readInputFile(o.design, /*nullTerminated=*/false);
  if (!text) {
    std::fprintf(stderr, "lcjit: %s: %s\n", o.design.c_str(), text.getError().message().c_str());
    return 1;
  }
  auto design = frontend::cfdg::parseDesign((*text)->getBuffer(), o.design);
  if (!design) return failed(design.takeError());
  auto unit = frontend::cfdg::translateDesign(*design);
  if (!unit) return failed(unit.takeError());
  if (o.emitCpp) {
    std::fputs(unit->cpp.c_str(), stdout);
    return 0;
  }

  jit::CompilerConfig config;
  config.runtimeHeader = runtimeIncludeDir() + "/lpfgall.h";
  config.cacheDir = o.cacheDir;
  config.prebuiltDir = prebuiltDir();
  for (auto& [name, address] : cf::hostSymbols()) config.hostSymbols.push_back({name, address});
  auto compiler = jit::Compiler::create(std::move(config));
  if (!compiler) return failed(compiler.takeError());
  jit::CompileOptions co;
  co.optLevel = o.optLevel;
  co.plainUnit = true;
  co.bufferName = o.design + ".cpp";
  auto code = (*compiler)->compile(unit->cpp, co);
  if (!code) return failed(code.takeError());
  auto table = (*code)->lookup("__cf_design");
  if (!table) return failed(table.takeError());
  const auto& compiled = *static_cast<const __cf_Design*>(*table);

  cf::ExpandOptions eo;
  eo.width = o.width;
  eo.height = o.height;
  eo.minimumSize = unit->settings.minimumSize > 0 ? unit->settings.minimumSize : o.minimumSize;
  eo.border = o.border;
  eo.borderFixed = unit->settings.borderFixed;
  eo.borderDynamic = unit->settings.borderDynamic;
  eo.maxShapes = o.maxShapes;
  if (o.variation.empty()) {
    std::random_device device;
    eo.variation = std::uniform_int_distribution<uint64_t>(1, 321272406)(device);
  } else {
    eo.variation = cf::variationOf(o.variation);
    if (eo.variation == 0) {
      std::fprintf(stderr, "lcjit: '%s' is not a variation (letters, or a number)\n", o.variation.c_str());
      return 1;
    }
  }
  // rand_static(): drawn once, before the run, from the variation.
  std::vector<double> statics;
  uint64_t s = eo.variation;
  for (int k = 0; k < unit->randStaticCount; ++k) statics.push_back(cf::drawDouble(s));

  cf::Expansion e = cf::expand(compiled, eo, statics);
  if (!e.error.empty()) {
    std::fprintf(stderr, "%s: error: %s\n", o.design.c_str(), e.error.c_str());
    return 1;
  }
  cf::Framing f = cf::frame(e, eo);
  for (const std::string& out : o.outs) {
    if (out.size() > 4 && out.substr(out.size() - 4) == ".svg") {
      if (auto err = support::writeWholeFile(out, cf::svgOf(e, f, eo))) return failed(std::move(err));
    } else if (out.size() > 4 && out.substr(out.size() - 4) == ".png") {
      cf::Canvas canvas = cf::drawExpansion(compiled, e, f, eo);
      if (auto err = cf::writePng(canvas, out)) return failed(std::move(err));
    } else {
      std::fprintf(stderr, "lcjit: %s: Context Free designs are written as .png or .svg\n", out.c_str());
      return 1;
    }
  }
  if (!o.quiet)
    std::fprintf(stderr, "lcjit: %s: variation %s, %zu shapes\n", o.design.c_str(),
                 cf::variationName(eo.variation).c_str(), e.shapes.size());
  return 0;
}

}  // namespace lcjit::app
