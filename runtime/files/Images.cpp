// Texture images: see Images.h. PNG through libpng, JPEG through libjpeg-turbo (hardened decoders
// of untrusted files: stb_image wrote out of bounds on a corrupt JPEG); SGI .rgb by
// the reader below.
#include "runtime/files/Images.h"
#include "runtime/files/TextLines.h"

#include <cstring>

#include <llvm/Support/MemoryBuffer.h>

// libpng and libjpeg report errors by longjmp. A longjmp must not skip a C++ destructor, so the
// functions below that call setjmp are plain C: their state lives in a struct the (C++) caller
// owns, and the caller allocates the pixels between the header and the pixel phase.
#include <csetjmp>
#include <cstdio>  // jpeglib.h uses FILE without including it

#include <jpeglib.h>
#include <jerror.h>
#include <png.h>

namespace lcjit::runtime {
namespace {

uint16_t be16(const uint8_t* p) { return uint16_t((p[0] << 8) | p[1]); }
uint32_t be32(const uint8_t* p) { return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]; }

constexpr size_t kMaxPixels = size_t(1) << 28;

// ---- PNG (libpng) ----

struct PngRead {
  const uint8_t* data = nullptr;
  size_t size = 0, pos = 0;
  png_structp png = nullptr;
  png_infop info = nullptr;
  char error[256] = "";
  png_uint_32 width = 0, height = 0;
  int channels = 0;     // in the file, as Image::fileChannels
  uint64_t rawBytes = 0;  // the filtered scanlines the compressed data must hold
};

void pngError(png_structp png, png_const_charp msg) {
  auto* r = static_cast<PngRead*>(png_get_error_ptr(png));
  std::snprintf(r->error, sizeof r->error, "%s", msg);
  png_longjmp(png, 1);
}

// Warnings are about damaged ancillary chunks (text, colour profiles), which textures do not use.
void pngWarning(png_structp, png_const_charp) {}

void pngSource(png_structp png, png_bytep out, size_t n) {
  auto* r = static_cast<PngRead*>(png_get_io_ptr(png));
  if (n > r->size - r->pos) png_error(png, "file truncated");
  std::memcpy(out, r->data + r->pos, n);
  r->pos += n;
}

// Reads the header and sets the transforms to RGBA8: palette and grey expanded, tRNS to alpha,
// 16 bits to their high byte (as the SGI reader does), no gamma correction (textures are drawn
// with their stored values, as lpfg does).
bool pngHeader(PngRead* r) {
  r->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, r, pngError, pngWarning);
  if (r->png) r->info = png_create_info_struct(r->png);
  if (!r->png || !r->info) {
    std::snprintf(r->error, sizeof r->error, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_set_read_fn(r->png, r, pngSource);
  png_read_info(r->png, r->info);
  r->width = png_get_image_width(r->png, r->info);
  r->height = png_get_image_height(r->png, r->info);
  const int type = png_get_color_type(r->png, r->info), depth = png_get_bit_depth(r->png, r->info);
  const bool trns = png_get_valid(r->png, r->info, PNG_INFO_tRNS) != 0;
  r->rawBytes = uint64_t(r->height) * (1 + (uint64_t(r->width) * png_get_channels(r->png, r->info) * depth + 7) / 8);
  switch (type) {
    case PNG_COLOR_TYPE_GRAY: r->channels = trns ? 2 : 1; break;
    case PNG_COLOR_TYPE_GRAY_ALPHA: r->channels = 2; break;
    case PNG_COLOR_TYPE_RGB_ALPHA: r->channels = 4; break;
    default: r->channels = trns ? 4 : 3; break;  // RGB, palette
  }
  png_set_expand(r->png);
  png_set_strip_16(r->png);
  png_set_gray_to_rgb(r->png);
  png_set_add_alpha(r->png, 0xff, PNG_FILLER_AFTER);
  png_set_interlace_handling(r->png);
  png_read_update_info(r->png, r->info);
  if (png_get_rowbytes(r->png, r->info) != size_t(r->width) * 4) png_error(r->png, "unsupported pixel format");
  return true;
}

bool pngPixels(PngRead* r, png_bytepp rows) {
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_read_image(r->png, rows);
  png_read_end(r->png, nullptr);  // the rest of the file: a truncated one is an error
  return true;
}

llvm::Expected<Image> decodePng(const uint8_t* data, size_t size, const std::string& name) {
  PngRead r;
  r.data = data;
  r.size = size;
  struct Destroy {
    PngRead& r;
    ~Destroy() { png_destroy_read_struct(&r.png, r.info ? &r.info : nullptr, nullptr); }
  } destroy{r};
  if (!pngHeader(&r)) return textfile::fail(name, 0, std::string("cannot decode PNG image: ") + r.error);
  if (size_t(r.width) * r.height > kMaxPixels)
    return textfile::fail(name, 0, "PNG image too large (" + std::to_string(r.width) + "x" + std::to_string(r.height) + ")");
  // Deflate expands at most 1032:1; a header that claims more than the file can hold is damaged
  // (and would otherwise have us allocate for pixels that are not there).
  if (r.rawBytes > uint64_t(size) * 1032)
    return textfile::fail(name, 0, "PNG image (" + std::to_string(r.width) + "x" + std::to_string(r.height) +
                          ") larger than its data allows");
  Image img;
  img.width = int(r.width);
  img.height = int(r.height);
  img.fileChannels = r.channels;
  img.rgba.resize(size_t(r.width) * r.height * 4);
  std::vector<png_bytep> rows(r.height);
  for (size_t y = 0; y < r.height; ++y)  // PNG stores the top row first, as Image does
    rows[y] = &img.rgba[y * size_t(r.width) * 4];
  if (!pngPixels(&r, rows.data())) return textfile::fail(name, 0, std::string("cannot decode PNG image: ") + r.error);
  return img;
}

// ---- JPEG (libjpeg-turbo) ----

// A progressive JPEG may hold any number of scans, each a pass over the whole image; libjpeg-turbo
// advises a limit for untrusted files (its TJPARAM_SCANLIMIT, djpeg -maxscans).
constexpr int kMaxJpegScans = 500;

struct JpegRead {
  jpeg_decompress_struct cinfo;
  jpeg_error_mgr err;
  jpeg_progress_mgr progress;
  std::jmp_buf jmp;
  char error[JMSG_LENGTH_MAX + 64];
  bool cmyk;  // decoded as CMYK, converted to RGB by the caller
};

[[noreturn]] void jpegErrorExit(j_common_ptr c) {
  auto* r = static_cast<JpegRead*>(c->client_data);
  (*c->err->format_message)(c, r->error);
  std::longjmp(r->jmp, 1);
}

// Warnings (corrupt entropy data, a premature end) still give a picture, the damaged part grey,
// as stb_image gave one; they are not printed.
void jpegMessage(j_common_ptr, int) {}

void jpegProgress(j_common_ptr c) {
  auto* d = reinterpret_cast<j_decompress_ptr>(c);
  if (d->input_scan_number > kMaxJpegScans) {
    auto* r = static_cast<JpegRead*>(c->client_data);
    std::snprintf(r->error, sizeof r->error, "more than %d progressive scans", kMaxJpegScans);
    std::longjmp(r->jmp, 1);
  }
}

bool jpegHeader(JpegRead* r, const uint8_t* data, size_t size) {
  r->cinfo.err = jpeg_std_error(&r->err);
  r->err.error_exit = jpegErrorExit;
  r->err.emit_message = jpegMessage;
  r->cinfo.client_data = r;  // kept by jpeg_create_decompress, which may already fail
  if (setjmp(r->jmp)) return false;
  jpeg_create_decompress(&r->cinfo);
  r->progress.progress_monitor = jpegProgress;
  r->cinfo.progress = &r->progress;
  jpeg_mem_src(&r->cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&r->cinfo, TRUE);
  r->cmyk = r->cinfo.jpeg_color_space == JCS_CMYK || r->cinfo.jpeg_color_space == JCS_YCCK;
  r->cinfo.out_color_space = r->cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  return true;
}

bool jpegStart(JpegRead* r) {
  if (setjmp(r->jmp)) return false;
  jpeg_start_decompress(&r->cinfo);
  if (r->cinfo.output_components != 4) ERREXIT(&r->cinfo, JERR_CONVERSION_NOTIMPL);
  return true;
}

bool jpegPixels(JpegRead* r, uint8_t* rgba) {
  if (setjmp(r->jmp)) return false;
  const size_t row = size_t(r->cinfo.output_width) * 4;
  while (r->cinfo.output_scanline < r->cinfo.output_height) {
    JSAMPROW dst = rgba + size_t(r->cinfo.output_scanline) * row;  // JPEG stores the top row first, as Image does
    jpeg_read_scanlines(&r->cinfo, &dst, 1);
  }
  return true;
}

llvm::Expected<Image> decodeJpeg(const uint8_t* data, size_t size, const std::string& name) {
  JpegRead r{};
  struct Destroy {
    JpegRead& r;
    ~Destroy() { jpeg_destroy_decompress(&r.cinfo); }
  } destroy{r};
  auto failed = [&] { return textfile::fail(name, 0, std::string("cannot decode JPEG image: ") + r.error); };
  if (!jpegHeader(&r, data, size)) return failed();
  const size_t w = r.cinfo.image_width, h = r.cinfo.image_height;
  if (w * h > kMaxPixels)
    return textfile::fail(name, 0, "JPEG image too large (" + std::to_string(w) + "x" + std::to_string(h) + ")");
  if (!jpegStart(&r)) return failed();
  Image img;
  img.width = int(r.cinfo.output_width);
  img.height = int(r.cinfo.output_height);
  img.fileChannels = r.cinfo.num_components == 1 ? 1 : 3;
  img.rgba.resize(size_t(img.width) * size_t(img.height) * 4);
  if (!jpegPixels(&r, img.rgba.data())) return failed();
  if (r.cmyk)  // Adobe's CMYK is stored inverted: R = C·K/255 of the stored values
    for (size_t i = 0; i < img.rgba.size(); i += 4) {
      uint8_t* p = &img.rgba[i];
      const unsigned k = p[3];
      for (int c = 0; c < 3; ++c) p[c] = uint8_t((p[c] * k + 127) / 255);
      p[3] = 255;
    }
  return img;
}

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
  for (size_t y = 0; y < ys; ++y)  // the file's row y, from the bottom
    for (size_t x = 0; x < xs; ++x) {
      uint8_t* o = &img.rgba[((ys - 1 - y) * xs + x) * 4];
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
  static const uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 8 && std::memcmp(data, kPng, 8) == 0) return decodePng(data, size, name);
  if (size >= 2 && data[0] == 0xff && data[1] == 0xd8) return decodeJpeg(data, size, name);
  return textfile::fail(name, 0, "not a PNG, JPEG or SGI (.rgb) image");
}

llvm::Expected<Image> loadImage(const std::string& path) {
  auto buf = textfile::readFile(path);
  if (!buf) return buf.takeError();
  const auto& b = **buf;
  return decodeImage(reinterpret_cast<const uint8_t*>(b.getBufferStart()), b.getBufferSize(), path);
}

}  // namespace lcjit::runtime
