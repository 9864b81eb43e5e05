// The window's Parameters panel: the model's .vset values (manual §6.7), its .tset timelines'
// ranges (vlab tools manual §10) and the items of its vlab panels (§2), as sliders and fields. A
// .vset value or a timeline's start/end changes in memory and re-runs the model with no recompile
// (the REPL's :set); "Save values" writes them back to the .vset and .tset. A panel item edits its
// target file as vlab's awkped does, and the file's change reloads the model. Values the model
// marks as tunable (`tunable(NAME, value, min, max)`, runtime::Tunables) are sliders too; a move
// is what the call returns from the next run on.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

#include "runtime/files/PanelFile.h"
#include "viewer/Window.h"

namespace lcjit::runtime {
class FunctionStore;
class Tunables;
}

namespace lcjit::app {

struct ModelFiles;

class ParameterPanel {
 public:
  static constexpr const char* kTitle = "Parameters";
  // `tunables`: the session's (its window state), shown after the files' values.
  explicit ParameterPanel(const runtime::Tunables& tunables) : tunables_(tunables) {}

  // Reads the .vset values and the model folder's panels (runtime::findPanels); again after each
  // load, keeping values not yet applied. Panels that cannot be read are reported in status().
  void load(const ModelFiles& files, const runtime::FunctionStore& functions);

  // What the window draws; its edits land here (they may come while the model derives).
  viewer::Panel panel();
  bool empty() const;

  // .vset values changed since the last call, for FunctionStore::setParameter and a re-run.
  std::map<std::string, float> takeParameters();
  // Tunable values moved since the last call, for runtime::Tunables::move and a re-run.
  std::map<std::string, float> takeTunables();
  // Timelines whose range changed since the last call (name → start, end), for setTimeline.
  std::map<std::string, std::pair<float, float>> takeTimelines();
  // Files a panel item has rewritten since the last call: the model must reload what reads them.
  std::vector<std::string> takeChangedFiles();

  // The .vset and .tset with their values as they are now (Save values); only the values'
  // characters change.
  llvm::Error saveParameters();
  // The .vset changed on disk: its values win over those moved in the panel and not saved. (Until
  // then a reload, which reads the .vset again, keeps the panel's values.)
  void forgetUnsaved() { unsaved_.clear(), unsavedTimelines_.clear(); }
  const std::string& status() const { return status_; }

 private:
  struct Control {
    viewer::PanelControl shown;
    std::string parameter;  // a .vset value's name, or ""
    std::string timeline;   // a .tset timeline's name, or "" (then `end`: its end, else its start)
    bool end = false;
    std::string target;     // the file a panel item edits
    std::string message;    // its awkped message (%d: the slider's whole value)
    float scale = 1;        // a `d NAME %d SCALE` slider shows value/scale
  };
  void changed(size_t index, float value);
  void edit(const Control& c, int shown);

  const runtime::Tunables& tunables_;
  std::vector<Control> controls_;
  std::string vsetPath_;
  std::map<std::string, float> pendingParameters_;
  std::map<std::string, float> unsaved_;
  std::vector<std::string> tunablesShown_;  // the tunables of the last panel(), after controls_
  std::map<std::string, float> pendingTunables_;
  std::string tsetPath_;
  std::map<std::string, std::pair<float, float>> pendingTimelines_, unsavedTimelines_;
  std::vector<std::string> changedFiles_;
  std::string status_;
};

}  // namespace lcjit::app
