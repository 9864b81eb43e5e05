// Texture images: SGI .rgb (verbatim and RLE, 1-4 channels, 8/16 bits) written by the test and
// read back pixel-exact, PNG (libpng) and JPEG (libjpeg-turbo) written by stb_image_write and
// libpng, the top row first (SGI's rows, stored bottom up, turned over), and error handling (a corrupt JPEG Huffman table among it).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/files/Images.h"

#include <png.h>
#include <zlib.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

using namespace lcjit::runtime;

namespace {

const std::string kDir = std::string(LCJIT_TEST_DATA) + "/images/";

// planes[z][y][x], y = 0 the bottom row (SGI order).
using Planes = std::vector<std::vector<std::vector<uint16_t>>>;

void put16(std::vector<uint8_t>& d, size_t at, unsigned v) {
  d[at] = uint8_t(v >> 8);
  d[at + 1] = uint8_t(v);
}
void put32(std::vector<uint8_t>& d, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) d[at + i] = uint8_t(v >> (24 - 8 * i));
}

std::vector<uint8_t> header(bool rle, int bpc, int dimension, size_t xs, size_t ys, size_t zs) {
  std::vector<uint8_t> d(512, 0);
  put16(d, 0, 474);
  d[2] = rle ? 1 : 0;
  d[3] = uint8_t(bpc);
  put16(d, 4, unsigned(dimension));
  put16(d, 6, unsigned(xs));
  put16(d, 8, unsigned(ys));
  put16(d, 10, unsigned(zs));
  put32(d, 16, bpc == 1 ? 255 : 65535);
  return d;
}

std::vector<uint8_t> writeSgiVerbatim(const Planes& p, int bpc = 1, int dimension = 3) {
  const size_t zs = p.size(), ys = p[0].size(), xs = p[0][0].size();
  std::vector<uint8_t> d = header(false, bpc, dimension, xs, ys, zs);
  for (size_t z = 0; z < zs; ++z)
    for (size_t y = 0; y < ys; ++y)
      for (size_t x = 0; x < xs; ++x) {
        if (bpc == 2) d.push_back(uint8_t(p[z][y][x] >> 8));
        d.push_back(uint8_t(p[z][y][x]));
      }
  return d;
}

// 8-bit RLE: runs of >= 3 equal values become repeat packets, the rest literal packets.
std::vector<uint8_t> encodeRow(const std::vector<uint16_t>& row) {
  std::vector<uint8_t> out;
  size_t i = 0;
  while (i < row.size()) {
    size_t run = 1;
    while (i + run < row.size() && row[i + run] == row[i] && run < 127) ++run;
    if (run >= 3) {
      out.push_back(uint8_t(run));
      out.push_back(uint8_t(row[i]));
      i += run;
      continue;
    }
    size_t start = i, n = 0;
    while (i < row.size() && n < 127) {
      if (i + 2 < row.size() && row[i] == row[i + 1] && row[i] == row[i + 2]) break;
      ++i;
      ++n;
    }
    out.push_back(uint8_t(0x80 | n));
    for (size_t k = start; k < start + n; ++k) out.push_back(uint8_t(row[k]));
  }
  out.push_back(0);
  return out;
}

std::vector<uint8_t> writeSgiRle(const Planes& p) {
  const size_t zs = p.size(), ys = p[0].size(), xs = p[0][0].size();
  std::vector<uint8_t> d = header(true, 1, 3, xs, ys, zs);
  const size_t tab = ys * zs;
  d.resize(512 + 8 * tab);
  for (size_t z = 0; z < zs; ++z)
    for (size_t y = 0; y < ys; ++y) {
      std::vector<uint8_t> r = encodeRow(p[z][y]);
      const size_t row = y + z * ys;
      put32(d, 512 + 4 * row, uint32_t(d.size()));
      put32(d, 512 + 4 * tab + 4 * row, uint32_t(r.size()));
      d.insert(d.end(), r.begin(), r.end());
    }
  return d;
}

Planes makePlanes(size_t xs, size_t ys, size_t zs) {
  Planes p(zs, std::vector<std::vector<uint16_t>>(ys, std::vector<uint16_t>(xs)));
  for (size_t z = 0; z < zs; ++z)
    for (size_t y = 0; y < ys; ++y)
      for (size_t x = 0; x < xs; ++x)
        p[z][y][x] = uint16_t(x < 3 && y == 1 ? 200 : (37 * x + 11 * y + 71 * z) % 256);  // with runs
  return p;
}

