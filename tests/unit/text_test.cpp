// Label text (runtime/text/LabelText.h): UTF-8 decoding, a face for every character (fontconfig's
// fallbacks), HarfBuzz's kerning and marks, FreeType's outlines and bitmaps. Needs the fonts
// setup.sh installs (DejaVu, the URW base 35, Droid Sans Fallback for CJK).
#include <gtest/gtest.h>

#include <algorithm>

#include "runtime/text/LabelText.h"

using namespace lcjit::runtime::text;

namespace {

const char* const kMixed = "\xc3\xa9 \xc3\xbc \xc3\x9f \xce\xa9 \xe6\x9c\xa8";  // "é ü ß Ω 木"
const char* const kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

TEST(Text, DecodeUtf8) {
  EXPECT_EQ(decodeUtf8(kMixed), std::u32string(U"\u00e9 \u00fc \u00df \u03a9 \u6728"));
  EXPECT_EQ(decodeUtf8("a\xf0\x9f\x8c\xb1"), std::u32string(U"a\U0001F331"));  // 4 bytes
  // Bytes that are no UTF-8 (Latin-1 "é", a lone continuation, an overlong "/", a surrogate)
  // each become U+FFFD; what follows them is read again.
  EXPECT_EQ(decodeUtf8("\xe9t\x80" "a\xc0\xaf" "b\xed\xa0\x80"),
            std::u32string(U"\ufffdt\ufffda\ufffd\ufffdb\ufffd\ufffd\ufffd"));
  EXPECT_EQ(decodeUtf8("\xe6\x9c"), std::u32string(U"\ufffd\ufffd"));  // cut short
  EXPECT_EQ(cleanUtf8("\xe9t"), "\xef\xbf\xbdt");
  EXPECT_EQ(cleanUtf8("a\x01\tb", true), "a\tb");
  EXPECT_EQ(cleanUtf8(kMixed), kMixed);
}

// Every character of a mixed label gets a real glyph (never .notdef, glyph 0): Times (Nimbus
// Roman) has the Latin and Greek ones, a fallback face the CJK one.
TEST(Text, FallbackFaces) {
  Fonts& fonts = Fonts::shared();
  FontSpec times;
  ShapedText t = fonts.shape(kMixed, times, 16);
  ASSERT_EQ(t.glyphs.size(), 9u);  // five characters, four spaces
  for (const PlacedGlyph& g : t.glyphs) EXPECT_NE(g.glyph, 0u) << "face " << fonts.faceFile(g.face);
  const std::string primary = fonts.primaryFile(times);
  EXPECT_EQ(fonts.faceFile(t.glyphs[0].face), primary);
  EXPECT_NE(fonts.faceFile(t.glyphs[8].face), primary);  // 木 is not in a Latin face
  // Pens move right, and each drawn glyph has an outline.
  for (size_t i = 1; i < t.glyphs.size(); ++i) EXPECT_GT(t.glyphs[i].x, t.glyphs[i - 1].x);
  for (size_t i = 0; i < t.glyphs.size(); i += 2) EXPECT_FALSE(fonts.outline(t.glyphs[i].face, t.glyphs[i].glyph, 16).empty()) << i;
  // A character no face has is the primary face's .notdef, not dropped and not '?'.
  ShapedText none = fonts.shape("\xf4\x8f\xbf\xbd", times, 16);  // U+10FFFD, private use
  ASSERT_EQ(none.glyphs.size(), 1u);
  EXPECT_EQ(none.glyphs[0].glyph, 0u);
}

// HarfBuzz applies the face's kerning: "AV" is narrower than A's and V's advances together.
TEST(Text, Kerning) {
  Fonts& fonts = Fonts::shared();
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  ShapedText av = fonts.shape("AV", dejavu, 100);
  ASSERT_EQ(av.glyphs.size(), 2u);
  float a = fonts.glyphAdvance(av.glyphs[0].face, av.glyphs[0].glyph, 100);
  float v = fonts.glyphAdvance(av.glyphs[1].face, av.glyphs[1].glyph, 100);
  EXPECT_GT(a, 50);
  EXPECT_LT(av.advance, a + v - 1);  // DejaVu Sans kerns A-V by several units of 100
  EXPECT_LT(av.glyphs[1].x, a - 1);
  // Without a kerning pair nothing changes: "HH" is two H advances.
  ShapedText hh = fonts.shape("HH", dejavu, 100);
  float h = fonts.glyphAdvance(hh.glyphs[0].face, hh.glyphs[0].glyph, 100);
  EXPECT_NEAR(hh.advance, 2 * h, 1e-3);
}

// A combining mark takes no room: "e" + U+0301 is as wide as "e" (composed to "é" or the mark
// placed over the e by the face's mark positioning).
TEST(Text, CombiningMarks) {
  Fonts& fonts = Fonts::shared();
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  ShapedText e = fonts.shape("e", dejavu, 50), marked = fonts.shape("e\xcc\x81", dejavu, 50);
  EXPECT_NEAR(marked.advance, e.advance, 1e-3);
  ASSERT_GE(marked.glyphs.size(), 1u);
  if (marked.glyphs.size() == 2) {
    EXPECT_LT(marked.glyphs[1].x, e.advance);
    EXPECT_NE(marked.glyphs[1].glyph, 0u);
  } else {
    EXPECT_EQ(marked.glyphs[0].glyph, fonts.shape("\xc3\xa9", dejavu, 50).glyphs[0].glyph);
  }
  // Arabic is joined: the same letter takes a different (contextual) glyph inside a word.
  ShapedText alone = fonts.shape("\xd8\xa8", dejavu, 50), word = fonts.shape("\xd8\xa8\xd8\xa8\xd8\xa8", dejavu, 50);
  ASSERT_EQ(word.glyphs.size(), 3u);
  EXPECT_NE(word.glyphs[1].glyph, alone.glyphs[0].glyph);
}

// Outlines: "O" is two closed contours in the em's box; bitmaps carry ink, shifted by the phase.
TEST(Text, OutlinesAndBitmaps) {
  Fonts& fonts = Fonts::shared();
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  ShapedText o = fonts.shape("O", dejavu, 100);
  GlyphOutline outline = fonts.outline(o.glyphs[0].face, o.glyphs[0].glyph, 100);
  EXPECT_EQ(std::count(outline.ops.begin(), outline.ops.end(), GlyphOutline::Move), 2);
  EXPECT_EQ(std::count(outline.ops.begin(), outline.ops.end(), GlyphOutline::Close), 2);
  float top = 0, bottom = -1000;
  for (size_t i = 1; i < outline.xy.size(); i += 2) top = std::min(top, outline.xy[i]), bottom = std::max(bottom, outline.xy[i]);
  EXPECT_LT(top, -60);     // above the baseline (y down): a capital's height, ~73 of 100
  EXPECT_GT(bottom, -3);   // down to the baseline
  EXPECT_LT(bottom, 3);
  GlyphBitmap b0, b2;
  ASSERT_TRUE(fonts.bitmap(o.glyphs[0].face, o.glyphs[0].glyph, 20, 0, b0));
  ASSERT_TRUE(fonts.bitmap(o.glyphs[0].face, o.glyphs[0].glyph, 20, 2, b2));  // half a pixel on
  EXPECT_GT(std::count_if(b0.pixels.begin(), b0.pixels.end(), [](uint8_t v) { return v > 128; }), 20);
  EXPECT_NE(b0.pixels, b2.pixels);
}

// Qt's layout of lpfg's labels: each glyph advances by its unhinted width truncated to 1/64
// pixel. DejaVu Sans has 2048 units to the em; at 32 px a unit is exactly 1/64 pixel (M 1767,
// i 569, n 1298, t 803 units: the pens Qt's QTextLayout reports, 0, 27.609375, 36.5, 56.78125).
// At 21 px, M's 1767 units are 18.1186 px, which Qt truncates to 1159/64 = 18.109375.
TEST(Text, QtAdvances) {
  Fonts& fonts = Fonts::shared();
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  ShapedText mint = fonts.shape("Mint", dejavu, 32);
  ASSERT_EQ(mint.glyphs.size(), 4u);
  const float pens[] = {0, 27.609375f, 36.5f, 56.78125f};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(mint.glyphs[i].x, pens[i]) << i;
  EXPECT_EQ(mint.advance, 69.328125f);
  ShapedText m = fonts.shape("M", dejavu, 21);
  EXPECT_EQ(m.advance, 18.109375f);
  EXPECT_EQ(fonts.glyphAdvance(m.glyphs[0].face, m.glyphs[0].glyph, 21), 18.109375f);
}

// Where the glyphs of "Mint" (24 points: 32 px) fall in lpfg's pixmap: the pen 5 px in, each
// glyph at its pen's whole pixel, the fraction in quarters (5 + 27.609 = 32.609: pixel 32, phase
// 2); the pixmap 69 + 10 columns wide (the advance rounded), 24 + 8 + 1 rows high, the baseline
// 24 rows down, laid 5 px left of the anchor with the baseline 2 px below it.
TEST(Text, RasterLabel) {
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  RasterLabel r = rasterLabel(Fonts::shared().shape("Mint", dejavu, 32), 24);
  ASSERT_EQ(r.glyphs.size(), 4u);
  const int whole[] = {0, 27, 36, 56}, phase[] = {0, 2, 2, 3};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(r.glyphs[i].x, whole[i]) << i;
    EXPECT_EQ(r.glyphs[i].phase, phase[i]) << i;
    EXPECT_EQ(r.glyphs[i].y, 2) << i;
  }
  EXPECT_EQ(r.left, -5);
  EXPECT_EQ(r.right, 74);
  EXPECT_EQ(r.top, -22);
  EXPECT_EQ(r.bottom, 11);
  EXPECT_EQ(subpixelSteps(32), 4);
  EXPECT_EQ(subpixelSteps(64), 4);  // Qt's glyph cache takes ems up to 64 px
  EXPECT_EQ(subpixelSteps(65), 64);
}

