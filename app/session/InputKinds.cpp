// The input files' table by extension (InputKinds.h).
#include "app/session/InputKinds.h"

#include "app/session/Languages.h"

#include <vector>

namespace lcjit::app {

namespace {

// The files read beside a model, in the order messages list them (after the models').
constexpr InputExtension kBeside[] = {
    {"a", FileKind::Animation, false, true},
    {"v", FileKind::View, false, true},          {"dr", FileKind::View, false, true},
    {"map", FileKind::Colormap, false, true},    {"mat", FileKind::Material, false, true},
    {"s", FileKind::Surface, false, true},       {"con", FileKind::Contour, false, true},
    {"cset", FileKind::Contour, true, true},     {"e", FileKind::Environment, false, true},
    {"func", FileKind::Function, false, true},   {"fset", FileKind::Function, true, true},
    {"tset", FileKind::Timeline, false, true},   {"vset", FileKind::Parameters, false, true},
    {"rgb", FileKind::Texture, false, false},    {"png", FileKind::Texture, false, false},
    {"jpg", FileKind::Texture, false, false},    {"jpeg", FileKind::Texture, false, false},
    {"bmp", FileKind::Texture, false, false},    {"tga", FileKind::Texture, false, false},
    {"tif", FileKind::Texture, false, false},    {"tiff", FileKind::Texture, false, false},
    {"gif", FileKind::Texture, false, false},
};

// Every row: the languages' model files, then the files beside them.
const std::vector<InputExtension>& inputs() {
  static const std::vector<InputExtension> rows = [] {
    std::vector<InputExtension> all;
    for (const Language& language : languages())
      for (std::string_view ext : language.extensions) all.push_back({ext, FileKind::Model, false, true});
    all.insert(all.end(), std::begin(kBeside), std::end(kBeside));
    return all;
  }();
  return rows;
}

}  // namespace

std::string_view extensionOf(std::string_view path) {
  size_t slash = path.find_last_of('/');
  std::string_view name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  size_t dot = name.find_last_of('.');
  if (dot == std::string_view::npos || dot == 0) return {};
  return name.substr(dot + 1);
}

std::span<const InputExtension> inputExtensions() { return inputs(); }

const InputExtension* inputExtensionOf(std::string_view path) {
  std::string_view ext = extensionOf(path);
  if (ext.empty()) return nullptr;
  for (const InputExtension& in : inputs())
    if (in.extension == ext) return &in;
  return nullptr;
}

FileKind fileKindOf(std::string_view path) {
  const InputExtension* in = inputExtensionOf(path);
  return in ? in->kind : FileKind::Other;
}

const char* toString(FileKind k) {
  switch (k) {
    case FileKind::Model: return "model";
    case FileKind::View: return "view";
    case FileKind::Animation: return "animation";
    case FileKind::Colormap: return "colormap";
    case FileKind::Material: return "material";
    case FileKind::Surface: return "surface";
    case FileKind::Texture: return "texture";
    case FileKind::Function: return "function";
    case FileKind::Timeline: return "timeline";
    case FileKind::Contour: return "contour";
    case FileKind::Parameters: return "parameters";
    case FileKind::Environment: return "environment";
    case FileKind::Other: return "other";
  }
  return "?";
}

std::string commandLineExtensions() {
  std::string list, last;
  for (const InputExtension& in : inputs()) {
    if (!in.commandLine) continue;
    if (!last.empty()) list += (list.empty() ? "" : ", ") + last;
    last = "." + std::string(in.extension);
  }
  return list + " or " + last;
}

}  // namespace lcjit::app