Image mustDecode(const std::vector<uint8_t>& d, const std::string& name = "test.rgb") {
  auto img = decodeImage(d.data(), d.size(), name);
  if (!img) {
    ADD_FAILURE() << llvm::toString(img.takeError());
    return Image();
  }
  return std::move(*img);
}

void expectPixels(const Image& img, const Planes& p) {
  const size_t zs = p.size(), ys = p[0].size(), xs = p[0][0].size();
  ASSERT_EQ(img.width, int(xs));
  ASSERT_EQ(img.height, int(ys));
  ASSERT_EQ(img.rgba.size(), xs * ys * 4);
  EXPECT_EQ(img.fileChannels, int(zs));
  for (size_t y = 0; y < ys; ++y)
    for (size_t x = 0; x < xs; ++x) {
      const uint8_t* px = img.pixelFromBottom(int(x), int(y));  // the file's row y, from the bottom
      auto c = [&](size_t z) { return uint8_t(p[z][y][x]); };
      uint8_t e[4];
      switch (zs) {
        case 1: e[0] = e[1] = e[2] = c(0); e[3] = 255; break;
        case 2: e[0] = e[1] = e[2] = c(0); e[3] = c(1); break;
        case 3: e[0] = c(0); e[1] = c(1); e[2] = c(2); e[3] = 255; break;
        default: e[0] = c(0); e[1] = c(1); e[2] = c(2); e[3] = c(3); break;
      }
      for (int k = 0; k < 4; ++k) ASSERT_EQ(px[k], e[k]) << "x " << x << " y " << y << " channel " << k;
    }
}

void sink(void* ctx, void* data, int size) {
  auto* v = static_cast<std::vector<uint8_t>*>(ctx);
  v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

std::string errorOf(llvm::Expected<Image> img) {
  if (img) return "";
  return llvm::toString(img.takeError());
}

std::string errorOf(const std::vector<uint8_t>& d, const std::string& name = "bad.rgb") {
  return errorOf(decodeImage(d.data(), d.size(), name));
}

}  // namespace

TEST(ImageSgi, VerbatimRgbTurnedTopRowFirst) {
  Planes p = {{{10, 20, 30}, {40, 50, 60}}, {{1, 2, 3}, {4, 5, 6}}, {{7, 8, 9}, {100, 110, 120}}};
  Image img = mustDecode(writeSgiVerbatim(p));
  expectPixels(img, p);
  // The file's first row is the picture's bottom: the image's last row (row 0 is the top).
  EXPECT_EQ(img.pixel(0, 1)[0], 10);
  EXPECT_EQ(img.pixel(2, 0)[2], 120);
}

TEST(ImageSgi, RleAllChannelCounts) {
  for (size_t zs = 1; zs <= 4; ++zs) {
    SCOPED_TRACE(zs);
    Planes p = makePlanes(300, 5, zs);  // rows longer than one 127-pixel packet
    expectPixels(mustDecode(writeSgiRle(p)), p);
    expectPixels(mustDecode(writeSgiVerbatim(p)), p);
  }
}

TEST(ImageSgi, SixteenBitsAndDimensions) {
  Planes p = {{{0xABCD, 0x1234}, {0xFF00, 0x00FF}}, {{0x0100, 0x0200}, {0x0300, 0x0400}},
              {{0, 0xFFFF}, {0x8000, 0x7FFF}}};
  Image img = mustDecode(writeSgiVerbatim(p, 2));
  EXPECT_EQ(img.pixelFromBottom(0, 0)[0], 0xAB);  // high byte
  EXPECT_EQ(img.pixelFromBottom(1, 0)[0], 0x12);
  EXPECT_EQ(img.pixelFromBottom(1, 1)[1], 0x04);
  EXPECT_EQ(img.pixelFromBottom(1, 0)[2], 0xFF);
  EXPECT_EQ(img.pixelFromBottom(0, 1)[3], 255);

  // dimension 2: one grey channel whatever zsize says.
  Planes g = {{{5, 6, 7}, {8, 9, 10}}};
  std::vector<uint8_t> d = writeSgiVerbatim(g, 1, 2);
  expectPixels(mustDecode(d), g);
  // dimension 1: a single row.
  Planes r = {{{1, 2, 3, 4}}};
  expectPixels(mustDecode(writeSgiVerbatim(r, 1, 1)), r);
}

