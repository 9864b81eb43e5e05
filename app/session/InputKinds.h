// The kinds of file a model is given, by extension: one table, read by the command line and the
// REPL (classifyInputs: which file is the model, the view, …), the watcher and the window (which
// action a change runs, FileMonitor.h) and the message naming what is accepted. The model files'
// rows come from the languages' table (Languages.h); the rest are the files lpfg reads beside them.
#pragma once
#include <span>
#include <string>
#include <string_view>

namespace lcjit::app {

enum class FileKind {
  Model,        // a grammar language's model: .l (Languages.h)
  View,         // .v (.dr: the old view file)
  Animation,    // .a
  Colormap,     // .map
  Material,     // .mat
  Surface,      // .s
  Texture,      // .rgb .png .jpg .jpeg .bmp .tga .tif .tiff .gif (named by the view file)
  Function,     // .func (and .fset: a set of functions)
  Timeline,     // .tset
  Contour,      // .con (and .cset: a set of contours)
  Parameters,   // .vset
  Environment,  // .e (a change restarts the environmental program: New L-system)
  Other,
};

struct InputExtension {
  std::string_view extension;  // without its dot, case-sensitive as lpfg's command line is
  FileKind kind;
  bool set;          // a file that names others of its kind (.fset, .cset)
  bool commandLine;  // given on the command line (a texture is named by the view file instead)
};

// The extension of `path`'s file name, without its dot; "" for none (a hidden file's name is not an
// extension).
std::string_view extensionOf(std::string_view path);
// Every row: the languages' model files first, then the files read beside them.
std::span<const InputExtension> inputExtensions();
// The row for `path`'s extension; nullptr for an extension no row has.
const InputExtension* inputExtensionOf(std::string_view path);
FileKind fileKindOf(std::string_view path);
const char* toString(FileKind k);
// ".l, .a, .v, … or .vset": the extensions the command line takes (the languages' first), for
// messages.
std::string commandLineExtensions();

}  // namespace lcjit::app
