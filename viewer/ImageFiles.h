// Picture files: an RGBA image and the types lcjit writes pictures as (.png, .jpg/.jpeg, .bmp,
// chosen by extension, through stb_image_write), and the names of videos (VideoFile.h). No
// OpenGL: a build without rendering still knows a picture's or a video's name when it sees one,
// to say that it cannot make it.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::viewer {

// RGBA8, rows top to bottom (row 0 is the top of the picture).
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
  std::array<uint8_t, 4> pixel(int x, int y) const {
    const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
};

// The picture types, as messages name them: ".png, .jpg, .jpeg or .bmp".
extern const char* const kImageFileTypes;

// Whether writeImage writes `path`'s type (any case).
bool isImageFileName(const std::string& path);

// The video types, as messages name them: ".mp4 or .webm".
extern const char* const kVideoFileTypes;

// Whether `path` names a video VideoWriter writes (.mp4, .webm; any case).
bool isVideoFileName(const std::string& path);

// Writes by extension: .png (RGB, or RGBA with `alpha`), .jpg/.jpeg (RGB, `jpegQuality`), .bmp.
llvm::Error writeImage(const Image& image, const std::string& path, bool alpha = false, int jpegQuality = 95);

}  // namespace lcjit::viewer