TEST(ImageSgi, CheckedInFile) {
  auto img = loadImage(kDir + "checker.rgb");
  ASSERT_TRUE(bool(img)) << llvm::toString(img.takeError());
  ASSERT_EQ(img->width, 2);
  ASSERT_EQ(img->height, 2);
  EXPECT_EQ(img->fileChannels, 3);
  const uint8_t expect[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(img->pixelFromBottom(x, y)[k], expect[2 * y + x][k]) << x << "," << y;
}

TEST(ImagePng, TopRowFirst) {
  // 3×2 RGBA, top row first as PNG stores it.
  const uint8_t src[2][3][4] = {{{255, 0, 0, 255}, {0, 255, 0, 128}, {0, 0, 255, 0}},
                                {{1, 2, 3, 4}, {50, 60, 70, 80}, {9, 9, 9, 9}}};
  std::vector<uint8_t> png;
  ASSERT_TRUE(stbi_write_png_to_func(sink, &png, 3, 2, 4, src, 3 * 4));
  Image img = mustDecode(png, "test.png");
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.fileChannels, 4);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int k = 0; k < 4; ++k) EXPECT_EQ(img.pixel(x, y)[k], src[y][x][k]) << x << "," << y;

  // Grey PNG, through a file.
  const uint8_t grey[2][2] = {{10, 20}, {30, 40}};
  const std::string path = testing::TempDir() + "/lcjit_image_grey.png";
  ASSERT_TRUE(stbi_write_png(path.c_str(), 2, 2, 1, grey, 2));
  auto g = loadImage(path);
  std::remove(path.c_str());
  ASSERT_TRUE(bool(g)) << llvm::toString(g.takeError());
  EXPECT_EQ(g->fileChannels, 1);
  EXPECT_EQ(g->pixel(0, 1)[0], 30);  // bottom left
  EXPECT_EQ(g->pixel(0, 1)[1], 30);
  EXPECT_EQ(g->pixel(1, 0)[2], 20);  // top right
  EXPECT_EQ(g->pixel(1, 0)[3], 255);
}

TEST(ImageJpeg, BlocksOfColour) {
  // 16×16: top half red, bottom half blue.
  std::vector<uint8_t> src(16 * 16 * 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      uint8_t* p = &src[size_t(y * 16 + x) * 3];
      p[0] = y < 8 ? 255 : 0;
      p[1] = 0;
      p[2] = y < 8 ? 0 : 255;
    }
  std::vector<uint8_t> jpg;
  ASSERT_TRUE(stbi_write_jpg_to_func(sink, &jpg, 16, 16, 3, src.data(), 95));
  Image img = mustDecode(jpg, "test.jpg");
  ASSERT_EQ(img.width, 16);
  ASSERT_EQ(img.height, 16);
  const uint8_t* bottom = img.pixel(4, 13);
  const uint8_t* top = img.pixel(4, 2);
  EXPECT_LT(bottom[0], 20);
  EXPECT_GT(bottom[2], 235);
  EXPECT_GT(top[0], 235);
  EXPECT_LT(top[2], 20);
  EXPECT_EQ(top[3], 255);
}

TEST(ImageErrors, TruncatedAndGarbage) {
  Planes p = makePlanes(20, 4, 3);
  std::vector<uint8_t> rle = writeSgiRle(p), raw = writeSgiVerbatim(p);

  std::string e = errorOf(std::vector<uint8_t>(raw.begin(), raw.begin() + 100));
  EXPECT_NE(e.find("bad.rgb: error:"), std::string::npos) << e;
  EXPECT_NE(e.find("header"), std::string::npos) << e;
  e = errorOf(std::vector<uint8_t>(raw.begin(), raw.end() - 1));
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  // Every prefix of the RLE file fails cleanly (or decodes); none crashes.
  for (size_t n = 0; n < rle.size(); n += 5)
    (void)errorOf(std::vector<uint8_t>(rle.begin(), rle.begin() + long(n)));
  e = errorOf(std::vector<uint8_t>(rle.begin(), rle.end() - 3));
  EXPECT_FALSE(e.empty());

  std::vector<uint8_t> bad = rle;
  put32(bad, 512, 0xFFFFFF00u);  // first row starts past the end
  e = errorOf(bad);
  EXPECT_NE(e.find("outside"), std::string::npos) << e;
  bad = rle;
  put32(bad, 512, 0);  // row 0 now decodes the header as RLE data
  EXPECT_FALSE(errorOf(bad).empty());
  bad = rle;
  bad[bad.size() - 1] = 0x7f;  // last row: a run that overflows, no terminator
  EXPECT_FALSE(errorOf(bad).empty());
  bad = raw;
  put16(bad, 4, 7);  // dimension 7
  EXPECT_NE(errorOf(bad).find("dimension"), std::string::npos);
  bad = raw;
  bad[3] = 3;  // 3 bytes per channel
  EXPECT_FALSE(errorOf(bad).empty());
  bad = raw;
  put16(bad, 10, 9);  // 9 channels
  EXPECT_FALSE(errorOf(bad).empty());

  std::vector<uint8_t> png;
  const uint8_t px[4] = {1, 2, 3, 4};
  ASSERT_TRUE(stbi_write_png_to_func(sink, &png, 1, 1, 4, px, 4));
  // Cut anywhere before the final IEND chunk (12 bytes), the PNG is rejected; stb accepts a
  // missing IEND since the pixels are complete. No prefix crashes.
  for (size_t n = 0; n < png.size(); ++n) {
    std::string err = errorOf(std::vector<uint8_t>(png.begin(), png.begin() + long(n)), "cut.png");
    if (n + 12 <= png.size()) {
      EXPECT_FALSE(err.empty()) << n;
    }
  }

  EXPECT_FALSE(errorOf(std::vector<uint8_t>{}).empty());
  std::vector<uint8_t> garbage(1000);
  for (size_t i = 0; i < garbage.size(); ++i) garbage[i] = uint8_t(i * 7 + 3);
  e = errorOf(garbage, "garbage.png");
  EXPECT_NE(e.find("garbage.png: error:"), std::string::npos) << e;
  e = errorOf(loadImage(kDir + "missing.png"));
  EXPECT_NE(e.find("missing.png"), std::string::npos) << e;
}

