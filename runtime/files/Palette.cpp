// Colormap (.map) and materials (.mat) files; formats from the vlab tools manual §3 and §4.4,
// behaviour checked against lpfg (colormap.h/.cpp, material.h/.cpp, materialset.cpp, glenv.cpp).
#include "runtime/files/Palette.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "support/InputFile.h"
#include "support/ReplacingFile.h"
#include "runtime/files/TextLines.h"

#include <llvm/Support/MemoryBuffer.h>

namespace lcjit::runtime {

namespace {

constexpr size_t kColors = 256;
constexpr size_t kPageBytes = kColors * 3;  // one colormap page: 256 RGB triplets
constexpr size_t kMaterialRecord = 15;      // u8 index + 14 bytes of material

llvm::Error fileError(const std::string& path, const std::string& what) {
  return llvm::createStringError(std::make_error_code(std::errc::invalid_argument), "%s: %s",
                                 path.c_str(), what.c_str());
}

llvm::Expected<std::unique_ptr<llvm::MemoryBuffer>> readBinary(const std::string& path) {
  auto buffer = support::readInputFile(path, /*nullTerminated=*/false);
  if (!buffer)
    return llvm::createStringError(buffer.getError(), "%s: cannot read: %s", path.c_str(),
                                   buffer.getError().message().c_str());
  return std::move(*buffer);
}

std::array<float, 4> rgba(const float* c, float alpha) { return {c[0], c[1], c[2], alpha}; }

}  // namespace

Palette::Palette() {
  // lpfg's Colormap constructor: 0 black, everything else white.
  std::array<std::array<float, 4>, 256> page;
  page.fill({1, 1, 1, 1});
  page[0] = {0, 0, 0, 1};
  pages_.push_back(page);
}

Palette Palette::ega() {
  Palette p;
  auto& page = p.pages_[0];
  // The EGA's 16: each channel 0, 170 or 255 with 85 for the light ones, brown's green halved.
  static constexpr int kEga[16][3] = {{0, 0, 0},     {0, 0, 170},    {0, 170, 0},    {0, 170, 170},
                                      {170, 0, 0},   {170, 0, 170},  {170, 85, 0},   {170, 170, 170},
                                      {85, 85, 85},  {85, 85, 255},  {85, 255, 85},  {85, 255, 255},
                                      {255, 85, 85}, {255, 85, 255}, {255, 255, 85}, {255, 255, 255}};
  auto rgb = [](const int* c) { return std::array<float, 4>{c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1.0f}; };
  for (int c = 0; c < 16; ++c) page[size_t(c) + 2] = rgb(kEga[c]);
  page[1] = rgb(kEga[14]);
  // After them GroIMP's named shaders (RGBAShader's STANDARD table goes on with java.awt.Color's
  // BLACK, BLUE, CYAN, DARK_GRAY, GRAY, GREEN, LIGHT_GRAY, MAGENTA, ORANGE, PINK, RED, YELLOW,
  // WHITE), at their place in that table + 2 as well.
  static constexpr int kNamed[13][3] = {{0, 0, 0},       {0, 0, 255},   {0, 255, 255},   {64, 64, 64},   {128, 128, 128},
                                        {0, 255, 0},     {192, 192, 192}, {255, 0, 255}, {255, 200, 0},  {255, 175, 175},
                                        {255, 0, 0},     {255, 255, 0}, {255, 255, 255}};
  for (int c = 0; c < 13; ++c) page[size_t(c) + 18] = rgb(kNamed[c]);
  return p;
}

Palette Palette::lcjitDefault() {
  Palette p;
  auto& page = p.pages_[0];
  auto rgb = [](int r, int g, int b) { return std::array<float, 4>{r / 255.0f, g / 255.0f, b / 255.0f, 1.0f}; };
  const std::array<float, 4> first[] = {rgb(0, 0, 0),       rgb(255, 191, 0),  rgb(32, 208, 32),  rgb(64, 128, 255),
                                        rgb(255, 64, 64),   rgb(255, 128, 255), rgb(128, 255, 255), rgb(255, 255, 96)};
  for (size_t i = 0; i < std::size(first); ++i) page[i] = first[i];
  // Dark green → green → yellow → red over the rest, in equal steps of hue and brightness.
  const size_t from = std::size(first);
  for (size_t i = from; i < kColors; ++i) {
    const float t = float(i - from) / float(kColors - 1 - from);
    const float hue = 120.0f * (1.0f - t);  // degrees: green 120 → red 0
    const float value = 0.45f + 0.55f * std::min(1.0f, 2.0f * t);
    auto channel = [&](float n) {
      const float k = std::fmod(n + hue / 60.0f, 6.0f);
      return value - value * std::max(0.0f, std::min({k, 4.0f - k, 1.0f}));
    };
    page[i] = {channel(5), channel(3), channel(1), 1.0f};
  }
  return p;
}

llvm::Error Palette::loadColormap(const std::string& path, std::vector<std::string>* warnings) {
  auto buffer = readBinary(path);
  if (!buffer) return buffer.takeError();
  llvm::StringRef data = (*buffer)->getBuffer();
  if (data.empty()) return fileError(path, "empty colormap file (expected 768 bytes per page)");
  if (data.size() < kPageBytes)
    return fileError(path, "truncated colormap: " + std::to_string(data.size()) +
                               " bytes, a page needs 768 (256 RGB triplets)");
  size_t count = data.size() / kPageBytes;
  if (size_t extra = data.size() % kPageBytes; extra && warnings)
    warnings->push_back(path + ": warning: a colormap is pages of 768 bytes (256 RGB triplets); the " +
                        std::to_string(extra) + " bytes after page " + std::to_string(count) + " are ignored");
  std::vector<std::array<std::array<float, 4>, 256>> pages(count);
  const auto* bytes = reinterpret_cast<const uint8_t*>(data.data());
  for (size_t p = 0; p < count; ++p)
    for (size_t i = 0; i < kColors; ++i) {
      const uint8_t* c = bytes + p * kPageBytes + i * 3;
      pages[p][i] = {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1.0f};
    }
  pages_ = std::move(pages);
  page_ = 0;
  materials_.fill(Material{});
  usesMaterials_ = false;
  return llvm::Error::success();
}

llvm::Error Palette::loadMaterials(const std::string& path) {
  auto buffer = readBinary(path);
  if (!buffer) return buffer.takeError();
  llvm::StringRef data = (*buffer)->getBuffer();
  if (data.empty()) return fileError(path, "empty materials file (no 15-byte records)");
  if (data.size() % kMaterialRecord != 0)
    return fileError(path, "truncated materials file: " + std::to_string(data.size()) +
                               " bytes is not a whole number of 15-byte records (last record has " +
                               std::to_string(data.size() % kMaterialRecord) + " bytes)");
  std::array<Material, 256> materials{};
  const auto* bytes = reinterpret_cast<const uint8_t*>(data.data());
  for (size_t off = 0; off < data.size(); off += kMaterialRecord) {
    const uint8_t* r = bytes + off;
    Material& m = materials[r[0]];
    m.transparency = r[1] / 255.0f;
    float alpha = 1.0f - m.transparency;
    auto set = [&](float* dst, const uint8_t* src) {
      for (int k = 0; k < 3; ++k) dst[k] = src[k] / 255.0f;
      dst[3] = alpha;
    };
    set(m.ambient, r + 2);
    set(m.diffuse, r + 5);
    set(m.emission, r + 8);
    set(m.specular, r + 11);
    m.shininess = r[14];
  }
  materials_ = materials;
  usesMaterials_ = true;
  return llvm::Error::success();
}

std::array<float, 4> Palette::color(int index) const {
  index = std::clamp(index, 0, 255);
  if (!usesMaterials_) return pages_[page_][index];
  const Material& m = materials_[index];
  return index == 0 ? rgba(m.emission, m.emission[3]) : rgba(m.diffuse, m.diffuse[3]);
}

std::array<float, 4> Palette::textColor(int index) const {
  index = std::clamp(index, 0, 255);
  if (!usesMaterials_) return pages_[page_][index];
  const Material& m = materials_[index];
  return rgba(m.emission, m.emission[3]);
}

const Material& Palette::material(int index) const {
  return materials_[std::clamp(index, 0, 255)];
}

void Palette::selectPage(int page) { page_ = std::clamp(page, 0, (int)pages_.size() - 1); }

// ---------------------------------------------------------------------------------------------
// The editors' files

namespace {
llvm::Expected<std::vector<uint8_t>> fileBytes(const std::string& path) {
  auto buffer = readBinary(path);
  if (!buffer) return buffer.takeError();
  llvm::StringRef data = (*buffer)->getBuffer();
  return std::vector<uint8_t>(data.bytes_begin(), data.bytes_end());
}
std::string asString(const std::vector<uint8_t>& bytes) { return std::string(bytes.begin(), bytes.end()); }
uint8_t toByte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }
}  // namespace

