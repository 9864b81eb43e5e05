// Picture files: the types lcjit writes pictures as (.png, .jpg/.jpeg, .bmp, chosen by
// extension, through stb_image_write), and the names of videos (VideoFile.h). A picture is
// lcjit's one RGBA image, runtime::Image (runtime/files/Images.h), top row first. No OpenGL: a
// build without rendering still knows a picture's or a video's name when it sees one, to say that
// it cannot make it.
#pragma once
#include <string>

#include <llvm/Support/Error.h>

#include "runtime/files/Images.h"

namespace lcjit::viewer {

// The picture types, as messages name them: ".png, .jpg, .jpeg or .bmp".
extern const char* const kImageFileTypes;

// Whether writeImage writes `path`'s type (any case).
bool isImageFileName(const std::string& path);

// The video types, as messages name them: ".mp4 or .webm".
extern const char* const kVideoFileTypes;

// Whether `path` names a video VideoWriter writes (.mp4, .webm; any case).
bool isVideoFileName(const std::string& path);

// Writes by extension: .png (RGB, or RGBA with `alpha`), .jpg/.jpeg (RGB, `jpegQuality`), .bmp.
llvm::Error writeImage(const runtime::Image& image, const std::string& path, bool alpha = false, int jpegQuality = 95);

}  // namespace lcjit::viewer
