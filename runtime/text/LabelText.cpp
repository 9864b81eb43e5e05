// Label text: fontconfig picks the faces, HarfBuzz shapes, FreeType draws (LabelText.h).
#include "runtime/text/LabelText.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <unordered_map>

#include <dlfcn.h>

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_ADVANCES_H
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include <hb.h>

namespace lcjit::runtime::text {

namespace {

// HarfBuzz is loaded when the first label is shaped, not with the program: it and what it loads
// (GLib, Graphite, a shared FreeType …) are nine libraries, 0.7 ms of every run's start-up, and
// most runs draw no label. Without it labels are still drawn, one glyph per character from the
// face's cmap, with the face's advances.
#define LCJIT_HARFBUZZ_FUNCTIONS(X)                                                                          \
  X(hb_blob_create_from_file_or_fail) X(hb_blob_destroy) X(hb_face_create) X(hb_face_destroy)               \
  X(hb_face_get_glyph_count) X(hb_font_create) X(hb_font_destroy) X(hb_font_set_scale)                        \
  X(hb_font_get_glyph_h_advance) X(hb_buffer_create) X(hb_buffer_destroy) X(hb_buffer_clear_contents)         \
  X(hb_buffer_add_utf32) X(hb_buffer_guess_segment_properties) X(hb_shape) X(hb_buffer_get_glyph_infos)       \
  X(hb_buffer_get_glyph_positions) X(hb_unicode_funcs_get_default) X(hb_unicode_general_category)             \
  X(hb_unicode_script) X(hb_font_create_sub_font) X(hb_font_set_funcs) X(hb_font_set_ppem) X(hb_font_funcs_create)        \
  X(hb_font_funcs_set_glyph_h_advance_func) X(hb_font_funcs_make_immutable) X(hb_font_funcs_set_nominal_glyph_func)    \
  X(hb_font_funcs_set_glyph_extents_func) X(hb_face_create_for_tables) X(hb_face_set_upem) X(hb_face_set_glyph_count)

struct HarfBuzz {
#define LCJIT_DECLARE(name) decltype(&::name) name = nullptr;
  LCJIT_HARFBUZZ_FUNCTIONS(LCJIT_DECLARE)
#undef LCJIT_DECLARE
  bool loaded = false;
};

const HarfBuzz& hb() {
  static const HarfBuzz loaded = [] {
    HarfBuzz h;
    void* library = dlopen("libharfbuzz.so.0", RTLD_NOW | RTLD_LOCAL);
    if (!library) return h;
    bool all = true;
#define LCJIT_RESOLVE(name) all = all && (h.name = reinterpret_cast<decltype(&::name)>(dlsym(library, #name)));
    LCJIT_HARFBUZZ_FUNCTIONS(LCJIT_RESOLVE)
#undef LCJIT_RESOLVE
    h.loaded = all;
    return h;
  }();
  return loaded;
}

}  // namespace

int pixelSizeForPoints(int points) { return std::max(1, (int)std::lround(points * 96.0 / 72.0)); }

std::u32string decodeUtf8(std::string_view s) {
  std::u32string out;
  out.reserve(s.size());
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const size_t n = s.size();
  for (size_t i = 0; i < n;) {
    unsigned char b = p[i];
    if (b < 0x80) {
      out += char32_t(b), ++i;
      continue;
    }
    int len = b >= 0xf0 && b <= 0xf4 ? 4 : b >= 0xe0 ? 3 : b >= 0xc2 && b < 0xe0 ? 2 : 0;
    char32_t c = len == 4 ? b & 0x07 : len == 3 ? b & 0x0f : b & 0x1f;
    bool ok = len > 0 && i + len <= n;
    for (int k = 1; ok && k < len; ++k) {
      if ((p[i + k] & 0xc0) != 0x80) ok = false;
      else c = (c << 6) | (p[i + k] & 0x3f);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not characters.
    if (ok && ((len == 3 && c < 0x800) || (len == 4 && (c < 0x10000 || c > 0x10ffff)) || (c >= 0xd800 && c <= 0xdfff)))
      ok = false;
    if (ok) out += c, i += len;
    else out += char32_t(0xfffd), ++i;
  }
  return out;
}

std::string cleanUtf8(std::string_view utf8, bool forXml) {
  std::string out;
  out.reserve(utf8.size());
  for (char32_t c : decodeUtf8(utf8)) {
    if (forXml && ((c < 0x20 && c != '\t' && c != '\n') || c == 0xfffe || c == 0xffff)) continue;
    if (c < 0x80) {
      out += char(c);
    } else if (c < 0x800) {
      out += char(0xc0 | (c >> 6)), out += char(0x80 | (c & 0x3f));
    } else if (c < 0x10000) {
      out += char(0xe0 | (c >> 12)), out += char(0x80 | ((c >> 6) & 0x3f)), out += char(0x80 | (c & 0x3f));
    } else {
      out += char(0xf0 | (c >> 18)), out += char(0x80 | ((c >> 12) & 0x3f)), out += char(0x80 | ((c >> 6) & 0x3f));
      out += char(0x80 | (c & 0x3f));
    }
  }
  return out;
}

namespace {

// HarfBuzz positions in Qt's units, 1/64 pixel (kPenUnits).
constexpr int kUnits = kPenUnits;

struct Face;
// The data of a font's advance callback.
struct QtAdvances {
  Face* face;
  int pixelSize;
};

struct Face {
  std::string file;
  int index = 0;
  FT_Face ft = nullptr;
  int ftPixelSize = 0;
  // Qt draws this family and style from a Type 1 file of the same outlines (the URW fonts come as
  // both; Qt takes the Type 1 one). A Type 1 file has none of the OpenType tables, so HarfBuzz
  // shapes it for Qt without any: no kerning, no ligatures, marks placed by HarfBuzz's fallback.
  // lcjit reads the OpenType file and gives HarfBuzz a face without tables too (tablelessFace).
  bool qtType1 = false;
  hb_face_t* hbFace = nullptr;     // null without HarfBuzz
  std::map<int, hb_font_t*> fonts;  // by pixel size
  std::map<int, std::unique_ptr<QtAdvances>> advances;  // the fonts' advance callbacks' data, by pixel size
  ~Face() {
    for (auto& [s, f] : fonts) hb().hb_font_destroy(f);
    if (hbFace) hb().hb_face_destroy(hbFace);
    if (ft) FT_Done_Face(ft);
  }
};

// A spec's faces: the primary one, then fontconfig's fallbacks in its order of preference.
struct SpecFaces {
  FontSpec spec;
  int primary = -1;
  struct Candidate {
    std::string file;
    int index = 0;
    FcCharSet* charset = nullptr;
    int face = -1;  // -1 not opened yet, -2 unusable
  };
  std::vector<Candidate> fallback;
  std::unordered_map<char32_t, int> chosen;
  ~SpecFaces() {
    for (auto& c : fallback)
      if (c.charset) FcCharSetDestroy(c.charset);
  }
};

bool setSize(Face& f, int pixelSize) {
  if (f.ftPixelSize == pixelSize) return true;
  if (FT_Set_Pixel_Sizes(f.ft, 0, (FT_UInt)pixelSize)) return false;
  f.ftPixelSize = pixelSize;
  return true;
}

// A glyph's advance as Qt lays labels out with light hinting: FreeType's unhinted (linear)
// advance in 16.16 pixels, truncated to 1/64 pixel.
int64_t qtAdvance(Face& f, uint32_t glyph, int pixelSize) {
  FT_Fixed a = 0;
  if (!setSize(f, pixelSize) || FT_Get_Advance(f.ft, glyph, FT_LOAD_NO_HINTING, &a)) return 0;
  return int64_t(a) >> 10;
}

// Qt's font functions for HarfBuzz, restated: the glyph of a character from FreeType's Unicode
// cmap, Qt's advance, and a glyph's box as Qt's glyph cache measures it (the light-hinted
// glyph's, out to whole pixels; HarfBuzz places marks by it when the face has no mark tables).
hb_position_t qtAdvanceForHarfBuzz(hb_font_t*, void* data, hb_codepoint_t glyph, void*) {
  auto* q = static_cast<QtAdvances*>(data);
  return hb_position_t(qtAdvance(*q->face, glyph, q->pixelSize));
}
hb_bool_t qtGlyphForHarfBuzz(hb_font_t*, void* data, hb_codepoint_t c, hb_codepoint_t* glyph, void*) {
  *glyph = FT_Get_Char_Index(static_cast<QtAdvances*>(data)->face->ft, c);
  return *glyph != 0;
}
hb_bool_t qtExtentsForHarfBuzz(hb_font_t*, void* data, hb_codepoint_t glyph, hb_glyph_extents_t* e, void*) {
  auto* q = static_cast<QtAdvances*>(data);
  *e = hb_glyph_extents_t{};
  if (!setSize(*q->face, q->pixelSize)) return true;
  FT_Face ft = q->face->ft;
  const FT_Int32 hinting = q->pixelSize <= 64 ? FT_LOAD_TARGET_LIGHT : FT_LOAD_NO_HINTING;
  if (FT_Load_Glyph(ft, glyph, FT_LOAD_DEFAULT | FT_LOAD_NO_BITMAP | FT_LOAD_IGNORE_GLOBAL_ADVANCE_WIDTH | hinting))
    return true;
  const FT_Glyph_Metrics& m = ft->glyph->metrics;
  const FT_Pos left = m.horiBearingX & -64, right = (m.horiBearingX + m.width + 63) & -64;
  const FT_Pos top = (m.horiBearingY + 63) & -64, bottom = (m.horiBearingY - m.height) & -64;
  // Qt's y points down, as this font's scale does.
  *e = hb_glyph_extents_t{hb_position_t(left), hb_position_t(-top), hb_position_t(right - left), hb_position_t(top - bottom)};
  return true;
}

// A HarfBuzz face with no tables, as Qt's HarfBuzz sees a Type 1 file.
hb_face_t* tablelessFace(FT_Face ft) {
  hb_face_t* face = hb().hb_face_create_for_tables([](hb_face_t*, hb_tag_t, void*) -> hb_blob_t* { return nullptr; },
                                                   nullptr, nullptr);
  hb().hb_face_set_upem(face, ft->units_per_EM ? ft->units_per_EM : 1000);
  hb().hb_face_set_glyph_count(face, (unsigned)ft->num_glyphs);
  return face;
}

int fcWeight(int weight) {
  return weight <= 25 ? FC_WEIGHT_LIGHT : weight <= 50 ? FC_WEIGHT_REGULAR : weight <= 63 ? FC_WEIGHT_DEMIBOLD
         : weight <= 75                                                     ? FC_WEIGHT_BOLD
                                                                            : FC_WEIGHT_BLACK;
}

bool isMark(char32_t c) {
  if (!hb().loaded) return false;
  switch (hb().hb_unicode_general_category(hb().hb_unicode_funcs_get_default(), c)) {
    case HB_UNICODE_GENERAL_CATEGORY_NON_SPACING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_SPACING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_ENCLOSING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_FORMAT:  // joiners, variation selectors' neighbours
      return true;
    default: return false;
  }
}

hb_script_t scriptOf(char32_t c) {
  if (!hb().loaded) return HB_SCRIPT_INVALID;
  hb_script_t s = hb().hb_unicode_script(hb().hb_unicode_funcs_get_default(), c);
  return s == HB_SCRIPT_COMMON || s == HB_SCRIPT_INHERITED || s == HB_SCRIPT_UNKNOWN ? HB_SCRIPT_INVALID : s;
}

}  // namespace

struct Fonts::Impl {
  std::mutex mutex;
  FT_Library library = nullptr;
  std::vector<std::unique_ptr<Face>> faces;
  std::map<std::pair<std::string, int>, int> faceIds;  // -1: unusable
  std::vector<std::unique_ptr<SpecFaces>> specs;

  ~Impl() {
    specs.clear();
    faces.clear();
    if (library) FT_Done_FreeType(library);
  }

  // The face of a file, opened once; -1 when FreeType or HarfBuzz cannot use it (HarfBuzz reads
  // only OpenType/TrueType files, not Type 1).
  int faceId(const std::string& file, int index) {
    auto key = std::make_pair(file, index);
    if (auto it = faceIds.find(key); it != faceIds.end()) return it->second;
    int id = -1;
    if (library || !FT_Init_FreeType(&library)) {
      auto f = std::make_unique<Face>();
      f->file = file, f->index = index;
      if (!FT_New_Face(library, file.c_str(), index, &f->ft) && FT_IS_SCALABLE(f->ft)) {
        hb_blob_t* blob = hb().loaded ? hb().hb_blob_create_from_file_or_fail(file.c_str()) : nullptr;
        if (blob) {
          f->hbFace = hb().hb_face_create(blob, (unsigned)index);
          hb().hb_blob_destroy(blob);
        }
        if (!hb().loaded || hb().hb_face_get_glyph_count(f->hbFace) > 0) {
          id = (int)faces.size();
          faces.push_back(std::move(f));
        }
      }
    }
    faceIds[key] = id;
    return id;
  }

  // The face at an em of pixelSize as Qt sets it up for HarfBuzz: scaled to 1/64 pixel, y down,
  // its ppem given (for the face's device-table adjustments), Qt's advances.
  hb_font_t* font(int face, int pixelSize) {
    Face& f = *faces[face];
    if (auto it = f.fonts.find(pixelSize); it != f.fonts.end()) return it->second;
    static hb_font_funcs_t* const funcs = [] {
      hb_font_funcs_t* fs = hb().hb_font_funcs_create();
      hb().hb_font_funcs_set_nominal_glyph_func(fs, qtGlyphForHarfBuzz, nullptr, nullptr);
      hb().hb_font_funcs_set_glyph_h_advance_func(fs, qtAdvanceForHarfBuzz, nullptr, nullptr);
      hb().hb_font_funcs_set_glyph_extents_func(fs, qtExtentsForHarfBuzz, nullptr, nullptr);
      hb().hb_font_funcs_make_immutable(fs);
      return fs;
    }();
    hb_font_t* parent = hb().hb_font_create(f.hbFace);
    hb().hb_font_set_scale(parent, pixelSize * kUnits, -pixelSize * kUnits);
    hb().hb_font_set_ppem(parent, (unsigned)pixelSize, (unsigned)pixelSize);
    hb_font_t* font = hb().hb_font_create_sub_font(parent);
    hb().hb_font_destroy(parent);
    auto& data = f.advances[pixelSize] = std::make_unique<QtAdvances>(QtAdvances{&f, pixelSize});
    hb().hb_font_set_funcs(font, funcs, data.get(), nullptr);
    return f.fonts[pixelSize] = font;
  }

  bool has(int face, char32_t c) { return face >= 0 && FT_Get_Char_Index(faces[face]->ft, c) != 0; }

  // Whether fontconfig lists a Type 1 file of the matched face's family and style (Nimbus Roman's
  // .t1 beside its .otf): Qt, asked for "Times", reports "Nimbus Roman [urw]", the Type 1 file's
  // foundry, and finds no kerning table in it.
  static bool hasType1Twin(FcPattern* match) {
    FcChar8 *family = nullptr, *style = nullptr, *format = nullptr;
    if (FcPatternGetString(match, FC_FAMILY, 0, &family) != FcResultMatch ||
        FcPatternGetString(match, FC_STYLE, 0, &style) != FcResultMatch)
      return false;
    if (FcPatternGetString(match, FC_FONTFORMAT, 0, &format) == FcResultMatch &&
        std::string_view(reinterpret_cast<const char*>(format)) == "Type 1")
      return false;
    FcPattern* twin = FcPatternBuild(nullptr, FC_FAMILY, FcTypeString, family, FC_STYLE, FcTypeString, style,
                                     FC_FONTFORMAT, FcTypeString, reinterpret_cast<const FcChar8*>("Type 1"),
                                     static_cast<const char*>(nullptr));
    FcObjectSet* objects = FcObjectSetBuild(FC_FILE, static_cast<const char*>(nullptr));
    FcFontSet* set = twin && objects ? FcFontList(nullptr, twin, objects) : nullptr;
    bool found = set && set->nfont > 0;
    if (set) FcFontSetDestroy(set);
    if (objects) FcObjectSetDestroy(objects);
    if (twin) FcPatternDestroy(twin);
    return found;
  }

  static void markQtType1(Face& f) {
    if (f.qtType1) return;
    f.qtType1 = true;
    if (!f.hbFace) return;
    for (auto& [size, font] : f.fonts) hb().hb_font_destroy(font);
    f.fonts.clear();
    hb().hb_face_destroy(f.hbFace);
    f.hbFace = tablelessFace(f.ft);
  }

  SpecFaces& facesFor(const FontSpec& spec) {
    for (auto& s : specs)
      if (s->spec == spec) return *s;
    auto sf = std::make_unique<SpecFaces>();
    sf->spec = spec;
    if (!spec.file.empty()) sf->primary = faceId(spec.file, 0);
    if (FcInit()) {
      FcPattern* pattern = FcPatternCreate();
      FcPatternAddString(pattern, FC_FAMILY, reinterpret_cast<const FcChar8*>(spec.family.c_str()));
      FcPatternAddInteger(pattern, FC_WEIGHT, fcWeight(spec.weight));
      FcPatternAddInteger(pattern, FC_SLANT, spec.italic ? FC_SLANT_ITALIC : FC_SLANT_ROMAN);
      FcConfigSubstitute(nullptr, pattern, FcMatchPattern);
      FcDefaultSubstitute(pattern);
      FcResult result;
      auto fileOf = [](FcPattern* p, std::string& file, int& index) {
        FcChar8* path = nullptr;
        if (FcPatternGetString(p, FC_FILE, 0, &path) != FcResultMatch || !path) return false;
        file = reinterpret_cast<const char*>(path);
        if (FcPatternGetInteger(p, FC_INDEX, 0, &index) != FcResultMatch) index = 0;
        return true;
      };
      if (sf->primary < 0) {
        // The face Qt draws lpfg's labels with: fontconfig's best match for family, weight, slant.
        if (FcPattern* match = FcFontMatch(nullptr, pattern, &result)) {
          std::string file;
          int index = 0;
          if (fileOf(match, file, index)) sf->primary = faceId(file, index);
          if (sf->primary >= 0 && hasType1Twin(match)) markQtType1(*faces[sf->primary]);
          FcPatternDestroy(match);
        }
      }
      // Fallbacks: fontconfig's list in order of preference, trimmed to those that add characters.
      if (FcFontSet* set = FcFontSort(nullptr, pattern, FcTrue, nullptr, &result)) {
        for (int i = 0; i < set->nfont; ++i) {
          SpecFaces::Candidate c;
          FcCharSet* cs = nullptr;
          if (!fileOf(set->fonts[i], c.file, c.index) ||
              FcPatternGetCharSet(set->fonts[i], FC_CHARSET, 0, &cs) != FcResultMatch || !cs)
            continue;
          c.charset = FcCharSetCopy(cs);
          sf->fallback.push_back(std::move(c));
        }
        FcFontSetDestroy(set);
      }
      FcPatternDestroy(pattern);
    }
    if (sf->primary < 0) sf->primary = faceId("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", 0);
    for (auto& c : sf->fallback)  // the primary face may not be usable: the first usable fallback
      if (sf->primary < 0 && (c.face = faceId(c.file, c.index)) >= 0) sf->primary = c.face;
    specs.push_back(std::move(sf));
    return *specs.back();
  }

  int pick(SpecFaces& sf, char32_t c) {
    if (auto it = sf.chosen.find(c); it != sf.chosen.end()) return it->second;
    int face = -1;
    if (has(sf.primary, c)) face = sf.primary;
    for (size_t i = 0; face < 0 && i < sf.fallback.size(); ++i) {
      auto& cand = sf.fallback[i];
      if (cand.face == -2 || !FcCharSetHasChar(cand.charset, c)) continue;
      if (cand.face == -1 && (cand.face = faceId(cand.file, cand.index)) < 0) cand.face = -2;
      if (has(cand.face, c)) face = cand.face;
    }
    if (face < 0) face = sf.primary;  // its .notdef box: what is missing shows as missing
    return sf.chosen[c] = face;
  }
};

Fonts& Fonts::shared() {
  static Fonts fonts;
  return fonts;
}
Fonts::Fonts() : impl_(new Impl) {}
Fonts::~Fonts() { delete impl_; }

std::string Fonts::primaryFile(const FontSpec& spec) {
  std::lock_guard lock(impl_->mutex);
  int f = impl_->facesFor(spec).primary;
  return f < 0 ? std::string() : impl_->faces[f]->file;
}

std::string Fonts::faceFile(int face) {
  std::lock_guard lock(impl_->mutex);
  return face >= 0 && face < (int)impl_->faces.size() ? impl_->faces[face]->file : std::string();
}

ShapedText Fonts::shape(std::string_view utf8, const FontSpec& spec, float pixelSize) {
  ShapedText out;
  const std::u32string text = decodeUtf8(utf8);
  const int em = (int)std::lround(pixelSize);  // Qt's ems are whole pixels
  if (text.empty() || em <= 0) return out;
  std::lock_guard lock(impl_->mutex);
  SpecFaces& sf = impl_->facesFor(spec);
  if (sf.primary < 0) return out;
  // A face per character; a mark stays with its base's face when that face has it, so that the
  // face's own mark positioning places it.
  std::vector<int> faceOf(text.size());
  for (size_t i = 0; i < text.size(); ++i)
    faceOf[i] = i > 0 && isMark(text[i]) && impl_->has(faceOf[i - 1], text[i]) ? faceOf[i - 1] : impl_->pick(sf, text[i]);
  // The pen in 1/64 pixel, summed exactly as Qt sums its fixed-point advances.
  int64_t pen = 0;
  if (!hb().loaded) {  // no shaping: the cmap's glyph per character, the face's advances
    for (size_t i = 0; i < text.size(); ++i) {
      uint32_t glyph = FT_Get_Char_Index(impl_->faces[faceOf[i]]->ft, text[i]);
      out.glyphs.push_back({faceOf[i], glyph, float(pen) / kUnits, 0});
      pen += qtAdvance(*impl_->faces[faceOf[i]], glyph, em);
    }
    out.advance = float(pen) / kUnits;
    return out;
  }
  // Runs of one face and one script (characters common to all scripts join either side).
  hb_buffer_t* buffer = hb().hb_buffer_create();
  for (size_t start = 0; start < text.size();) {
    hb_script_t script = scriptOf(text[start]);
    size_t end = start + 1;
    for (; end < text.size() && faceOf[end] == faceOf[start]; ++end) {
      hb_script_t s = scriptOf(text[end]);
      if (s != HB_SCRIPT_INVALID && script != HB_SCRIPT_INVALID && s != script) break;
      if (script == HB_SCRIPT_INVALID) script = s;
    }
    hb().hb_buffer_clear_contents(buffer);
    hb().hb_buffer_add_utf32(buffer, reinterpret_cast<const uint32_t*>(text.data()), (int)text.size(), (unsigned)start,
                        (int)(end - start));
    hb().hb_buffer_guess_segment_properties(buffer);
    const int face = faceOf[start];
    const bool kerning = spec.kerning;
    const hb_feature_t noKerning{HB_TAG('k', 'e', 'r', 'n'), 0, HB_FEATURE_GLOBAL_START, HB_FEATURE_GLOBAL_END};
    hb().hb_shape(impl_->font(face, em), buffer, kerning ? nullptr : &noKerning, kerning ? 0 : 1);
    unsigned n = 0;
    const hb_glyph_info_t* info = hb().hb_buffer_get_glyph_infos(buffer, &n);
    const hb_glyph_position_t* pos = hb().hb_buffer_get_glyph_positions(buffer, &n);
    for (unsigned i = 0; i < n; ++i) {
      out.glyphs.push_back({face, info[i].codepoint, float(pen + pos[i].x_offset) / kUnits,
                            float(pos[i].y_offset) / kUnits});
      pen += pos[i].x_advance;
    }
    start = end;
  }
  hb().hb_buffer_destroy(buffer);
  out.advance = float(pen) / kUnits;
  return out;
}

float Fonts::glyphAdvance(int face, uint32_t glyph, float pixelSize) {
  std::lock_guard lock(impl_->mutex);
  if (face < 0 || face >= (int)impl_->faces.size()) return 0;
  return float(qtAdvance(*impl_->faces[face], glyph, (int)std::lround(pixelSize))) / kUnits;
}

GlyphOutline Fonts::outline(int face, uint32_t glyph, float pixelSize) {
  GlyphOutline out;
  std::lock_guard lock(impl_->mutex);
  if (face < 0 || face >= (int)impl_->faces.size()) return out;
  FT_Face ft = impl_->faces[face]->ft;
  // Unscaled and unhinted: the design outline, scaled here, so that vector output has no
  // pixel-grid fitting in it.
  if (FT_Load_Glyph(ft, glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_BITMAP) || ft->glyph->format != FT_GLYPH_FORMAT_OUTLINE)
    return out;
  struct State {
    GlyphOutline* out;
    float k;
    float x = 0, y = 0;
    bool open = false;
    void point(const FT_Vector* v) {
      out->xy.push_back(float(v->x) * k);
      out->xy.push_back(-float(v->y) * k);
    }
  } st{&out, pixelSize / float(ft->units_per_EM ? ft->units_per_EM : 1000)};
  FT_Outline_Funcs funcs{};
  funcs.move_to = [](const FT_Vector* to, void* u) {
    auto* s = static_cast<State*>(u);
    if (s->open) s->out->ops.push_back(GlyphOutline::Close);
    s->out->ops.push_back(GlyphOutline::Move);
    s->point(to);
    s->x = float(to->x), s->y = float(to->y), s->open = true;
    return 0;
  };
  funcs.line_to = [](const FT_Vector* to, void* u) {
    auto* s = static_cast<State*>(u);
    s->out->ops.push_back(GlyphOutline::Line);
    s->point(to);
    s->x = float(to->x), s->y = float(to->y);
    return 0;
  };
  funcs.conic_to = [](const FT_Vector* c, const FT_Vector* to, void* u) {
    auto* s = static_cast<State*>(u);
    // The quadratic as the cubic with the same curve: control points 2/3 of the way to c.
    FT_Vector c1{FT_Pos(std::lround(s->x + 2.0 / 3 * (double(c->x) - s->x))),
                 FT_Pos(std::lround(s->y + 2.0 / 3 * (double(c->y) - s->y)))};
    FT_Vector c2{FT_Pos(std::lround(to->x + 2.0 / 3 * (double(c->x) - to->x))),
                 FT_Pos(std::lround(to->y + 2.0 / 3 * (double(c->y) - to->y)))};
    s->out->ops.push_back(GlyphOutline::Cubic);
    s->point(&c1), s->point(&c2), s->point(to);
    s->x = float(to->x), s->y = float(to->y);
    return 0;
  };
  funcs.cubic_to = [](const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* u) {
    auto* s = static_cast<State*>(u);
    s->out->ops.push_back(GlyphOutline::Cubic);
    s->point(c1), s->point(c2), s->point(to);
    s->x = float(to->x), s->y = float(to->y);
    return 0;
  };
  if (FT_Outline_Decompose(&ft->glyph->outline, &funcs, &st)) return GlyphOutline();
  if (st.open) out.ops.push_back(GlyphOutline::Close);
  return out;
}

namespace {
// Qt draws glyphs from its glyph cache up to an em of this many pixels, and fills the outlines
// of larger ones.
constexpr int kQtCachedGlyphLimit = 64;
}  // namespace

int subpixelSteps(int pixelSize) { return pixelSize <= kQtCachedGlyphLimit ? 4 : kPenUnits; }

bool Fonts::bitmap(int face, uint32_t glyph, int pixelSize, int phase, GlyphBitmap& out) {
  out = GlyphBitmap();
  std::lock_guard lock(impl_->mutex);
  if (face < 0 || face >= (int)impl_->faces.size()) return false;
  Face& f = *impl_->faces[face];
  if (!setSize(f, pixelSize)) return false;
  FT_Face ft = f.ft;
  // Qt's glyph cache loads light-hinted glyphs and moves them right by the quarter pixel plus
  // 1/64; a filled outline is unhinted, at the pen's 1/64.
  const bool cached = pixelSize <= kQtCachedGlyphLimit;
  const FT_Int32 load = FT_LOAD_DEFAULT | FT_LOAD_NO_BITMAP | FT_LOAD_IGNORE_GLOBAL_ADVANCE_WIDTH |
                        (cached ? FT_LOAD_TARGET_LIGHT : FT_LOAD_NO_HINTING);
  const FT_Pos shift = cached ? phase * (kPenUnits / subpixelSteps(pixelSize)) + 1 : phase;
  if (FT_Load_Glyph(ft, glyph, load)) return false;
  if (ft->glyph->format == FT_GLYPH_FORMAT_OUTLINE) FT_Outline_Translate(&ft->glyph->outline, shift, 0);
  if (FT_Render_Glyph(ft->glyph, cached ? FT_RENDER_MODE_LIGHT : FT_RENDER_MODE_NORMAL)) return false;
  const FT_Bitmap& b = ft->glyph->bitmap;
  out.left = ft->glyph->bitmap_left;
  out.top = ft->glyph->bitmap_top;
  out.width = (int)b.width;
  out.height = (int)b.rows;
  out.pixels.assign(size_t(out.width) * out.height, 0);
  for (int r = 0; r < out.height; ++r) {
    const unsigned char* row = b.buffer + (ptrdiff_t)r * b.pitch;
    for (int x = 0; x < out.width; ++x) {
      uint8_t v = 0;
      if (b.pixel_mode == FT_PIXEL_MODE_GRAY) v = row[x];
      else if (b.pixel_mode == FT_PIXEL_MODE_MONO) v = (row[x >> 3] >> (7 - (x & 7))) & 1 ? 255 : 0;
      else return false;
      out.pixels[size_t(r) * out.width + x] = v;
    }
  }
  return true;
}

RasterLabel rasterLabel(const ShapedText& shaped, int points) {
  RasterLabel r;
  const int steps = subpixelSteps(pixelSizeForPoints(points));
  // lpfg's pixmap, from the anchor's pixel: the pen starts 5 px in, the baseline 2 px below.
  constexpr int kPenStart = 5, kBaseline = 2;
  for (const PlacedGlyph& g : shaped.glyphs) {
    const int64_t x = int64_t(kPenStart) * kPenUnits + std::llround(double(g.x) * kPenUnits);
    const int64_t whole = x >= 0 ? x / kPenUnits : -((-x + kPenUnits - 1) / kPenUnits);
    const int phase = int(x - whole * kPenUnits) * steps / kPenUnits;
    r.glyphs.push_back({g.face, g.glyph, phase, int(whole) - kPenStart, kBaseline + (int)std::floor(g.y + 0.5f)});
  }
  // The pixmap: the label's rounded advance and 10 px wide, points + points/3 + 1 rows high.
  r.left = -kPenStart;
  r.right = r.left + (int)std::floor(shaped.advance + 0.5f) + 10;
  r.top = kBaseline - points;
  r.bottom = r.top + points + points / 3 + 1;
  return r;
}

GlyphBitmap Fonts::labelBitmap(const ShapedText& shaped, int points) {
  const RasterLabel r = rasterLabel(shaped, points);
  const int em = pixelSizeForPoints(points);
  GlyphBitmap out;
  out.left = r.left, out.top = -r.top;
  out.width = r.right - r.left, out.height = r.bottom - r.top;
  out.pixels.assign(size_t(out.width) * out.height, 0);
  GlyphBitmap g;
  for (const RasterGlyph& rg : r.glyphs) {
    if (!bitmap(rg.face, rg.glyph, em, rg.phase, g)) continue;
    // The bitmap's corner in the pixmap, then Qt's source-over of the glyph's coverage.
    const int x0 = rg.x + g.left - r.left, y0 = rg.y - g.top - r.top;
    for (int y = std::max(0, -y0); y < g.height && y0 + y < out.height; ++y)
      for (int x = std::max(0, -x0); x < g.width && x0 + x < out.width; ++x) {
        const int c = g.pixels[size_t(y) * g.width + x];
        uint8_t& d = out.pixels[size_t(y0 + y) * out.width + x0 + x];
        if (c) d = uint8_t(c + premultiply(d, 255 - c));
      }
  }
  return out;
}

}  // namespace lcjit::runtime::text
