// A Context Free design in the window (DesignWindow.h).
#include "app/cfdg/DesignWindow.h"

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <optional>

#include "app/cfdg/DesignProfile.h"
#include "app/common/Background.h"
#include "app/window/Interactive.h"
#include "app/window/ModelHost.h"
#include "app/window/ProfilePanel.h"
#include "app/window/WindowController.h"
#include "jit/Compiler.h"
#include "runtime/ModelGuard.h"
#include "runtime/cfdg/DesignGeometry.h"
#include "runtime/export/Export.h"
#include "support/ReplacingFile.h"
#include "viewer/Window.h"

namespace lcjit::app {
namespace {

namespace cf = runtime::cfdg;

// A design compiled on the compile thread: the design, or why it failed.
struct Compiled {
  std::optional<LoadedDesign> design;
  std::string error;
};

// An expansion as the window shows it, made on the worker.
struct Drawn {
  std::shared_ptr<const LoadedDesign> design;  // what was expanded (its code draws its paths)
  std::shared_ptr<const DesignExpansion> expansion;
  cf::Framing framing;
  runtime::Geometry geometry;
  std::string error;  // file:line:col: error: … (the run's error; nothing to show)
};

class DesignHost final : public ModelHost {
 public:
  DesignHost(jit::Compiler& compiler, Compiled first, const DesignRunOptions& o, uint64_t variation,
             viewer::Window& window, const InteractiveOptions& io)
      : compiler_(compiler), options_(o), variation_(variation), window_(window), quiet_(io.quiet) {
    install(std::move(first));
  }
  ~DesignHost() override {
    if (work_.valid()) work_.wait();
  }

  // ---- runs: a design has no steps; every run is the whole expansion.

  void derive(RunTarget) override {
    if (busy() || !design_) return;
    // The worker has its own reference to the design it expands; it counts while the Profile
    // panel is open.
    DesignRunOptions o = options_;
    o.profile = window_.panelOpen(kProfilePanelTitle) ? "-" : "";
    work_ = std::async(std::launch::async, [this, design = design_, variation = variation_, o = std::move(o)] {
      Drawn d;
      d.design = design;
      auto x = std::make_shared<DesignExpansion>(expandDesign(*design, o, variation));
      const cf::Expansion& e = x->expansion;
      if (!e.error.empty()) {
        d.error = (e.errorAt.empty() ? options_.design : e.errorAt) + ": error: " + e.error;
        return d;
      }
      d.framing = cf::frame(e, x->options);
      d.geometry = cf::geometryOf(e, d.framing, x->options);
      d.expansion = std::move(x);
      return d;
    });
  }
  void redraw() override {
    if (shown_) news_.run = end();
  }
  bool busy() const override { return work_.valid(); }
  bool itemsWaitWhileBusy() const override { return true; }
  // Esc and Stop: the expansion stops where it is (the design's only guarded run in the process);
  // its shapes so far are shown.
  void stop() override { interrupt(); }
  void interrupt() override {
    if (busy()) runtime::interruptEveryRun();
  }

  HostNews poll(int waitMs) override {
    if (std::optional<Compiled> c = compile_.take()) waiting_ = std::move(*c);
    if (work_.valid() && work_.wait_for(std::chrono::milliseconds(waitMs)) == std::future_status::ready)
      show(work_.get());
    if (waiting_ && !busy()) {
      // A recompile replaces the design once the run in progress has been shown, and runs.
      const bool loaded = install(std::move(*waiting_));
      waiting_.reset();
      if (loaded) news_.rerun = true;
    }
    return std::exchange(news_, HostNews{});
  }

  // ---- files

  void apply(Action a) override {
    switch (a) {
      case Action::NewModel:
      case Action::NewLsystem:
        news_.resetView = news_.resetView || a == Action::NewModel;
        compile_.start([this, o = withMoved()] { return compile(compiler_, o); });
        break;
      case Action::NewRun: news_.rerun = true; break;
      case Action::NewView:
        news_.resetView = true;
        news_.redraw = true;
        break;
      case Action::NewRendering: news_.redraw = true; break;
      case Action::NewAnimate:
      case Action::None: break;
    }
  }
  std::vector<std::string> watchedFiles() const override {
    return design_ ? design_->files : std::vector<std::string>{options_.design};
  }

  // ---- the window's input and menu

