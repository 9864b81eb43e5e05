// The labels' pictures and quads (LabelQuads.h): each label text drawn once as lpfg's Qt draws its
// pixmap (runtime/text), shelf-packed into an atlas; each frame, a quad per label at its anchor's
// pixel, drawn over the picture where the string has the label (Renderer.cpp's drawAll).
//
// Sections, in order (each begins with a `// ----` rule): The atlas (packing, pictures, upload) ·
// The frame's quads (prepareLabels) · Drawing a range of them.
#include "viewer/LabelQuads.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "runtime/turtle/Camera.h"

namespace lcjit::viewer {

using runtime::CameraMatrices;
using runtime::ViewSettings;

void LabelQuads::init() {
  glGenVertexArrays(1, &textVao);
  glGenBuffers(1, &textVbo);
  glBindVertexArray(textVao);
  glBindBuffer(GL_ARRAY_BUFFER, textVbo);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 32, (void*)0);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 32, (void*)8);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, 32, (void*)16);
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glEnableVertexAttribArray(2);
  glBindVertexArray(0);
}

void LabelQuads::release() {
  glDeleteVertexArrays(1, &textVao);
  glDeleteBuffers(1, &textVbo);
  if (labelAtlas.atlas) glDeleteTextures(1, &labelAtlas.atlas);
}

// ---------------------------------------------------------------------------------------------
// The atlas

// Pictures are shelf-packed into the atlas as they first appear; a full atlas doubles and
// everything is packed again.
bool LabelQuads::packLabel(const std::string& text, const std::vector<uint8_t>& bits) {
  LabelAtlas& a = labelAtlas;
  LabelImage& im = a.images[text];
  if (im.width == 0) return true;
  const int size = a.atlasSize;
  if (im.width + 2 > size) return false;
  if (a.x + im.width + 1 > size) a.x = 1, a.y += a.rowHeight + 1, a.rowHeight = 0;
  if (a.y + im.height + 1 > size) return false;
  im.x = a.x, im.y = a.y;
  for (int r = 0; r < im.height; ++r)
    std::memcpy(&a.pixels[size_t(im.y + r) * size + im.x], &bits[size_t(r) * im.width], (size_t)im.width);
  a.x += im.width + 1;
  a.rowHeight = std::max(a.rowHeight, im.height);
  a.dirty = true;
  return true;
}

// The picture of a label text, drawn and packed the first time.
const LabelImage& LabelQuads::labelImage(const std::string& text) {
  LabelAtlas& a = labelAtlas;
  if (auto it = a.images.find(text); it != a.images.end()) return it->second;
  runtime::text::Fonts& fonts = runtime::text::Fonts::shared();
  runtime::text::GlyphBitmap b =
      fonts.labelBitmap(fonts.shape(text, a.spec, (float)runtime::text::pixelSizeForPoints(a.points)), a.points);
  LabelImage& im = a.images[text];
  im.left = b.left, im.top = b.top, im.width = b.width, im.height = b.height;
  if (a.pixels.empty()) a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
  bool fits = packLabel(text, b.pixels);
  while (!fits && a.atlasSize < 4096) {
    a.atlasSize *= 2;
    a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
    a.x = a.y = 1, a.rowHeight = 0;
    fits = packLabel(text, b.pixels);
    for (auto& [t, bits] : a.bitmaps) fits = fits && packLabel(t, bits);
  }
  if (!fits) {  // the largest atlas is full: start it afresh (labels already placed this frame are skipped)
    a.images.clear(), a.bitmaps.clear();
    std::fill(a.pixels.begin(), a.pixels.end(), 0);
    a.x = a.y = 1, a.rowHeight = 0;
    LabelImage& fresh = a.images[text];
    fresh.left = b.left, fresh.top = b.top, fresh.width = b.width, fresh.height = b.height;
    if (!packLabel(text, b.pixels)) fresh.width = 0;
    a.bitmaps[text] = std::move(b.pixels);
    return fresh;
  }
  a.bitmaps[text] = std::move(b.pixels);
  return im;
}

void LabelQuads::uploadAtlas() {
  LabelAtlas& a = labelAtlas;
  if (!a.atlas) glGenTextures(1, &a.atlas);
  glBindTexture(GL_TEXTURE_2D, a.atlas);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (a.pixels.empty()) a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, a.atlasSize, a.atlasSize, 0, GL_RED, GL_UNSIGNED_BYTE, a.pixels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  a.dirty = false;
}

// ---------------------------------------------------------------------------------------------
// The frame's quads

