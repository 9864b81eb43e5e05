// vlab's control panels (vlab tools manual §2.4) and the parameter editor awkped (§11.2) that their
// messages drive: what the window's Parameters panel shows, and the edits its sliders make to a
// model's files (`#define NAME value` lines of the .l, an included header or the .vset).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::runtime {

// One awkped message (§11.2.1), %d already replaced: `d NAME VALUE [SCALE]` sets the value of
// `#define NAME` to VALUE/SCALE; `n LINE WORD EXP VALUE` sets word WORD of line LINE to
// VALUE×10^EXP. `value` is the number written, scaled.
struct AwkpedEdit {
  enum class Kind { Define, LineWord } kind = Kind::Define;
  std::string name;
  int line = 0, word = 0;
  double value = 0;
};

// The edit a panel message makes when its item shows `shown` (a slider's value; 1/0 for buttons),
// or nothing for a message awkped does not understand.
std::optional<AwkpedEdit> awkpedEdit(std::string_view message, int shown);

// `text` with the edit made. Unlike awkped, which rebuilds the line from its words, only the value's
// characters change, so the rest of the file stays byte for byte as it was. An edit of a #define the
// text does not have, or of a line/word past its end, is an error naming `file`.
llvm::Expected<std::string> applyAwkped(std::string_view text, const AwkpedEdit& edit, const std::string& file);

// A number as awk prints it (%.6g; whole numbers without a point): what an edited file holds.
std::string awkNumber(double v);

// The value `#define NAME VALUE` gives NAME in `text` (the last such line), if it is a number.
std::optional<double> definedValue(std::string_view text, std::string_view name);

struct PanelItem {
  enum class Kind { Slider, Button, Label, Menu, Page } kind = Kind::Label;
  std::string name, message;
  int min = 0, max = 0;  // a slider's range: vlab's sliders move in whole steps
  int value = 0;         // a slider's start; a button's: 0 off, 1 on, 2 monostable
  int group = -1;        // the buttons of one GROUP are exclusive: the group's number
};

struct PanelFile {
  std::string name;     // `panel name:` (vlab) or `name:` (L-studio)
  std::string target;   // `associate: File NAME` (L-studio), as written; vlab names it in `specifications`
  std::string trigger;  // L-studio's `trigger:` (newlsystem, newmodel …); "" when not given
  std::vector<PanelItem> items;
};

// A panel specification file. Unknown headings are skipped (each vlab version added some); a line
// that is not `heading: value` where one is expected is an error with its line number.
llvm::Expected<PanelFile> parsePanel(std::string_view text, const std::string& file);

// A panel and the file its messages edit, both as paths.
struct PanelAndTarget {
  std::string panel, target;
};
// The panels of a model folder: the lines `panel P | awkped T` of a vlab object's `specifications`
// (how vlab starts them), then `*.pnl` files whose `associate:` names their target. Sorted by panel
// path, without repeats; files that cannot be read are left out.
std::vector<PanelAndTarget> findPanels(const std::string& modelDir);

}  // namespace lcjit::runtime
