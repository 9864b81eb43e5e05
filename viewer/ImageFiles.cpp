// Picture files (see ImageFiles.h).
#include "viewer/ImageFiles.h"

#include <algorithm>

#include <llvm/Support/Path.h>

#include "support/ReplacingFile.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

namespace lcjit::viewer {

namespace {

// "png" for "a/b.PNG"; "" when the name has no extension.
std::string imageExtension(const std::string& path) { return llvm::sys::path::extension(path).drop_front().lower(); }

}  // namespace

const char* const kImageFileTypes = ".png, .jpg, .jpeg or .bmp";

bool isImageFileName(const std::string& path) {
  const std::string ext = imageExtension(path);
  return ext == "png" || ext == "jpg" || ext == "jpeg" || ext == "bmp";
}

const char* const kVideoFileTypes = ".mp4 or .webm";

bool isVideoFileName(const std::string& path) {
  const std::string ext = imageExtension(path);
  return ext == "mp4" || ext == "webm";
}

llvm::Error writeImage(const runtime::Image& image, const std::string& path, bool alpha, int jpegQuality) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() < size_t(image.width) * image.height * 4)
    return llvm::createStringError("cannot write " + path + ": empty image");
  const std::string ext = imageExtension(path);
  const bool png = ext == "png", jpg = ext == "jpg" || ext == "jpeg", bmp = ext == "bmp";
  if (!png && !jpg && !bmp)
    return llvm::createStringError("cannot write " + path + ": unknown image type (use " + kImageFileTypes + ")");
  const int comp = (png && alpha) ? 4 : 3;
  std::vector<uint8_t> rgb;
  const uint8_t* data = image.rgba.data();
  if (comp == 3) {
    rgb.resize(size_t(image.width) * image.height * 3);
    for (size_t i = 0, n = size_t(image.width) * image.height; i < n; ++i) {
      rgb[i * 3] = image.rgba[i * 4];
      rgb[i * 3 + 1] = image.rgba[i * 4 + 1];
      rgb[i * 3 + 2] = image.rgba[i * 4 + 2];
    }
    data = rgb.data();
  }
  support::ReplacingFile file(path);  // a viewer re-reading the picture never gets half of it
  const char* to = file.writePath().c_str();
  int ok = 0;
  if (png) ok = stbi_write_png(to, image.width, image.height, comp, data, image.width * comp);
  else if (jpg) ok = stbi_write_jpg(to, image.width, image.height, comp, data, std::clamp(jpegQuality, 1, 100));
  else ok = stbi_write_bmp(to, image.width, image.height, comp, data);
  if (!ok) return llvm::createStringError("cannot write " + path);
  return file.commit();
}

}  // namespace lcjit::viewer