llvm::Expected<ColormapFile> ColormapFile::read(const std::string& path) {
  auto bytes = fileBytes(path);
  if (!bytes) return bytes.takeError();
  if (bytes->size() < kPageBytes)
    return fileError(path, "not a colormap: " + std::to_string(bytes->size()) + " bytes, a page needs 768");
  ColormapFile f;
  f.bytes_ = std::move(*bytes);
  return f;
}

ColormapFile ColormapFile::fromPalette(const Palette& palette) {
  ColormapFile f;
  f.bytes_.resize(kPageBytes);
  for (size_t i = 0; i < kColors; ++i) {
    const auto c = palette.color(int(i));
    f.setColor(int(i), {toByte(c[0]), toByte(c[1]), toByte(c[2])});
  }
  return f;
}

std::array<uint8_t, 3> ColormapFile::color(int index) const {
  const size_t at = size_t(std::clamp(index, 0, 255)) * 3;
  return {bytes_[at], bytes_[at + 1], bytes_[at + 2]};
}

void ColormapFile::setColor(int index, std::array<uint8_t, 3> rgb) {
  const size_t at = size_t(std::clamp(index, 0, 255)) * 3;
  std::copy(rgb.begin(), rgb.end(), bytes_.begin() + at);
}

llvm::Error ColormapFile::write(const std::string& path) const { return support::writeWholeFile(path, asString(bytes_)); }

