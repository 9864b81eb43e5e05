// Colours for colour/material indices 0..255: a colormap (.map, binary RGB, possibly several
// pages) or a materials file (.mat). Index 0 is the background.
// lpfg: one colour file, chosen by its extension on the command line (the last one given wins);
// without one it is in colormap mode with index 0 black and 1..255 white. In colormap mode lpfg
// draws unlit with glColor (lights unused); in materials mode lighting is always on
// (glMaterial, two-sided) and the background is material 0's emission.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <llvm/Support/Error.h>

namespace lcjit::runtime {

// A default-constructed Material is lpfg's (and OpenGL's) default, used for every index a .mat
// file does not list.
struct Material {
  float ambient[4] = {0.2f, 0.2f, 0.2f, 1};
  float diffuse[4] = {0.8f, 0.8f, 0.8f, 1};
  float specular[4] = {0, 0, 0, 1};
  float emission[4] = {0, 0, 0, 1};
  float shininess = 0;     // the file's byte as is (0..255; medit writes 0..128)
  float transparency = 0;  // 0 opaque .. 1; every colour's alpha above is 1 - transparency
};

class Palette {
 public:
  Palette();  // lpfg's default colours when no .map/.mat is given
  // lcjit's colours for a model without a colour file in the window (docs/editors.md): lpfg's
  // black background, as vlab's colormaps nearly all keep it, and the colours those colormaps
  // most often give the first indices (1 warm, 2 green, then distinct hues), a ramp from dark
  // green through yellow to red from index 8 on (the gradients models index into), instead of
  // lpfg's white for every index.
  static Palette lcjitDefault();
  // The 16 colours of IBM's EGA, which GroIMP's turtle indexes (its colour c, 0 black … 14 yellow
  // … 15 white) and the XL quick reference lists: colour c is index c + 2; index 1, where lcjit's
  // turtle starts, is GroIMP's turtle's own colour, 14; index 0 the background, black. Indices
  // 18 to 30 are GroIMP's named shaders, BLACK … WHITE (java.awt.Color's), its STANDARD table's
  // 16 to 28.
  static Palette ega();

  // .map: 256 × RGB bytes per page; every page becomes a colormap (page 0 active). lpfg itself
  // reads only the first 768 bytes. Fewer than 768 bytes is an error; bytes after the last whole
  // page are ignored, with a warning into `warnings` ("FILE: warning: …"). Switches
  // to colormap mode. On error nothing changes.
  llvm::Error loadColormap(const std::string& path, std::vector<std::string>* warnings = nullptr);
  // .mat: binary materials (vlab tools manual §4.4): 15-byte records {u8 index, u8 transparency,
  // u8 ambient[3], diffuse[3], emission[3], specular[3], u8 shininess}, colours /255, later
  // records win. Unlisted indices get Material{}. An empty file or a partial record is an error.
  // Switches to materials mode. On error nothing changes.
  llvm::Error loadMaterials(const std::string& path);

  bool usesMaterials() const { return usesMaterials_; }
  // The colour a flat (unlit) drawing uses for `index` (clamped to 0..255): the colormap colour
  // (alpha 1), or as lpfg's GLEnv::GetSolidColor: the material's diffuse, for index 0 its
  // emission (alpha 1 - transparency).
  std::array<float, 4> color(int index) const;
  // lpfg's text (label) colour: the colormap colour, or the material's emission.
  std::array<float, 4> textColor(int index) const;
  const Material& material(int index) const;  // Material{} entries in colormap mode
  std::array<float, 4> background() const { return color(0); }

  int pageCount() const { return (int)pages_.size(); }
  void selectPage(int page);  // clamped to the pages there are
  int page() const { return page_; }

 private:
  std::vector<std::array<std::array<float, 4>, 256>> pages_;
  int page_ = 0;
  std::array<Material, 256> materials_;
  bool usesMaterials_ = false;
};

// The colour files as vlab's palette and medit edit them: the file's bytes, changed in place, so
// that a file written without a change is the file read, with any further pages of a colormap
// and every record of a materials file (a later record for the same index included).
class ColormapFile {
 public:
  // A file of at least one page (768 bytes).
  static llvm::Expected<ColormapFile> read(const std::string& path);
  // One page of `palette`'s current colours: a colormap for a model that had none.
  static ColormapFile fromPalette(const Palette& palette);
  // Page 0, the page lpfg reads.
  std::array<uint8_t, 3> color(int index) const;
  void setColor(int index, std::array<uint8_t, 3> rgb);
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  llvm::Error write(const std::string& path) const;

 private:
  std::vector<uint8_t> bytes_;
};

// A material as its 14 bytes after the index: transparency, ambient RGB, diffuse RGB, emission
// RGB, specular RGB, shininess (vlab tools manual §4.4).
using MaterialRecord = std::array<uint8_t, 14>;

class MaterialFile {
 public:
  // A file of whole 15-byte records, at least one.
  static llvm::Expected<MaterialFile> read(const std::string& path);
  // The record lpfg uses for `index` (the last one for it), else Material{}'s bytes.
  MaterialRecord record(int index) const;
  // Changes the last record for `index`, or appends one.
  void setRecord(int index, const MaterialRecord& record);
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  llvm::Error write(const std::string& path) const;

 private:
  std::vector<uint8_t> bytes_;
};

}  // namespace lcjit::runtime
