// lcjit's one RGBA image (Image): the textures of the view file's `texture:` lines, read here, and
// the pictures lcjit renders, writes (viewer/ImageFiles) and films (viewer/VideoFile). And the
// texture readers (lpfg manual §5.7, §8.2.3): PNG (libpng), JPEG (libjpeg-turbo) and SGI .rgb
// (uncompressed or RLE, 1-4 channels, 8 or 16 bits per channel).
//
// Pixels are RGBA8 with the TOP row first (row 0 = the image's top), as PNG and JPEG store them
// and as pictures are written; SGI files store rows bottom-up and are flipped. lpfg hands
// glTexImage2D the bottom row first; the renderer flips a texture as it uploads it. Grey becomes
// (g,g,g,255), grey+alpha (g,g,g,a), RGB gets alpha 255; 16-bit SGI values keep their high byte
// (16-bit PNG too); no gamma correction.
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
  int fileChannels = 0;       // channels stored in the file (1-4); 0: a picture lcjit made
  std::vector<uint8_t> rgba;  // width·height·4 bytes, top row first
  // Pixel (x, y), y counted from the top (as a picture is seen).
  const uint8_t* pixel(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
  // Pixel (x, y), y counted from the bottom (as texture coordinates count).
  const uint8_t* pixelFromBottom(int x, int y) const { return pixel(x, height - 1 - y); }
};

llvm::Expected<Image> loadImage(const std::string& path);
// From memory; `name` appears in errors.
llvm::Expected<Image> decodeImage(const uint8_t* data, size_t size, const std::string& name);
llvm::Expected<Image> decodeSgi(const uint8_t* data, size_t size, const std::string& name);

}  // namespace lcjit::runtime
