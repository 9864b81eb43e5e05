// The window's editors of vlab's files (Editors.h).
#include "app/window/Editors.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <llvm/Support/Process.h>

#include "runtime/Functions.h"
#include "runtime/files/Contours.h"
#include "support/ReplacingFile.h"

namespace lcjit::app {
namespace fs = std::filesystem;

struct Editors::CurveDoc {
  std::string path;
  runtime::CurveFile file;
  std::string error;   // the file could not be read: the panel says why
  std::string status;  // what the last edit or Save did
  std::vector<std::vector<std::array<float, 2>>> drawn;  // each curve as the model sees it
  fs::file_time_type stamp;  // the file's when read

  void read() {
    drawn.clear();
    error.clear();
    std::error_code ec;
    stamp = fs::last_write_time(path, ec);
    auto f = runtime::readCurveFile(path);
    if (!f) {
      error = llvm::toString(f.takeError());
      return;
    }
    file = std::move(*f);
    for (size_t k = 0; k < file.curves.size(); ++k) drawn.push_back(sample(k));
  }

  // The curve through the points, by the model's own readers: a function at 101 x's, a contour at
  // 200 points along it.
  std::vector<std::array<float, 2>> sample(size_t k) const {
    std::vector<std::array<float, 2>> out;
    const std::string text = runtime::curveText(file.curves[k]);
    if (file.kind == runtime::CurveFile::Kind::Function) {
      runtime::FunctionStore store;
      if (auto e = store.loadFunctionText(text, path)) {
        llvm::consumeError(std::move(e));
        return out;
      }
      for (int i = 0; i <= 100; ++i) out.push_back({i / 100.0f, store.func(1, i / 100.0f)});
    } else {
      auto c = runtime::Contour::parse(text, path);
      if (!c) {
        llvm::consumeError(c.takeError());
        return out;
      }
      for (const V3f& p : c->sampled(200).points) out.push_back({p.x, p.y});
    }
    return out;
  }
};

struct Editors::ColourDoc {
  std::string path;       // the colour file; a model without one: the .map Save would create
  bool fresh = false;     // no colour file: the colours the model is drawn with
  bool materials = false;
  runtime::ColormapFile map;
  runtime::MaterialFile mat;
  int selected = 1;
  std::string error, status;
  fs::file_time_type stamp;

