// Label text for every output: UTF-8 decoded, faces picked by fontconfig (the view file's
// `winfont:` first, other faces for the characters it lacks), shaped by HarfBuzz, glyphs drawn by
// FreeType — as bitmaps for the renderer, as outlines for the vector exports.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lcjit::runtime::text {

// What the view file's `winfont:` asks for; `file` (a font file) overrides the family when set.
struct FontSpec {
  std::string family = "Times";
  int weight = 50;  // Qt's scale: 50 regular, 75 bold
  bool italic = false;
  std::string file;
  // The face's kerning pairs, as Qt's QFont applies them by default. A face that Qt reads from
  // its Type 1 file (Times: Nimbus Roman, foundry urw) has none there, and is laid out unkerned.
  bool kerning = true;
  bool operator==(const FontSpec&) const = default;
};

// The label em in picture pixels for `winfont:`'s point size: Qt's at 96 dpi, as lpfg's labels.
int pixelSizeForPoints(int points);

// UTF-8 to code points; a byte that does not start a valid sequence becomes U+FFFD (as Qt's
// QString::fromUtf8 does with lpfg's labels).
std::u32string decodeUtf8(std::string_view utf8);
// The same text re-encoded: valid UTF-8 whatever the input, without the characters XML 1.0
// forbids (controls but tab and newline, U+FFFE, U+FFFF).
std::string cleanUtf8(std::string_view utf8, bool forXml = false);

// One glyph of a shaped label: glyph `glyph` of face `face` (Fonts' numbering), its pen position
// in pixels from the label's origin on the baseline, y down.
struct PlacedGlyph {
  int face = 0;
  uint32_t glyph = 0;
  float x = 0, y = 0;
};
struct ShapedText {
  std::vector<PlacedGlyph> glyphs;
  float advance = 0;  // the pen's travel, pixels
};

// A glyph's outline in pixels, origin at the pen, y down. Quadratic pieces are raised to cubics.
struct GlyphOutline {
  enum Op : uint8_t { Move, Line, Cubic, Close };
  std::vector<Op> ops;
  std::vector<float> xy;  // Move/Line: 1 point, Cubic: 3, Close: none
  bool empty() const { return ops.empty(); }
};

// Coverage (0–255), `left`/`top` from the pen to the bitmap's top-left corner (top: y up).
struct GlyphBitmap {
  int left = 0, top = 0, width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width × height, rows top down
};

// The faces, their shaping and drawing. One per process (shared()), safe from any thread.
class Fonts {
 public:
  static Fonts& shared();

  // `utf8` at an em of `pixelSize` pixels, with kerning, ligatures and marks as the face's
  // OpenType tables place them. A character no installed face has is the primary face's .notdef.
  ShapedText shape(std::string_view utf8, const FontSpec& spec, float pixelSize);
  // The face a spec's labels are drawn with (fontconfig's match, as Qt's for lpfg).
  std::string primaryFile(const FontSpec& spec);
  std::string faceFile(int face);

  GlyphOutline outline(int face, uint32_t glyph, float pixelSize);
  // Light-hinted at an em of `pixelSize`, the outline moved `shift` pixels right first (Qt's
  // subpixel positions). False when FreeType cannot draw it.
  bool bitmap(int face, uint32_t glyph, int pixelSize, float shift, GlyphBitmap& out);

  // Unkerned advance of one glyph in pixels (the tests compare it with shaped advances).
  float glyphAdvance(int face, uint32_t glyph, float pixelSize);

  struct Impl;
  ~Fonts();

 private:
  Fonts();
  Impl* impl_;
};

}  // namespace lcjit::runtime::text
