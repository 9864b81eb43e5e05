// The segments' GL objects (SegmentBuffers.cpp), for the renderer's pixel-style lines: the
// segments in buffer textures, with what lets them be drawn as GL lines (runs of one rounded
// width; index lists per width when the widths change every few segments) or as quads (an index
// buffer of four vertices a segment). Internal to the renderer (Renderer.cpp draws them).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <epoxy/gl.h>

#include "runtime/turtle/Geometry.h"

namespace lcjit::viewer {

constexpr uint32_t kGroupMinimum = 2048;  // fewer segments with fragmented widths: quads

// Segments of one rounded width, for drawing fragmented widths as a few GL_LINES draws.
struct WidthGroup {
  float width = 1;
  uint32_t offset = 0;        // first index in the chunk's group index buffer
  std::vector<uint32_t> ids;  // chunk-local segment numbers, increasing
};

// A million segments are 2M texels; GL 3.3 only promises 64K texels per buffer texture.
struct SegmentChunk {
  GLuint buffer = 0, texture = 0;
  uint32_t first = 0, count = 0;
  GLuint groupEbo = 0;
  std::vector<WidthGroup> groups;  // empty unless the widths are fragmented
};

// An aliased GL line's width: rounded, at least 1.
inline float lineWidth(float w) { return std::max(1.0f, std::floor(w + 0.5f)); }

struct SegmentBuffers {
  GLuint quadEbo = 0;  // bound to the renderer's empty vertex array
  uint32_t quadEboSegments = 0;
  // Runs of segments of one rounded width: (first segment, width); a sentinel ends the list.
  std::vector<std::pair<uint32_t, float>> widthRuns;
  std::vector<SegmentChunk> chunks;
  GLint maxTexelsBuffer = 65536;

  void init(GLuint emptyVao);  // the context's limits, the quad index buffer
  // Uploads the segments (32 bytes each, in chunks that fit a buffer texture).
  void upload(const std::vector<runtime::Segment>& segments, GLuint emptyVao);
  void release();  // the context must be current
};

}  // namespace lcjit::viewer