// The pixmaps Qt 5.15 draws for lpfg (QPainter::drawText into a transparent QPixmap, lpfg's
// GLWidget::renderText, run under Xvfb at 96 dpi): rows of their alpha, as Qt drew them.
//  - DejaVu Sans 24 pt, "Mint", row 15: light-hinted stems at quarter pixels plus 1/64 (the n's
//    stems: 148 255 255 128 and 204 255 255 20);
//  - Times 16 pt (Nimbus Roman), "ÉÅÖ", row 0: the accents cut off at the pixmap's top.
TEST(Text, LabelBitmapAsQtDrawsIt) {
  Fonts& fonts = Fonts::shared();
  FontSpec dejavu;
  dejavu.file = kDejaVu;
  GlyphBitmap mint = fonts.labelBitmap(fonts.shape("Mint", dejavu, 32), 24);
  ASSERT_EQ(mint.width, 79);
  ASSERT_EQ(mint.height, 33);
  EXPECT_EQ(mint.left, -5);
  EXPECT_EQ(mint.top, 22);
  const std::vector<uint8_t> row15 = {
      0, 0, 0, 0, 0, 0, 0, 0, 216, 255, 255, 56, 0, 0, 0, 82, 255, 255, 95, 191, 255, 238, 7, 0, 0, 0,
      148, 255, 255, 128, 0, 0, 0, 0, 0, 120, 255, 255, 104, 0, 0, 0, 0, 0, 148, 255, 255, 80, 0, 0,
      0, 0, 0, 0, 0, 0, 204, 255, 255, 20, 0, 0, 0, 0, 68, 255, 255, 160, 0, 0, 0, 0, 0, 0, 0, 0, 0,
      0, 0};
  EXPECT_EQ(std::vector<uint8_t>(mint.pixels.begin() + 15 * 79, mint.pixels.begin() + 16 * 79), row15);

  FontSpec times;
  times.family = "Times";
  GlyphBitmap accents = fonts.labelBitmap(fonts.shape("\xc3\x89\xc3\x85\xc3\x96", times, 21), 16);
  ASSERT_EQ(accents.width, 53);
  ASSERT_EQ(accents.height, 22);
  const std::vector<uint8_t> row0 = {
      0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 137, 85, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 63, 199, 198, 111, 0, 0,
      0, 0, 0, 0, 0, 0, 0, 0, 122, 222, 21, 0, 84, 229, 55, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(accents.pixels.begin(), accents.pixels.begin() + 53), row0);
}

