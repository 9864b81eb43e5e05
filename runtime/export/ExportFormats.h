// Internal to the exporters: one writer per format.
#pragma once
#include "runtime/export/ExportCommon.h"

namespace lcjit::runtime::exporting {

llvm::Error writeObj(const Context& cx);
llvm::Error writePly(const Context& cx);
llvm::Error writeStl(const Context& cx);
llvm::Error writeGltf(const Context& cx, bool binary);
llvm::Error writeSvg(const Context& cx);
llvm::Error writePostScript(const Context& cx, bool eps);
llvm::Error writePdf(const Context& cx);
llvm::Error writePov(const Context& cx);

}  // namespace lcjit::runtime::exporting