  void takeInput() override {}
  void addToMenu(viewer::MenuActions& a) override {
    a.newModel = [this] { apply(Action::NewModel); };
    a.newRun = [this] { apply(Action::NewRun); };
    a.newView = [this] { apply(Action::NewView); };
    a.newRendering = [this] { apply(Action::NewRendering); };
    a.nextVariation = [this] {
      ++variation_;
      news_.rerun = true;
    };
    a.interrupt = [this] { interrupt(); };
    if (design_ && !design_->variables.empty()) a.panels.push_back(parameters());
    a.panels.push_back(profilePanel());
    const std::filesystem::path design(options_.design);
    a.saveName = (design.parent_path() / design.stem()).string() + ".png";
    a.saveAs = [this](const std::string& path) { save(path); };
  }
  bool records() const override { return false; }

  // The Parameters panel: a slider for each constant number the design defines (`turn = 10`),
  // from 0 to twice its value as first read (-1 to 1 for 0). A move compiles the design again
  // with NAME=VALUE as -D gives it (the design's own definition gives way) and draws it anew.
  viewer::Panel parameters() {
    viewer::Panel p;
    p.title = "Parameters";
    for (const frontend::cfdg::DesignVariable& v : design_->variables) {
      const std::pair<double, double> first = v.value > 0   ? std::pair(0.0, 2 * v.value)
                                              : v.value < 0 ? std::pair(2 * v.value, 0.0)
                                                            : std::pair(-1.0, 1.0);
      const auto range = ranges_.try_emplace(v.name, first).first->second;
      viewer::PanelControl c;
      c.label = v.name;
      c.value = float(v.value);
      c.min = float(range.first), c.max = float(range.second);
      c.tooltip = v.line ? options_.design + ":" + std::to_string(v.line) : "-D " + v.name;
      p.controls.push_back(c);
    }
    p.changed = [this, names = p.controls](size_t control, float value) {
      char text[32];
      auto end = std::to_chars(text, text + sizeof text, value).ptr;
      moved_[names[control].label] = std::string(text, end);
      compile_.start([this, o = withMoved()] { return compile(compiler_, o); });
    };
    return p;
  }
  // The Profile panel: the rules by time, from the last run shown, as the L-system's panel shows
  // them (Interactive.cpp); counting is on while the panel is open: opening it counts from the
  // next run (Run again).
  viewer::Panel profilePanel() {
    const bool open = window_.panelOpen(kProfilePanelTitle);
    if (open != profiling_) profileRows_.clear(), profileFinished_.clear();
    profiling_ = open;
    return app::profilePanel(profileRows_, ProfiledRules::Design, profileFinished_, [this] {
      if (!busy()) news_.rerun = true;
    });
  }

  // The options a compile takes: the command line's, with the values moved in the panel.
  DesignRunOptions withMoved() const {
    DesignRunOptions o = options_;
    std::erase_if(o.defines, [this](const std::string& d) { return moved_.count(d.substr(0, d.find('='))) != 0; });
    for (const auto& [name, shown] : moved_) o.defines.push_back(name + "=" + shown);
    return o;
  }

  static Compiled compile(jit::Compiler& compiler, const DesignRunOptions& o) {
    Compiled c;
    auto d = loadDesign(compiler, o);
    if (d) c.design = std::move(*d);
    else c.error = llvm::toString(d.takeError());
    return c;
  }

 private:
  // A compile's result becomes the design the runs use; a failed one leaves the last good design
  // (and its picture), with the error over it.
  bool install(Compiled c) {
    if (!c.design) {
      report(c.error);
      window_.setMessage(c.error + "\n(the last good design is shown; save a fix to reload)");
      return false;
    }
    design_ = std::make_shared<const LoadedDesign>(std::move(*c.design));
    window_.setMessage("");
    return true;
  }

  void show(Drawn d) {
    if (!d.error.empty()) {
      report(d.error);
      window_.setMessage(d.error);
      RunEnd failed;
      failed.failed = true;
      news_.run = failed;
      return;
    }
    const cf::Expansion& e = d.expansion->expansion;
    if (!e.stopped.empty())
      report("lcjit: " + options_.design + ": stopped: " + e.stopped + "; showing the " +
             std::to_string(e.shapes.size()) + " shapes made so far");
    double rgba[4];
    cf::rgbOf(e.background, rgba);
    palette_.color[0] = {float(rgba[0]), float(rgba[1]), float(rgba[2]), 1.f};
    geometry_ = std::move(d.geometry);
    shown_ = std::move(d.expansion);
    shownDesign_ = std::move(d.design);
    framing_ = d.framing;
    if (!e.ruleRuns.empty()) {
      profileRows_ = designProfileRows(*shownDesign_->table, e);
      profileFinished_ = finishedText(finishedByKind(*shownDesign_->table, e));
    }
    window_.setStatus("variation " + cf::variationName(variation_) + ": " + std::to_string(e.shapes.size()) + " shapes");
    news_.run = end();
  }

