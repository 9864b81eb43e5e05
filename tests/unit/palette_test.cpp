// Colormap (.map) and materials (.mat) loading (runtime/files/Palette): lpfg's defaults, pages,
// the binary material record, errors on short/empty files.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

#include "runtime/files/Palette.h"

using namespace lcjit::runtime;

namespace {

std::string writeFile(const std::string& name, const std::vector<uint8_t>& bytes) {
  std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "lcjit_palette_test";
  std::filesystem::create_directories(dir);
  std::string path = (dir / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  return path;
}

std::string errorText(llvm::Error e) { return e ? llvm::toString(std::move(e)) : std::string(); }
#define ASSERT_LOADS(expr) ASSERT_EQ(errorText(expr), "")

#define EXPECT_RGBA(c, R, G, B, A)  \
  do {                              \
    auto c_ = (c);                  \
    EXPECT_FLOAT_EQ(c_[0], (R));    \
    EXPECT_FLOAT_EQ(c_[1], (G));    \
    EXPECT_FLOAT_EQ(c_[2], (B));    \
    EXPECT_FLOAT_EQ(c_[3], (A));    \
  } while (0)

// A colormap page whose colour i is (i, 255 - i, 7 * i mod 256) plus `shift` on red.
std::vector<uint8_t> page(int shift) {
  std::vector<uint8_t> bytes;
  for (int i = 0; i < 256; ++i) {
    bytes.push_back(uint8_t((i + shift) & 255));
    bytes.push_back(uint8_t(255 - i));
    bytes.push_back(uint8_t((7 * i) & 255));
  }
  return bytes;
}

}  // namespace

TEST(PaletteDefaults, LpfgDefaultColormap) {
  Palette p;
  EXPECT_FALSE(p.usesMaterials());
  EXPECT_EQ(p.pageCount(), 1);
  EXPECT_RGBA(p.background(), 0, 0, 0, 1);
  EXPECT_RGBA(p.color(0), 0, 0, 0, 1);
  EXPECT_RGBA(p.color(1), 1, 1, 1, 1);
  EXPECT_RGBA(p.color(255), 1, 1, 1, 1);
  EXPECT_RGBA(p.color(-5), 0, 0, 0, 1);   // clamped to 0
  EXPECT_RGBA(p.color(999), 1, 1, 1, 1);  // clamped to 255
  const Material& m = p.material(3);
  EXPECT_FLOAT_EQ(m.ambient[0], 0.2f);
  EXPECT_FLOAT_EQ(m.diffuse[1], 0.8f);
  EXPECT_FLOAT_EQ(m.specular[2], 0);
  EXPECT_FLOAT_EQ(m.emission[3], 1);
  EXPECT_FLOAT_EQ(m.shininess, 0);
  EXPECT_FLOAT_EQ(m.transparency, 0);
}

TEST(PaletteColormap, TwoPages) {
  std::vector<uint8_t> bytes = page(0), second = page(100);
  bytes.insert(bytes.end(), second.begin(), second.end());
  ASSERT_EQ(bytes.size(), 1536u);
  Palette p;
  ASSERT_LOADS(p.loadColormap(writeFile("two.map", bytes)));
  EXPECT_FALSE(p.usesMaterials());
  EXPECT_EQ(p.pageCount(), 2);
  EXPECT_EQ(p.page(), 0);
  EXPECT_RGBA(p.background(), 0, 1, 0, 1);                          // (0, 255, 0)
  EXPECT_RGBA(p.color(2), 2 / 255.f, 253 / 255.f, 14 / 255.f, 1);
  EXPECT_RGBA(p.color(40), 40 / 255.f, 215 / 255.f, 24 / 255.f, 1);  // 280 & 255 = 24
  EXPECT_RGBA(p.textColor(40), 40 / 255.f, 215 / 255.f, 24 / 255.f, 1);
  p.selectPage(1);
  EXPECT_EQ(p.page(), 1);
  EXPECT_RGBA(p.color(2), 102 / 255.f, 253 / 255.f, 14 / 255.f, 1);
  EXPECT_RGBA(p.color(200), 44 / 255.f, 55 / 255.f, 120 / 255.f, 1);  // 300&255, 255-200, 1400&255
  p.selectPage(7);  // clamped
  EXPECT_EQ(p.page(), 1);
  p.selectPage(0);
  EXPECT_RGBA(p.color(2), 2 / 255.f, 253 / 255.f, 14 / 255.f, 1);
}

TEST(PaletteColormap, TrailingBytesIgnored) {
  std::vector<uint8_t> bytes = page(5);
  bytes.resize(768 + 100, 9);
  Palette p;
  std::vector<std::string> warnings;
  const std::string path = writeFile("trailing.map", bytes);
  ASSERT_LOADS(p.loadColormap(path, &warnings));
  // Said, not silently dropped.
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], path + ": warning: a colormap is pages of 768 bytes (256 RGB triplets); the 100 bytes after page 1 are ignored");
  EXPECT_EQ(p.pageCount(), 1);
  EXPECT_RGBA(p.color(255), 4 / 255.f, 0, (7 * 255 & 255) / 255.f, 1);
}