TEST(ImagePng, SixteenBitsPaletteAndTransparency) {
  // 16-bit grey: the high byte of each value, as for 16-bit SGI files (no gamma correction).
  const uint16_t grey16[2][2] = {{0xABCD, 0x1234}, {0xFF00, 0x00FF}};
  png_image w;
  std::memset(&w, 0, sizeof w);
  w.version = PNG_IMAGE_VERSION;
  w.width = 2;
  w.height = 2;
  w.format = PNG_FORMAT_LINEAR_Y;
  png_alloc_size_t n = 0;
  ASSERT_TRUE(png_image_write_to_memory(&w, nullptr, &n, 0, grey16, 0, nullptr));
  std::vector<uint8_t> png(n);
  ASSERT_TRUE(png_image_write_to_memory(&w, png.data(), &n, 0, grey16, 0, nullptr)) << w.message;
  png.resize(n);
  Image img = mustDecode(png, "grey16.png");
  EXPECT_EQ(img.fileChannels, 1);
  EXPECT_EQ(img.pixel(0, 0)[0], 0xAB);  // top row of the file = row 0
  EXPECT_EQ(img.pixel(1, 0)[1], 0x12);
  EXPECT_EQ(img.pixel(0, 1)[2], 0xFF);
  EXPECT_EQ(img.pixel(1, 1)[0], 0x00);
  EXPECT_EQ(img.pixel(1, 1)[3], 255);

  // A palette with a transparent entry: RGBA, fileChannels 4.
  const uint8_t colormap[2][4] = {{255, 0, 0, 255}, {0, 0, 255, 0}};
  const uint8_t indices[1][3] = {{0, 1, 0}};
  std::memset(&w, 0, sizeof w);
  w.version = PNG_IMAGE_VERSION;
  w.width = 3;
  w.height = 1;
  w.format = PNG_FORMAT_RGBA_COLORMAP;
  w.colormap_entries = 2;
  n = 0;
  ASSERT_TRUE(png_image_write_to_memory(&w, nullptr, &n, 0, indices, 0, colormap));
  png.assign(n, 0);
  ASSERT_TRUE(png_image_write_to_memory(&w, png.data(), &n, 0, indices, 0, colormap)) << w.message;
  png.resize(n);
  img = mustDecode(png, "palette.png");
  EXPECT_EQ(img.fileChannels, 4);
  const uint8_t red[4] = {255, 0, 0, 255}, clear[4] = {0, 0, 255, 0};
  EXPECT_EQ(std::memcmp(img.pixel(0, 0), red, 4), 0);
  EXPECT_EQ(std::memcmp(img.pixel(1, 0), clear, 4), 0);
  EXPECT_EQ(std::memcmp(img.pixel(2, 0), red, 4), 0);
}

