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
  ASSERT_TRUE(fonts.bitmap(o.glyphs[0].face, o.glyphs[0].glyph, 20, 0.5f, b2));
  EXPECT_GT(std::count_if(b0.pixels.begin(), b0.pixels.end(), [](uint8_t v) { return v > 128; }), 20);
  EXPECT_NE(b0.pixels, b2.pixels);
}

}  // namespace