  RunEnd end() {
    RunEnd r;
    r.picture = HostPicture{&geometry_, &panes_, &view_, &palette_, &textures_};
    r.step = r.derivationLength = 1;
    r.ended = true;
    return r;
  }

  // Save as… a name that is not an image's (the window writes those): the picture shown, as
  // Context Free's SVG or one of lcjit's exports.
  void save(const std::string& path) {
    if (!shown_) return report("lcjit: " + path + ": no picture to save yet");
    llvm::Error e = llvm::Error::success();
    if (path.size() > 4 && path.substr(path.size() - 4) == ".svg") {
      e = support::writeWholeFile(path, cf::svgOf(shown_->expansion, framing_, shown_->options));
    } else if (auto page = pageFormatFor(path)) {
      e = support::writeWholeFile(path, cf::vectorPage(*shownDesign_->table, shown_->expansion, framing_, shown_->options, *page));
    } else if (auto format = runtime::exportFormatFor(path)) {
      runtime::ExportInput in;
      in.geometry = &geometry_;
      in.width = framing_.width;
      in.height = framing_.height;
      e = runtime::exportGeometry(path, *format, in);
    } else {
      e = llvm::createStringError("lcjit: " + path + ": not a picture or export lcjit writes");
    }
    if (e) report(llvm::toString(std::move(e)));
  }

  void report(const std::string& message) const {
    if (!quiet_ || message.find("error") != std::string::npos) std::fprintf(stderr, "%s\n", message.c_str());
  }

  jit::Compiler& compiler_;
  DesignRunOptions options_;
  uint64_t variation_;
  viewer::Window& window_;
  bool quiet_;
  std::shared_ptr<const LoadedDesign> design_;  // the last good design
  // The Parameters panel: each variable's slider range (from its first value) and the values
  // moved there (what -D NAME=VALUE the next compiles add).
  std::map<std::string, std::pair<double, double>> ranges_;
  std::map<std::string, std::string> moved_;
  // The Profile panel: whether it was open (counting), and what the last counted run shown says.
  bool profiling_ = false;
  std::vector<ProfileRow> profileRows_;
  std::string profileFinished_;
  std::optional<Compiled> waiting_;     // a recompile waiting for the worker to finish
  std::future<Drawn> work_;
  // What the window shows: its geometry, the expansion it came from (for Save as…), and the
  // plain view and palette of a flat picture (colour 0: CF::Background).
  std::shared_ptr<const DesignExpansion> shown_;
  std::shared_ptr<const LoadedDesign> shownDesign_;  // its design, kept while it is shown
  cf::Framing framing_;
  runtime::Geometry geometry_;
  const std::vector<viewer::ViewPane> panes_;
  const runtime::ViewSettings view_;
  viewer::RenderPalette palette_;
  const std::vector<runtime::Image> textures_;
  HostNews news_;
  Background<Compiled> compile_;  // declared last: destroyed first, it waits for its job
};

}  // namespace

int runDesignWindow(const DesignRunOptions& o, const viewer::WindowOptions& window, const InteractiveOptions& io) {
  runtime::interruptModelCodeOnSigint();
  const uint64_t variation = chooseVariation(o.variation);
  if (variation == 0) {
    std::fprintf(stderr, "lcjit: '%s' is not a variation (letters, or a number)\n", o.variation.c_str());
    return 1;
  }
  auto compiler = designCompiler(o.cacheDir);
  if (!compiler) {
    std::fprintf(stderr, "%s\n", llvm::toString(compiler.takeError()).c_str());
    return 1;
  }
  Compiled first = DesignHost::compile(**compiler, o);
  if (!first.design && io.refresh == RefreshMode::Explicit) {  // nothing to show, no fix awaited
    std::fprintf(stderr, "%s\n", first.error.c_str());
    return 1;
  }
  viewer::WindowOptions flat = window;
  flat.flat = true;
  return runWindow(flat, io, o.design, [&](viewer::Window& w) -> std::unique_ptr<ModelHost> {
    return std::make_unique<DesignHost>(**compiler, std::move(first), o, variation, w, io);
  });
}

}  // namespace lcjit::app