  void read(const runtime::Palette& start) {
    error.clear();
    std::error_code ec;
    stamp = fs::last_write_time(path, ec);
    if (fresh) {
      map = runtime::ColormapFile::fromPalette(start);
    } else if (materials) {
      auto f = runtime::MaterialFile::read(path);
      if (f) mat = std::move(*f);
      else error = llvm::toString(f.takeError());
    } else {
      auto f = runtime::ColormapFile::read(path);
      if (f) map = std::move(*f);
      else error = llvm::toString(f.takeError());
    }
  }
  const std::vector<uint8_t>& bytes() const { return materials ? mat.bytes() : map.bytes(); }
};

namespace {

std::array<float, 4> rgba(const uint8_t* rgb) { return {rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f, 1.0f}; }
uint8_t toByte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

viewer::PanelControl text(std::string label) {
  viewer::PanelControl c;
  c.kind = viewer::PanelControl::Kind::Text;
  c.label = std::move(label);
  return c;
}

viewer::PanelControl color(std::string label, const uint8_t* rgb) {
  viewer::PanelControl c;
  c.kind = viewer::PanelControl::Kind::Color;
  c.label = std::move(label);
  c.colors = {rgba(rgb)};
  return c;
}

viewer::PanelControl slider(std::string label, float value, float max) {
  viewer::PanelControl c;
  c.label = std::move(label);
  c.value = value;
  c.max = max;
  c.step = 1;
  return c;
}

std::string saved(llvm::Error e, const std::string& path) {
  if (e) return llvm::toString(std::move(e));
  return "saved " + fs::path(path).filename().string();
}

}  // namespace

Editors::Editors(const ModelFiles& files, const runtime::Palette& start) {
  std::vector<std::string> functions;
  if (!files.functionSet.empty()) functions.push_back(files.functionSet);
  functions.insert(functions.end(), files.functions.begin(), files.functions.end());
  const std::vector<std::string>* lists[] = {&functions, &files.contours};
  for (const auto* list : lists)
    for (const std::string& path : *list) {
      auto doc = std::make_unique<CurveDoc>();
      doc->path = path;
      doc->read();
      curves_.push_back(std::move(doc));
    }
  colours_ = std::make_unique<ColourDoc>();
  // lpfg reads one colour file: the last one given, whichever kind (ModelFiles keeps both).
  if (!files.materials.empty()) {
    colours_->path = files.materials;
    colours_->materials = true;
  } else if (!files.colormap.empty()) {
    colours_->path = files.colormap;
  } else {
    fs::path l(files.lsystem);
    colours_->path = (l.parent_path() / (l.stem().string() + ".map")).string();
    colours_->fresh = true;
  }
  colours_->read(start);
}

Editors::~Editors() {
  std::error_code ec;
  if (!scratch_.empty()) fs::remove_all(scratch_, ec);
}

void Editors::edited(const std::string& path, std::string bytes, Action action, std::string& status) {
  std::error_code ec;
  if (scratch_.empty()) {
    fs::path dir = fs::temp_directory_path(ec) / ("lcjit-edits-" + std::to_string(llvm::sys::Process::getProcessId()));
    fs::create_directories(dir, ec);
    scratch_ = dir.string();
  }
  auto it = copies_.find(path);
  std::string copy;
  if (it != copies_.end()) {
    copy = it->second;
  } else {
    // A folder per file: two files of one name in different folders stay apart.
    fs::path dir = fs::path(scratch_) / std::to_string(copies_.size());
    fs::create_directories(dir, ec);
    copy = (dir / fs::path(path).filename()).string();
  }
  if (auto e = support::writeWholeFile(copy, bytes)) {
    status = llvm::toString(std::move(e));
    return;
  }
  copies_[path] = copy;
  status = "edited, not saved";
  // New run re-reads the colours too.
  if (pending_ != Action::NewRun) pending_ = action;
}

Action Editors::takeAction() { return std::exchange(pending_, Action::None); }

ModelFiles Editors::files(const ModelFiles& base) const {
  ModelFiles f = base;
  auto swap = [&](std::string& path) {
    if (auto it = copies_.find(path); it != copies_.end()) path = it->second;
  };
  for (std::string& p : f.functions) swap(p);
  swap(f.functionSet);
  for (std::string& p : f.contours) swap(p);
  swap(f.colormap);
  swap(f.materials);
  if (colours_->fresh && f.colormap.empty() && f.materials.empty())
    if (auto it = copies_.find(colours_->path); it != copies_.end()) f.colormap = it->second;
  return f;
}

// A file another program changed (a text editor, vlab's own tools) is read again, unless it has
// edits of ours not saved: those stay until Save or Revert.
bool Editors::changedOnDisk(const std::string& path, fs::file_time_type stamp) const {
  if (copies_.count(path)) return false;
  std::error_code ec;
  const fs::file_time_type now = fs::last_write_time(path, ec);
  return !ec && now != stamp;
}

std::vector<viewer::Panel> Editors::panels() {
  for (auto& doc : curves_)
    if (changedOnDisk(doc->path, doc->stamp)) doc->read();
  if (!colours_->fresh && changedOnDisk(colours_->path, colours_->stamp)) colours_->read(runtime::Palette::lcjitDefault());
  std::vector<viewer::Panel> out;
  for (auto& doc : curves_) addCurvePanels(*doc, out);
  addColourPanel(*colours_, out);
  return out;
}

void Editors::addCurvePanels(CurveDoc& doc, std::vector<viewer::Panel>& out) {
  const bool function = doc.file.kind == runtime::CurveFile::Kind::Function;
  const std::string file = fs::path(doc.path).filename().string();
  auto titled = [&](const std::string& name) {
    std::string title = (function ? "Function " : "Contour ") + name;
    for (const viewer::Panel& p : out)
      if (p.title == title) return title + " (" + file + ")";
    return title;
  };
  if (!doc.error.empty()) {
    viewer::Panel p;
    p.title = titled(file);
    p.controls.push_back(text(doc.error));
    out.push_back(std::move(p));
    return;
  }
  for (size_t k = 0; k < doc.file.curves.size(); ++k) {
    const runtime::Curve& c = doc.file.curves[k];
    viewer::Panel p;
    p.title = titled(c.name);
    p.controls.push_back(text(file + (doc.file.set ? ", item " + std::to_string(k + 1) : std::string())));
    viewer::PanelControl curve;
    curve.kind = viewer::PanelControl::Kind::Curve;
    curve.label = c.name;
    curve.function = function;
    curve.closed = c.closed;
    for (const runtime::CurvePoint& q : c.points) curve.points.push_back({float(q.x), float(q.y)});
    curve.curve = doc.drawn[k];
    p.controls.push_back(std::move(curve));
    p.controls.push_back(text("Ctrl+click: add; Shift+Ctrl+click: remove"));  // funcedit's keys
    p.buttons = {"Save", "Revert"};
    p.status = doc.status;
    CurveDoc* d = &doc;
    p.edited = [this, d, k](size_t, size_t point, std::array<float, 4> v) {
      runtime::movePoint(d->file.curves[k], point, v[0], v[1]);
      d->drawn[k] = d->sample(k);
      edited(d->path, runtime::curveFileText(d->file), Action::NewRun, d->status);
    };
    // A curve keeps the 4 points lpfg needs (functions and contours alike).
    p.added = [this, d, k](size_t, size_t at, std::array<float, 2> q) {
      runtime::insertPoint(d->file.curves[k], at, q[0], q[1]);
      d->drawn[k] = d->sample(k);
      edited(d->path, runtime::curveFileText(d->file), Action::NewRun, d->status);
    };
    p.removed = [this, d, k](size_t, size_t index) {
      if (d->file.curves[k].points.size() <= 4) {
        d->status = "a curve needs at least 4 points";
        return;
      }
      runtime::removePoint(d->file.curves[k], index);
      d->drawn[k] = d->sample(k);
      edited(d->path, runtime::curveFileText(d->file), Action::NewRun, d->status);
    };
    p.pressed = [this, d](size_t button) {
      if (button == 0) {
        d->status = saved(runtime::writeCurveFile(d->file, d->path), d->path);
      } else {
        d->read();
        d->status = d->error.empty() ? "read " + fs::path(d->path).filename().string() + " again" : d->error;
        pending_ = Action::NewRun;
      }
      copies_.erase(d->path);  // the file itself holds what is shown now
    };
    out.push_back(std::move(p));
  }
}

void Editors::addColourPanel(ColourDoc& doc, std::vector<viewer::Panel>& out) {
  viewer::Panel p;
  const std::string file = fs::path(doc.path).filename().string();
  p.title = doc.materials ? "Materials" : "Colormap";
  if (!doc.error.empty()) {
    p.controls.push_back(text(doc.error));
    out.push_back(std::move(p));
    return;
  }
  p.controls.push_back(text(doc.fresh ? "no colour file: the colours the model is drawn with (Save writes " + file + ")" : file));
  viewer::PanelControl grid;
  grid.kind = viewer::PanelControl::Kind::Swatches;
  grid.label = "colours";
  grid.value = float(doc.selected);
  for (int i = 0; i < 256; ++i) {
    if (doc.materials) {
      // A material shown by its diffuse colour, the background (0) by its emission, as lpfg draws them.
      runtime::MaterialRecord r = doc.mat.record(i);
      grid.colors.push_back(rgba(r.data() + (i == 0 ? 7 : 4)));
    } else {
      std::array<uint8_t, 3> c = doc.map.color(i);
      grid.colors.push_back(rgba(c.data()));
    }
  }
  p.controls.push_back(std::move(grid));
  const std::string n = std::to_string(doc.selected);
  ColourDoc* d = &doc;
  auto changed = [this, d] { edited(d->path, std::string(d->bytes().begin(), d->bytes().end()), Action::NewRendering, d->status); };
  if (doc.materials) {
    runtime::MaterialRecord r = doc.mat.record(doc.selected);
    p.controls.push_back(color("Ambient " + n, &r[1]));
    p.controls.push_back(color("Diffuse " + n, &r[4]));
    p.controls.push_back(color("Specular " + n, &r[10]));
    p.controls.push_back(color("Emission " + n, &r[7]));
    p.controls.push_back(slider("Shininess", r[13], 128));
    p.controls.push_back(slider("Transparency", r[0], 255));
    // Controls 2..5 are colours at these record offsets; 6 and 7 single bytes.
    p.edited = [d, changed](size_t control, size_t, std::array<float, 4> v) {
      static const int at[] = {1, 4, 10, 7};
      if (control < 2 || control > 5) return;
      runtime::MaterialRecord r = d->mat.record(d->selected);
      for (int k = 0; k < 3; ++k) r[at[control - 2] + k] = toByte(v[k]);
      d->mat.setRecord(d->selected, r);
      changed();
    };
    p.changed = [d, changed](size_t control, float v) {
      if (control == 1) {
        d->selected = std::clamp(int(v), 0, 255);
        return;
      }
      runtime::MaterialRecord r = d->mat.record(d->selected);
      r[control == 6 ? 13 : 0] = uint8_t(std::clamp(std::lround(v), 0L, 255L));
      d->mat.setRecord(d->selected, r);
      changed();
    };
  } else {
    std::array<uint8_t, 3> c = doc.map.color(doc.selected);
    p.controls.push_back(color("Colour " + n, c.data()));
    p.edited = [d, changed](size_t, size_t, std::array<float, 4> v) {
      d->map.setColor(d->selected, {toByte(v[0]), toByte(v[1]), toByte(v[2])});
      changed();
    };
    p.changed = [d](size_t control, float v) {
      if (control == 1) d->selected = std::clamp(int(v), 0, 255);
    };
  }
  p.buttons = {"Save", "Revert"};
  p.status = doc.status;
  p.pressed = [this, d](size_t button) {
    if (button == 0) {
      if (d->fresh && fs::exists(d->path)) {
        d->status = fs::path(d->path).filename().string() + " exists and is not the model's colour file: not overwritten";
        return;
      }
      llvm::Error e = d->materials ? d->mat.write(d->path) : d->map.write(d->path);
      d->status = saved(std::move(e), d->path);
      if (d->fresh && d->status.rfind("saved ", 0) == 0)
        d->status += "; give it to lcjit with the model to use it";
      // A new colormap is not the model's yet: its copy stays what the window draws with.
      if (!d->fresh) copies_.erase(d->path);
      return;
    }
    d->read(runtime::Palette::lcjitDefault());
    d->status = d->error.empty() ? "read again" : d->error;
    copies_.erase(d->path);
    if (pending_ == Action::None) pending_ = Action::NewRendering;
  };
  out.push_back(std::move(p));
}

}  // namespace lcjit::app
