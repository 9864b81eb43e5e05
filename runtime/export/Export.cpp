// Exporters' entry point (see Export.h): the format chosen by extension, the input resolved once
// (palette, view, camera), then the format's writer.
#include "runtime/export/Export.h"

#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"

namespace lcjit::runtime {

namespace {
struct Known {
  const char* ext;
  ExportFormat format;
};
constexpr Known kFormats[] = {{"obj", ExportFormat::Obj}, {"ply", ExportFormat::Ply},   {"stl", ExportFormat::Stl},
                              {"gltf", ExportFormat::Gltf}, {"glb", ExportFormat::Glb}, {"svg", ExportFormat::Svg},
                              {"ps", ExportFormat::Ps},   {"eps", ExportFormat::Eps},   {"pdf", ExportFormat::Pdf},
                              {"pov", ExportFormat::Pov}};
}  // namespace

std::optional<ExportFormat> exportFormatFor(std::string_view pathOrExtension) {
  std::string ext = exporting::lowerExtension(pathOrExtension);
  for (const Known& k : kFormats)
    if (ext == k.ext) return k.format;
  return std::nullopt;
}

bool isExportFormat(std::string_view pathOrExtension) { return exportFormatFor(pathOrExtension).has_value(); }

const char* exportFormatExtension(ExportFormat format) {
  for (const Known& k : kFormats)
    if (k.format == format) return k.ext;
  return "";
}

bool exportDrawsPage(ExportFormat format) {
  return format == ExportFormat::Svg || format == ExportFormat::Ps || format == ExportFormat::Eps ||
         format == ExportFormat::Pdf;
}

llvm::Error exportGeometry(const std::string& path, const ExportInput& in) {
  std::optional<ExportFormat> format = exportFormatFor(path);
  if (!format) {
    std::string names;
    for (const Known& k : kFormats) names += std::string(names.empty() ? "." : ", .") + k.ext;
    return llvm::createStringError(std::errc::invalid_argument,
                                   "cannot export '%s': unknown file extension (known: %s)", path.c_str(), names.c_str());
  }
  return exportGeometry(path, *format, in);
}

llvm::Error exportGeometry(const std::string& path, ExportFormat format, const ExportInput& in) {
  if (!in.geometry)
    return llvm::createStringError(std::errc::invalid_argument, "cannot export '%s': no geometry", path.c_str());
  const size_t nv = in.geometry->vertices.size();
  for (uint32_t i : in.geometry->indices)
    if (i >= nv)
      return llvm::createStringError(std::errc::invalid_argument,
                                     "cannot export '%s': triangle vertex index %u out of range (%zu vertices)",
                                     path.c_str(), i, nv);
  exporting::Context cx(path, in);
  auto write = [&]() -> llvm::Error {
    switch (format) {
      case ExportFormat::Obj: return exporting::writeObj(cx);
      case ExportFormat::Ply: return exporting::writePly(cx);
      case ExportFormat::Stl: return exporting::writeStl(cx);
      case ExportFormat::Gltf: return exporting::writeGltf(cx, false);
      case ExportFormat::Glb: return exporting::writeGltf(cx, true);
      case ExportFormat::Svg: return exporting::writeSvg(cx);
      case ExportFormat::Ps: return exporting::writePostScript(cx, false);
      case ExportFormat::Eps: return exporting::writePostScript(cx, true);
      case ExportFormat::Pdf: return exporting::writePdf(cx);
      case ExportFormat::Pov: return exporting::writePov(cx);
    }
    return llvm::createStringError(std::errc::invalid_argument, "cannot export '%s': unknown format", path.c_str());
  };
  if (llvm::Error e = write()) return e;
  // A multi-view model in a 3D format: view 0 only (ExportInput::views), said.
  const auto& windows = cx.view.windows;
  if (!exportDrawsPage(format) && in.note && windows.size() > 1) {
    if (!in.note->empty()) *in.note += "; ";
    *in.note += fmt::format("{} holds view 0{} only: the view file's {} windows are laid out together only in "
                            "pictures and in .svg, .ps, .eps and .pdf",
                            path, windows[0].name.empty() ? "" : " (" + windows[0].name + ")", windows.size());
  }
  return llvm::Error::success();
}

}  // namespace lcjit::runtime
