// The window's editors of a model's vlab files (vlab's funcedit, cuspy, palette and medit in
// panels of the window): a panel for each function (.func, each function of the .fset), each
// contour (.con, each contour of a .cset), and the colormap (.map) or the materials (.mat) — a
// model without a colour file gets a colormap panel that starts from the colours it is drawn with.
//
// An edit changes the file's copy here at once and asks for what FileMonitor's table runs when
// such a file changes (functions and contours: New run; colours: New rendering); until it is
// saved, the reload reads the edited copy (files()), written to a folder of the editors' own under
// the file's own name, so that the model sees the names it would see. "Save" writes the file
// itself (vlab's format, byte for byte the file read where nothing changed), "Revert" reads it
// again. A file changed by another program is read again when it has no unsaved edits here.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/session/FileMonitor.h"
#include "app/session/Session.h"
#include "runtime/files/CurveFiles.h"
#include "runtime/files/Palette.h"
#include "viewer/Window.h"

namespace lcjit::app {

class Editors {
 public:
  // `files`: the model's; `start`: the colours a model without a colour file is drawn with (a new
  // colormap starts from them).
  Editors(const ModelFiles& files, const runtime::Palette& start);
  ~Editors();
  Editors(const Editors&) = delete;
  Editors& operator=(const Editors&) = delete;

  // The panels as they stand (their callbacks call back into this object; run them before it goes).
  std::vector<viewer::Panel> panels();
  // `base` with every edited, unsaved file replaced by its edited copy: what a reload reads.
  ModelFiles files(const ModelFiles& base) const;
  // What the edits since the last call ask for: NewRun, NewRendering, or None.
  Action takeAction();

 private:
  struct CurveDoc;
  struct ColourDoc;
  void edited(const std::string& path, std::string bytes, Action action, std::string& status);
  void addCurvePanels(CurveDoc& doc, std::vector<viewer::Panel>& out);
  void addColourPanel(ColourDoc& doc, std::vector<viewer::Panel>& out);
  bool changedOnDisk(const std::string& path, std::filesystem::file_time_type stamp) const;

  std::vector<std::unique_ptr<CurveDoc>> curves_;
  std::unique_ptr<ColourDoc> colours_;
  std::string scratch_;  // the edited copies' folder ("" until the first edit)
  std::map<std::string, std::string> copies_;  // file → its edited copy
  Action pending_ = Action::None;
};

}  // namespace lcjit::app