llvm::Expected<MaterialFile> MaterialFile::read(const std::string& path) {
  auto bytes = fileBytes(path);
  if (!bytes) return bytes.takeError();
  if (bytes->empty() || bytes->size() % kMaterialRecord)
    return fileError(path, "not a materials file: " + std::to_string(bytes->size()) + " bytes are not whole 15-byte records");
  MaterialFile f;
  f.bytes_ = std::move(*bytes);
  return f;
}

MaterialRecord MaterialFile::record(int index) const {
  for (size_t off = bytes_.size(); off >= kMaterialRecord; off -= kMaterialRecord)
    if (bytes_[off - kMaterialRecord] == index) {
      MaterialRecord r;
      std::copy_n(bytes_.begin() + long(off - kMaterialRecord + 1), r.size(), r.begin());
      return r;
    }
  const Material m;
  MaterialRecord r{};
  r[0] = toByte(m.transparency);
  for (int k = 0; k < 3; ++k) {
    r[1 + k] = toByte(m.ambient[k]);
    r[4 + k] = toByte(m.diffuse[k]);
    r[7 + k] = toByte(m.emission[k]);
    r[10 + k] = toByte(m.specular[k]);
  }
  r[13] = toByte(m.shininess / 255.0f);
  return r;
}

void MaterialFile::setRecord(int index, const MaterialRecord& record) {
  index = std::clamp(index, 0, 255);
  for (size_t off = bytes_.size(); off >= kMaterialRecord; off -= kMaterialRecord)
    if (bytes_[off - kMaterialRecord] == index) {
      std::copy(record.begin(), record.end(), bytes_.begin() + long(off - kMaterialRecord + 1));
      return;
    }
  bytes_.push_back(uint8_t(index));
  bytes_.insert(bytes_.end(), record.begin(), record.end());
}

llvm::Error MaterialFile::write(const std::string& path) const { return support::writeWholeFile(path, asString(bytes_)); }

}  // namespace lcjit::runtime