TEST(PaletteColormap, Errors) {
  Palette p;
  std::string missing = (std::filesystem::path(::testing::TempDir()) / "no_such_dir" / "x.map").string();
  std::string msg = errorText(p.loadColormap(missing));
  EXPECT_NE(msg.find("x.map"), std::string::npos) << msg;

  std::string empty = writeFile("empty.map", {});
  msg = errorText(p.loadColormap(empty));
  EXPECT_NE(msg.find("empty.map"), std::string::npos) << msg;
  EXPECT_NE(msg.find("empty"), std::string::npos) << msg;

  std::vector<uint8_t> shortMap = page(0);
  shortMap.resize(700);
  std::string shortPath = writeFile("short.map", shortMap);
  msg = errorText(p.loadColormap(shortPath));
  EXPECT_NE(msg.find("short.map"), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  EXPECT_NE(msg.find("700"), std::string::npos) << msg;
  // Nothing changed.
  EXPECT_EQ(p.pageCount(), 1);
  EXPECT_RGBA(p.color(0), 0, 0, 0, 1);
  EXPECT_RGBA(p.color(1), 1, 1, 1, 1);
}

TEST(PaletteMaterials, RoundTripHandComputedBytes) {
  // Records: index, transparency, ambient rgb, diffuse rgb, emission rgb, specular rgb, shininess.
  std::vector<uint8_t> bytes = {
      3, 51, 51, 102, 153, 255, 0, 128, 10, 20, 30, 255, 255, 255, 64,  //
      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 0, 0,                     // background: blue emission
      9, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13,                   //
      9, 255, 0, 0, 0, 255, 255, 255, 0, 0, 0, 0, 0, 0, 128,             // a later record wins
  };
  ASSERT_EQ(bytes.size(), 60u);
  Palette p;
  ASSERT_LOADS(p.loadMaterials(writeFile("m.mat", bytes)));
  EXPECT_TRUE(p.usesMaterials());

  const Material& m = p.material(3);
  EXPECT_FLOAT_EQ(m.transparency, 0.2f);
  EXPECT_FLOAT_EQ(m.ambient[0], 0.2f);
  EXPECT_FLOAT_EQ(m.ambient[1], 0.4f);
  EXPECT_FLOAT_EQ(m.ambient[2], 0.6f);
  EXPECT_FLOAT_EQ(m.ambient[3], 0.8f);
  EXPECT_FLOAT_EQ(m.diffuse[0], 1);
  EXPECT_FLOAT_EQ(m.diffuse[1], 0);
  EXPECT_FLOAT_EQ(m.diffuse[2], 128 / 255.f);
  EXPECT_FLOAT_EQ(m.emission[0], 10 / 255.f);
  EXPECT_FLOAT_EQ(m.emission[2], 30 / 255.f);
  EXPECT_FLOAT_EQ(m.emission[3], 0.8f);
  EXPECT_FLOAT_EQ(m.specular[1], 1);
  EXPECT_FLOAT_EQ(m.specular[3], 0.8f);
  EXPECT_FLOAT_EQ(m.shininess, 64);
  // Flat colour: the diffuse; text: the emission; background: material 0's emission.
  EXPECT_RGBA(p.color(3), 1, 0, 128 / 255.f, 0.8f);
  EXPECT_RGBA(p.textColor(3), 10 / 255.f, 20 / 255.f, 30 / 255.f, 0.8f);
  EXPECT_RGBA(p.background(), 0, 0, 1, 1);
  EXPECT_RGBA(p.color(0), 0, 0, 1, 1);

  const Material& n = p.material(9);
  EXPECT_FLOAT_EQ(n.transparency, 1);
  EXPECT_FLOAT_EQ(n.ambient[0], 0);
  EXPECT_FLOAT_EQ(n.diffuse[0], 1);
  EXPECT_FLOAT_EQ(n.diffuse[3], 0);
  EXPECT_FLOAT_EQ(n.shininess, 128);

  // Unlisted indices: lpfg's default material.
  EXPECT_RGBA(p.color(200), 0.8f, 0.8f, 0.8f, 1);
  EXPECT_FLOAT_EQ(p.material(200).ambient[0], 0.2f);

  // Switching back to a colormap.
  ASSERT_LOADS(p.loadColormap(writeFile("after.map", page(0))));
  EXPECT_FALSE(p.usesMaterials());
  EXPECT_RGBA(p.color(3), 3 / 255.f, 252 / 255.f, 21 / 255.f, 1);
  EXPECT_FLOAT_EQ(p.material(3).shininess, 0);
}

TEST(PaletteMaterials, Errors) {
  Palette p;
  std::string msg = errorText(p.loadMaterials(writeFile("empty.mat", {})));
  EXPECT_NE(msg.find("empty.mat"), std::string::npos) << msg;

  std::vector<uint8_t> bytes(20, 7);  // one record and 5 bytes of the next
  msg = errorText(p.loadMaterials(writeFile("short.mat", bytes)));
  EXPECT_NE(msg.find("short.mat"), std::string::npos) << msg;
  EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
  EXPECT_FALSE(p.usesMaterials());
  EXPECT_FLOAT_EQ(p.material(7).ambient[0], 0.2f);

  msg = errorText(p.loadMaterials("/nonexistent/dir/x.mat"));
  EXPECT_NE(msg.find("x.mat"), std::string::npos) << msg;
}

// The editors' colour files: unchanged, the bytes read; changed, what Palette then reads.
TEST(ColourFiles, ColormapRoundTripAndEdit) {
  std::vector<uint8_t> bytes = page(0);
  std::vector<uint8_t> second = page(9);
  bytes.insert(bytes.end(), second.begin(), second.end());
  bytes.push_back(42);  // a stray byte after the last page stays too
  std::string path = writeFile("edit.map", bytes);
  auto f = ColormapFile::read(path);
  ASSERT_TRUE(bool(f)) << llvm::toString(f.takeError());
  EXPECT_EQ(f->bytes(), bytes);
  std::string copy = writeFile("edit-copy.map", {});
  ASSERT_LOADS(f->write(copy));
  auto back = ColormapFile::read(copy);
  ASSERT_TRUE(bool(back));
  EXPECT_EQ(back->bytes(), bytes);
  EXPECT_EQ(f->color(5), (std::array<uint8_t, 3>{5, 250, 35}));
  f->setColor(5, {10, 20, 30});
  ASSERT_LOADS(f->write(copy));
  Palette p;
  ASSERT_LOADS(p.loadColormap(copy));
  EXPECT_RGBA(p.color(5), 10 / 255.0f, 20 / 255.0f, 30 / 255.0f, 1);
  EXPECT_RGBA(p.color(6), 6 / 255.0f, 249 / 255.0f, 42 / 255.0f, 1);  // the others as they were
  EXPECT_FALSE(bool(ColormapFile::read(writeFile("short.map", std::vector<uint8_t>(700)))));
}

TEST(ColourFiles, MaterialsRoundTripAndEdit) {
  // Index 3 twice (the later record wins, in lpfg and in the editor), then index 7.
  std::vector<uint8_t> bytes;
  auto record = [&](uint8_t index, uint8_t base) {
    bytes.push_back(index);
    for (int k = 0; k < 14; ++k) bytes.push_back(uint8_t(base + k));
  };
  record(3, 10);
  record(7, 50);
  record(3, 100);
  std::string path = writeFile("edit.mat", bytes);
  auto f = MaterialFile::read(path);
  ASSERT_TRUE(bool(f)) << llvm::toString(f.takeError());
  std::string copy = writeFile("edit-copy.mat", {});
  ASSERT_LOADS(f->write(copy));
  auto back = MaterialFile::read(copy);
  ASSERT_TRUE(bool(back));
  EXPECT_EQ(back->bytes(), bytes);
  EXPECT_EQ(f->record(3)[0], 100);
  EXPECT_EQ(f->record(1)[4], 204);  // unlisted: Material{}'s diffuse 0.8
  MaterialRecord r = f->record(3);
  r[4] = 255, r[5] = 0, r[6] = 0;  // diffuse red
  f->setRecord(3, r);
  r[0] = 0;
  f->setRecord(9, r);  // not in the file: appended
  EXPECT_EQ(f->bytes().size(), bytes.size() + 15);
  EXPECT_TRUE(std::equal(bytes.begin(), bytes.begin() + 30, f->bytes().begin()));  // earlier records untouched
  ASSERT_LOADS(f->write(copy));
  Palette p;
  ASSERT_LOADS(p.loadMaterials(copy));
  EXPECT_FLOAT_EQ(p.material(3).diffuse[0], 1);
  EXPECT_FLOAT_EQ(p.material(3).diffuse[1], 0);
  EXPECT_FLOAT_EQ(p.material(9).diffuse[0], 1);
  EXPECT_FLOAT_EQ(p.material(7).ambient[0], 51 / 255.0f);  // after the index: transparency 50, ambient 51…
}

// A model without a colour file in the window: not lpfg's white on black.
TEST(PaletteDefaults, LcjitDefaultIsNotWhiteOnBlack) {
  Palette p = Palette::lcjitDefault();
  EXPECT_FALSE(p.usesMaterials());
  EXPECT_RGBA(p.background(), 0, 0, 0, 1);  // lpfg's and vlab's usual background
  std::set<std::array<float, 4>> firstSeven;
  for (int i = 1; i < 256; ++i) {
    auto c = p.color(i);
    EXPECT_FALSE(c[0] == 1 && c[1] == 1 && c[2] == 1) << i;
    EXPECT_GT(c[0] + c[1] + c[2], 0.3f) << i;  // visible on the background
    if (i < 8) firstSeven.insert(c);
  }
  EXPECT_EQ(firstSeven.size(), 7u);  // the first indices tell parts apart
  ColormapFile f = ColormapFile::fromPalette(p);
  EXPECT_EQ(f.bytes().size(), 768u);
  EXPECT_EQ(f.color(2), (std::array<uint8_t, 3>{32, 208, 32}));
}
