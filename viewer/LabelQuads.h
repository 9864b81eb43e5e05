// The renderer's labels (LabelQuads.cpp): each label text's picture as lpfg's Qt draws it, packed
// into an atlas, and each frame's quads, one per label at its anchor's pixel, in a vertex buffer
// of their own. The renderer draws a range of them wherever the string has labels, with the state
// around the draw its own (Renderer.cpp's drawLabelRange). Internal to the renderer.
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include "viewer/Renderer.h"
#include "viewer/Shaders.h"

namespace lcjit::viewer {

// Label pictures: each label text's pixmap as lpfg's Qt draws it (Fonts::labelBitmap), in one
// atlas, packed as the labels first need them.
struct LabelImage {
  int x = 0, y = 0, width = 0, height = 0;  // in the atlas
  int left = 0, top = 0;                    // the pixmap's corner from the anchor's pixel, y up
};
struct LabelAtlas {
  runtime::text::FontSpec spec;  // what the pictures were drawn with
  int points = 0;
  GLuint atlas = 0;
  int atlasSize = 256;
  bool dirty = false;  // the texture lags the pictures
  std::unordered_map<std::string, LabelImage> images;
  std::unordered_map<std::string, std::vector<uint8_t>> bitmaps;  // kept to re-pack into a bigger atlas
  std::vector<uint8_t> pixels;                                  // atlasSize²
  int x = 1, y = 1, rowHeight = 0;                              // the shelf packer's pen
};

struct LabelQuads {
  LabelAtlas labelAtlas;
  GLuint textVao = 0, textVbo = 0;
  size_t textVboSize = 0;
  // This frame's label quads in textVbo (prepareLabels): label i's six vertices (none when it is
  // not drawn) from labelFirstVertex[i]; empty when no label is drawn.
  std::vector<uint32_t> labelFirstVertex;
  glm::vec2 labelViewport{1, 1};

  void init();     // the vertex array and buffer
  void release();  // the context must be current
  // The frame's quads, uploaded before anything is drawn (labels in the palette's text colours).
  void prepareLabels(const std::vector<runtime::Label>& labels, const RenderPalette& palette,
                     const runtime::ViewSettings& view, const runtime::CameraMatrices& cam,
                     const RenderOptions& options);
  // The vertices of labels [first, first+count): none (a >= b) when none of them is drawn.
  std::pair<uint32_t, uint32_t> vertexRange(uint32_t first, uint32_t count) const;
  // Draws vertices [a, b) with the labels' program, blended as Qt's premultiplied pixmap; the
  // caller sets the depth test, culling and polygon mode.
  void drawQuads(Program& text, uint32_t a, uint32_t b);

 private:
  bool packLabel(const std::string& text, const std::vector<uint8_t>& bits);
  const LabelImage& labelImage(const std::string& text);
  void uploadAtlas();
};

}  // namespace lcjit::viewer