// Each label's picture at its anchor's pixel (runtime/text: lpfg's pixmap, its left end 5 px
// before the anchor, the baseline 2 px below it): the quads of the frame's labels, uploaded
// before anything is drawn, since drawAll draws them where the string has them.
void LabelQuads::prepareLabels(const std::vector<runtime::Label>& labels, const RenderPalette& palette,
                               const ViewSettings& view, const CameraMatrices& cam, const RenderOptions& options) {
  labelFirstVertex.clear();
  if (labels.empty() || !options.drawLabels) return;
  runtime::text::FontSpec spec = labelFont(view);
  spec.file = options.fontFile;
  // A new font, or an atlas grown mostly of texts earlier frames had (an animated counter's):
  // drawn afresh.
  if (!(spec == labelAtlas.spec) || labelAtlas.points != view.winFontSize ||
      labelAtlas.images.size() > 4 * labels.size() + 1024)
    labelAtlas = LabelAtlas{.spec = spec, .points = view.winFontSize, .atlas = labelAtlas.atlas};
  // Quads first (they may grow the atlas), the texture coordinates once the atlas is final.
  struct Quad {
    int x, y;  // the anchor's pixel
    const std::string* text;
    std::array<float, 4> col;
  };
  std::vector<std::optional<Quad>> quads(labels.size());
  bool any = false;
  for (size_t i = 0; i < labels.size(); ++i) {
    const runtime::Label& l = labels[i];
    glm::vec4 c = cam.projection * cam.view * glm::vec4(l.position.x, l.position.y, l.position.z, 1);
    if (c.w <= 0) continue;
    glm::vec3 w = runtime::projectToWindow(cam, l.position);
    if (labelImage(l.text).width == 0) continue;
    auto col = palette.textColor(l.color);
    std::array<float, 4> bytes{};
    for (int k = 0; k < 3; ++k) bytes[k] = (float)runtime::text::colorByte(col[k]);
    quads[i] = Quad{(int)std::round(w.x), (int)std::round(w.y), &l.text, bytes};
    any = true;
  }
  if (!any) return;
  if (labelAtlas.dirty || !labelAtlas.atlas) uploadAtlas();
  std::vector<float> v;
  v.reserve(labels.size() * 48);
  labelFirstVertex.reserve(labels.size() + 1);
  const float n = 1.0f / labelAtlas.atlasSize;
  for (const std::optional<Quad>& q : quads) {
    labelFirstVertex.push_back(uint32_t(v.size() / 8));
    if (!q) continue;
    auto it = labelAtlas.images.find(*q->text);
    if (it == labelAtlas.images.end() || it->second.width == 0) continue;
    const LabelImage& im = it->second;
    float x0 = float(q->x + im.left), y0 = float(q->y - im.top), x1 = x0 + im.width, y1 = y0 + im.height;
    float s0 = im.x * n, t0 = im.y * n, s1 = (im.x + im.width) * n, t1 = (im.y + im.height) * n;
    float quad[6][4] = {{x0, y0, s0, t0}, {x1, y0, s1, t0}, {x1, y1, s1, t1},
                        {x0, y0, s0, t0}, {x1, y1, s1, t1}, {x0, y1, s0, t1}};
    for (auto& p : quad) v.insert(v.end(), {p[0], p[1], p[2], p[3], q->col[0], q->col[1], q->col[2], 1.0f});
  }
  labelFirstVertex.push_back(uint32_t(v.size() / 8));
  if (v.empty()) {
    labelFirstVertex.clear();
    return;
  }
  glBindBuffer(GL_ARRAY_BUFFER, textVbo);
  if (v.size() * sizeof(float) > textVboSize) {
    textVboSize = v.size() * sizeof(float);
    glBufferData(GL_ARRAY_BUFFER, textVboSize, v.data(), GL_STREAM_DRAW);
  } else {
    glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(float), v.data());
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  labelViewport = {(float)cam.width, (float)cam.height};
}

// ---------------------------------------------------------------------------------------------
// Drawing a range of them

std::pair<uint32_t, uint32_t> LabelQuads::vertexRange(uint32_t first, uint32_t count) const {
  if (labelFirstVertex.empty() || first >= labelFirstVertex.size() - 1) return {0, 0};
  const uint32_t end = std::min<uint32_t>(first + count, (uint32_t)labelFirstVertex.size() - 1);
  return {labelFirstVertex[first], labelFirstVertex[end]};
}

void LabelQuads::drawQuads(Program& text, uint32_t a, uint32_t b) {
  glUseProgram(text.id);
  glUniform2f(text.loc("uViewport"), labelViewport.x, labelViewport.y);
  glUniform1i(text.loc("uAtlas"), 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, labelAtlas.atlas);
  glBindVertexArray(textVao);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // Qt's premultiplied pixmap
  glDrawArrays(GL_TRIANGLES, GLint(a), GLsizei(b - a));
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glBindVertexArray(0);
}

}  // namespace lcjit::viewer
