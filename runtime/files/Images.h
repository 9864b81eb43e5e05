// Texture images of the view file's `texture:` lines (lpfg manual §5.7, §8.2.3): PNG (libpng), JPEG
// (libjpeg-turbo) and SGI .rgb (uncompressed or RLE, 1-4 channels, 8 or 16 bits per channel).
//
// Pixels are RGBA8 with the BOTTOM row first (row 0 = the image's bottom), ready for
// glTexImage2D, as lpfg passes them: SGI files already store rows bottom-up; PNG/JPEG rows are
// flipped. Grey becomes (g,g,g,255), grey+alpha (g,g,g,a), RGB gets alpha 255; 16-bit SGI values
// keep their high byte (16-bit PNG too); no gamma correction.
// lpfg itself reads only .rgb (3 or 4 channels, power-of-two sizes) and .png, chosen by the
// file extension; here the format is recognised from the file's first bytes and those limits are
// not enforced. Ids: view-file order from 0. lpfg draws textures with GL_NEAREST filtering.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::runtime {

struct Image {
  int width = 0, height = 0;
  int fileChannels = 0;       // channels stored in the file (1-4)
  std::vector<uint8_t> rgba;  // width·height·4 bytes, bottom row first
  // Pixel (x, y) with y counted from the bottom.
  const uint8_t* pixel(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
};

llvm::Expected<Image> loadImage(const std::string& path);
// From memory; `name` appears in errors.
llvm::Expected<Image> decodeImage(const uint8_t* data, size_t size, const std::string& name);
llvm::Expected<Image> decodeSgi(const uint8_t* data, size_t size, const std::string& name);

}  // namespace lcjit::runtime