TEST(ImagePng, HeaderClaimingMoreThanTheData) {
  // A 1×1 PNG whose IHDR (CRC fixed up) claims 30000×30000: rejected before the pixels are
  // allocated, not decoded into 3.6 GB of nothing.
  std::vector<uint8_t> png;
  const uint8_t px[4] = {1, 2, 3, 4};
  ASSERT_TRUE(stbi_write_png_to_func(sink, &png, 1, 1, 4, px, 4));
  put32(png, 16, 30000);  // IHDR data starts at 16: width, height
  put32(png, 20, 30000);
  put32(png, 29, uint32_t(crc32(0, png.data() + 12, 17)));
  std::string e = errorOf(std::vector<uint8_t>(png), "huge.png");
  EXPECT_NE(e.find("huge.png: error:"), std::string::npos) << e;
  EXPECT_NE(e.find("30000x30000"), std::string::npos) << e;
  put32(png, 16, 200);  // 200×200 RGBA from 70 bytes: still more than deflate can hold
  put32(png, 20, 200);
  put32(png, 29, uint32_t(crc32(0, png.data() + 12, 17)));
  e = errorOf(std::vector<uint8_t>(png), "huge.png");
  EXPECT_NE(e.find("larger than its data allows"), std::string::npos) << e;

  // A bad CRC in a critical chunk is an error (stb_image never checked them).
  png.clear();
  ASSERT_TRUE(stbi_write_png_to_func(sink, &png, 1, 1, 4, px, 4));
  png[29] ^= 1;
  e = errorOf(std::vector<uint8_t>(png), "crc.png");
  EXPECT_NE(e.find("crc.png: error: cannot decode PNG image:"), std::string::npos) << e;
}

TEST(ImageJpeg, CorruptHuffmanTableFinding012) {
  // birch.jpg with one byte changed: a DHT segment whose code counts add up to more than 256.
  // stb_image wrote past its Huffman table (UBSan: index 257 out of bounds); libjpeg-turbo
  // rejects the table with a clear error.
  std::string e = errorOf(loadImage(kDir + "huffman_overflow.jpg"));
  EXPECT_NE(e.find("huffman_overflow.jpg: error: cannot decode JPEG image: Bogus Huffman table definition"),
            std::string::npos)
      << e;
  // Every prefix of it fails cleanly or decodes.
  std::ifstream f(kDir + "huffman_overflow.jpg", std::ios::binary);
  std::vector<uint8_t> jpg((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  ASSERT_GT(jpg.size(), 1000u);
  for (size_t n = 0; n < jpg.size(); n += 7) {
    auto img = decodeImage(jpg.data(), n, "cut.jpg");
    if (img) EXPECT_EQ(img->rgba.size(), size_t(img->width) * size_t(img->height) * 4);
    else EXPECT_NE(llvm::toString(img.takeError()).find("cut.jpg: error:"), std::string::npos);
  }
}

TEST(ImageJpeg, EveryByteChanged) {
  // A valid JPEG with each byte replaced by 0, 0xff and itself ^ 0x10: an error naming the file,
  // or a whole picture (damaged entropy data decodes, the rest grey, as stb_image did).
  std::vector<uint8_t> src(24 * 16 * 3);
  for (size_t i = 0; i < src.size(); ++i) src[i] = uint8_t(i * 13);
  std::vector<uint8_t> jpg;
  ASSERT_TRUE(stbi_write_jpg_to_func(sink, &jpg, 24, 16, 3, src.data(), 90));
  size_t decoded = 0, failed = 0;
  for (size_t i = 2; i < jpg.size(); ++i)
    for (uint8_t v : {uint8_t(0), uint8_t(0xff), uint8_t(jpg[i] ^ 0x10)}) {
      std::vector<uint8_t> bad = jpg;
      bad[i] = v;
      auto img = decodeImage(bad.data(), bad.size(), "bad.jpg");
      if (img) {
        ++decoded;
        ASSERT_EQ(img->rgba.size(), size_t(img->width) * size_t(img->height) * 4) << i;
      } else {
        ++failed;
        ASSERT_NE(llvm::toString(img.takeError()).find("bad.jpg: error: cannot decode JPEG image: "), std::string::npos) << i;
      }
    }
  EXPECT_GT(decoded, 0u);
  EXPECT_GT(failed, 0u);
}

TEST(ImageErrors, UnknownFormat) {
  const std::string gif = "GIF89a\x01\x00\x01\x00";
  std::string e = errorOf(std::vector<uint8_t>(gif.begin(), gif.end()), "anim.gif");
  EXPECT_NE(e.find("anim.gif: error: not a PNG, JPEG or SGI (.rgb) image"), std::string::npos) << e;
}
