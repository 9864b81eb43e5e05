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
  // its Type 1 file (Times: Nimbus Roman, foundry urw) has no OpenType tables there, and is laid
  // out unkerned and without ligatures whatever this says.
  bool kerning = true;
  bool operator==(const FontSpec&) const = default;
};

// The label em in picture pixels for `winfont:`'s point size: Qt's at 96 dpi, as lpfg's labels.
int pixelSizeForPoints(int points);

// Pen positions are in 1/64 pixel, as Qt's text layout keeps them (its fixed-point QFixed): each
// glyph advances by its unhinted width truncated to 1/64, HarfBuzz's kerning and marks are scaled
// to 1/64 too. PlacedGlyph::x and ShapedText::advance are exact multiples of 1/64.
constexpr int kPenUnits = 64;

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
  // The glyph as a picture draws it (the rules of RasterLabel below) at an em of `pixelSize`,
  // for a pen `phase` steps of 1/subpixelSteps(pixelSize) pixel into its pixel. False when
  // FreeType cannot draw it.
  bool bitmap(int face, uint32_t glyph, int pixelSize, int phase, GlyphBitmap& out);
  // A label's coverage as lpfg's pixmap holds it (RasterLabel below): its glyphs composited as Qt
  // composites them (a pixel's coverage a, then b over it: b + a·(255 − b)/255, premultiply()'s
  // rounding), cut to the pixmap; left/top is the pixmap's corner from the anchor's pixel (top: y
  // up). `shaped` is the label at pixelSizeForPoints(points).
  GlyphBitmap labelBitmap(const ShapedText& shaped, int points);

  // Unkerned advance of one glyph in pixels (the tests compare it with shaped advances).
  float glyphAdvance(int face, uint32_t glyph, float pixelSize);

  struct Impl;
  ~Fonts();

 private:
  Fonts();
  Impl* impl_;
};

// --- Labels in pictures: how lpfg's labels come out of Qt 5 (X11, fontconfig, FreeType) -------
//
// lpfg draws each label with QPainter::drawText into a transparent pixmap of its own and lays
// the pixmap over the view; lcjit draws the same pixels by these rules:
//  - the pixmap: `points + points/3 + 1` rows, the baseline `points` rows down (`points` is
//    winfont:'s size, not the em in pixels, so the top of tall glyphs can be cut off), and
//    round(advance) + 10 columns with the pen starting 5 in; glyph pixels outside it are lost.
//    Its left end is 5 px left of the anchor's pixel, its baseline 2 px below it;
//  - glyphs of an em up to 64 px come from Qt's glyph cache: FreeType's light hinting (fontconfig's
//    "hintslight", which Qt follows) and light rendering, each glyph drawn at its pen's whole
//    pixel with its outline moved right by the pen's fraction rounded down to a quarter pixel,
//    plus 1/64 pixel (Qt adds it to every pen not at x = 0, and lpfg's pens start at 5);
//  - larger glyphs are filled as unhinted outlines at the pen's exact position (1/64 pixel);
//  - the colour is each of the label colour's components as a byte, (int)(c * 255); a pixel's
//    premultiplied colour is Qt's rounded product colour × coverage / 255 (premultiply()), and
//    the pixmap is blended over the view as premultiplied colour;
//  - lpfg leaves the alpha test on (alpha > 0.1), and a pixel of the pixmap whose coverage is
//    26/255 or less is not drawn at all (kMinDrawnCoverage: measured, lpfg's pictures drop 26 too,
//    the test's 0.1 being compared in 8 bits).

// Pen fractions per pixel at an em of `pixelSize`: 4 (Qt's glyph cache), 64 beyond 64 px.
int subpixelSteps(int pixelSize);
constexpr int kMinDrawnCoverage = 27;

// One byte of a label colour component, as lpfg hands it to Qt.
inline int colorByte(float c) { return int(c * 255); }
// Qt's product of two bytes, x·a/255 rounded its way (its BYTE_MUL).
inline int premultiply(int x, int a) {
  int t = x * a;
  return (t + (t >> 8) + 0x80) >> 8;
}

struct RasterGlyph {
  int face = 0;
  uint32_t glyph = 0;
  int phase = 0;    // Fonts::bitmap's phase
  int x = 0, y = 0; // the pen's whole pixel and baseline row, from the anchor's pixel (y down)
};
struct RasterLabel {
  std::vector<RasterGlyph> glyphs;
  int left = 0, top = 0, right = 0, bottom = 0;  // lpfg's pixmap from the anchor's pixel, right and bottom excluded
};
// Where a shaped label's glyphs fall in a picture, for `winfont:`'s size `points`.
RasterLabel rasterLabel(const ShapedText& shaped, int points);

}  // namespace lcjit::runtime::text
