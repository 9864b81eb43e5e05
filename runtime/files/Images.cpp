// Texture images: see Images.h. PNG/JPEG through stb_image; SGI .rgb by the reader below.
#include "runtime/files/Images.h"
#include "runtime/files/TextLines.h"

#include <cstring>

#include <llvm/Support/MemoryBuffer.h>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_NO_STDIO
#define STBI_FAILURE_USERMSG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace lcjit::runtime {
namespace {

uint16_t be16(const uint8_t* p) { return uint16_t((p[0] << 8) | p[1]); }
uint32_t be32(const uint8_t* p) { return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]; }

constexpr size_t kMaxPixels = size_t(1) << 28;

}  // namespace

llvm::Expected<Image> decodeSgi(const uint8_t* d, size_t size, const std::string& name) {
  constexpr size_t kHeader = 512;
  if (size < kHeader) return textfile::fail(name, 0, "truncated SGI image header");
  if (be16(d) != 474) return textfile::fail(name, 0, "not an SGI image (bad magic number)");
  const int storage = d[2], bpc = d[3];
  const int dimension = be16(d + 4);
  size_t xs = be16(d + 6), ys = be16(d + 8), zs = be16(d + 10);
  if (storage != 0 && storage != 1) return textfile::fail(name, 0, "unknown SGI storage format " + std::to_string(storage));
  if (bpc != 1 && bpc != 2) return textfile::fail(name, 0, "unsupported SGI bytes per channel " + std::to_string(bpc));
  if (dimension == 1) {
    ys = 1;
    zs = 1;
  } else if (dimension == 2) {
    zs = 1;
  } else if (dimension != 3) {
    return textfile::fail(name, 0, "invalid SGI dimension " + std::to_string(dimension));
  }
  if (xs == 0 || ys == 0 || zs == 0) return textfile::fail(name, 0, "empty SGI image");
  if (zs > 4) return textfile::fail(name, 0, "SGI images with " + std::to_string(zs) + " channels are not supported");
  if (xs * ys > kMaxPixels) return textfile::fail(name, 0, "SGI image too large");

  Image img;
  img.width = int(xs);
  img.height = int(ys);
  img.fileChannels = int(zs);
  std::vector<uint8_t> planes(xs * ys * zs);  // channel z, row y, column x (8-bit)
  const size_t rowBytes = xs * size_t(bpc);

  if (storage == 0) {
    if (size < kHeader + rowBytes * ys * zs) return textfile::fail(name, 0, "truncated SGI image data");
    for (size_t z = 0; z < zs; ++z)
      for (size_t y = 0; y < ys; ++y) {
        const uint8_t* src = d + kHeader + (z * ys + y) * rowBytes;
        uint8_t* dst = &planes[(z * ys + y) * xs];
        for (size_t x = 0; x < xs; ++x) dst[x] = src[x * size_t(bpc)];  // high byte for 16 bits
      }
  } else {
    const size_t tab = ys * zs;
    if (size < kHeader + tab * 8) return textfile::fail(name, 0, "truncated SGI RLE tables");
    if (xs * ys * zs > (size - kHeader) * 127) return textfile::fail(name, 0, "SGI RLE image larger than its data allows");
    for (size_t z = 0; z < zs; ++z)
      for (size_t y = 0; y < ys; ++y) {
        const size_t row = y + z * ys;
        const size_t start = be32(d + kHeader + row * 4);
        const size_t len = be32(d + kHeader + tab * 4 + row * 4);
        if (start > size || len > size - start)
          return textfile::fail(name, 0, "SGI RLE row " + std::to_string(y) + " of channel " + std::to_string(z) +
                                " lies outside the file");
        const uint8_t* p = d + start;
        const uint8_t* end = p + len;
        uint8_t* dst = &planes[(z * ys + y) * xs];
        size_t x = 0;
        auto bad = [&] {
          return textfile::fail(name, 0, "corrupt SGI RLE data in row " + std::to_string(y) + " of channel " + std::to_string(z));
        };
        while (true) {
          if (p + bpc > end) return bad();
          const unsigned ctl = bpc == 1 ? p[0] : p[1];  // 16 bits: the count is in the low byte
          p += bpc;
          const size_t count = ctl & 0x7f;
          if (count == 0) break;
          if (x + count > xs) return bad();
          if (ctl & 0x80) {
            if (size_t(end - p) < count * size_t(bpc)) return bad();
            for (size_t i = 0; i < count; ++i, p += bpc) dst[x++] = p[0];
          } else {
            if (p + bpc > end) return bad();
            const uint8_t v = p[0];
            p += bpc;
            for (size_t i = 0; i < count; ++i) dst[x++] = v;
          }
        }
        if (x != xs) return bad();
      }
  }

  img.rgba.resize(xs * ys * 4);
  for (size_t y = 0; y < ys; ++y)
    for (size_t x = 0; x < xs; ++x) {
      uint8_t* o = &img.rgba[(y * xs + x) * 4];
      auto ch = [&](size_t z) { return planes[(z * ys + y) * xs + x]; };
      switch (zs) {
        case 1: o[0] = o[1] = o[2] = ch(0); o[3] = 255; break;
        case 2: o[0] = o[1] = o[2] = ch(0); o[3] = ch(1); break;
        case 3: o[0] = ch(0); o[1] = ch(1); o[2] = ch(2); o[3] = 255; break;
        default: o[0] = ch(0); o[1] = ch(1); o[2] = ch(2); o[3] = ch(3); break;
      }
    }
  return img;
}

llvm::Expected<Image> decodeImage(const uint8_t* data, size_t size, const std::string& name) {
  if (size >= 2 && be16(data) == 474) return decodeSgi(data, size, name);
  if (size == 0) return textfile::fail(name, 0, "empty image file");
  if (size > size_t(INT32_MAX)) return textfile::fail(name, 0, "image file too large");
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(data, int(size), &w, &h, &comp))
    return textfile::fail(name, 0, std::string("cannot decode image: ") + stbi_failure_reason());
  if (w <= 0 || h <= 0 || size_t(w) * size_t(h) > kMaxPixels) return textfile::fail(name, 0, "image too large");
  unsigned char* px = stbi_load_from_memory(data, int(size), &w, &h, &comp, 4);
  if (!px) return textfile::fail(name, 0, std::string("cannot decode image: ") + stbi_failure_reason());
  Image img;
  img.width = w;
  img.height = h;
  img.fileChannels = comp;
  img.rgba.resize(size_t(w) * size_t(h) * 4);
  const size_t row = size_t(w) * 4;
  for (int y = 0; y < h; ++y)  // stb gives the top row first
    std::memcpy(&img.rgba[size_t(y) * row], px + size_t(h - 1 - y) * row, row);
  stbi_image_free(px);
  return img;
}

llvm::Expected<Image> loadImage(const std::string& path) {
  auto buf = llvm::MemoryBuffer::getFile(path, /*IsText=*/false);
  if (!buf) return textfile::fail(path, 0, "cannot open file: " + buf.getError().message());
  const auto& b = **buf;
  return decodeImage(reinterpret_cast<const uint8_t*>(b.getBufferStart()), b.getBufferSize(), path);
}

}  // namespace lcjit::runtime