// Qt reads Times from Nimbus Roman's Type 1 file, which has no OpenType tables: no ligatures
// ("office" stays six glyphs, where the OpenType file has an "ffi" ligature) and no kerning.
TEST(Text, Type1FaceAsQtShapesIt) {
  Fonts& fonts = Fonts::shared();
  FontSpec times;
  times.family = "Times";
  EXPECT_EQ(fonts.shape("office", times, 21).glyphs.size(), 6u);
  ShapedText av = fonts.shape("AV", times, 21);
  ASSERT_EQ(av.glyphs.size(), 2u);
  EXPECT_EQ(av.glyphs[1].x, fonts.glyphAdvance(av.glyphs[0].face, av.glyphs[0].glyph, 21));
}

// The label colour's bytes and Qt's premultiplied products: an opaque colour's alpha is the
// coverage itself, which lpfg's alpha test then compares.
TEST(Text, ColourBytes) {
  for (int n = 0; n < 256; ++n) {
    EXPECT_EQ(colorByte(n / 255.0f), n);
    EXPECT_EQ(premultiply(255, n), n);
    EXPECT_EQ(premultiply(n, 255), n);
  }
  EXPECT_EQ(premultiply(191, 20), 15);   // 191·20/255 = 14.98
  EXPECT_EQ(premultiply(100, 128), 50);  // 50.2
}

}  // namespace
