// The segments' GL objects (SegmentBuffers.h): the geometry's segments in buffer textures, the
// runs and groups of equal width that let them be drawn as GL lines, and the index buffer that
// draws them as quads.
#include "viewer/SegmentBuffers.h"

#include <algorithm>
#include <cstring>

namespace lcjit::viewer {

void SegmentBuffers::init(GLuint emptyVao) {
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexelsBuffer);
  if (maxTexelsBuffer < 2) maxTexelsBuffer = 65536;
  glGenBuffers(1, &quadEbo);
  glBindVertexArray(emptyVao);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, quadEbo);
  glBindVertexArray(0);
}

void SegmentBuffers::upload(const std::vector<runtime::Segment>& segments, GLuint emptyVao) {
  // Segments: 32 bytes each, in chunks that fit a buffer texture.
  const uint32_t segmentCount = (uint32_t)segments.size();
  uint32_t perChunk = (uint32_t)std::min<int64_t>(maxTexelsBuffer / 2, 1 << 22);
  size_t nChunks = (segmentCount + perChunk - 1) / perChunk;
  while (chunks.size() > nChunks) {
    glDeleteTextures(1, &chunks.back().texture);
    glDeleteBuffers(1, &chunks.back().buffer);
    if (chunks.back().groupEbo) glDeleteBuffers(1, &chunks.back().groupEbo);
    chunks.pop_back();
  }
  std::vector<float> data;
  for (size_t c = 0; c < nChunks; ++c) {
    if (c >= chunks.size()) {
      SegmentChunk sc;
      glGenBuffers(1, &sc.buffer);
      glGenTextures(1, &sc.texture);
      chunks.push_back(sc);
    }
    SegmentChunk& sc = chunks[c];
    sc.first = (uint32_t)(c * perChunk);
    sc.count = std::min(perChunk, segmentCount - sc.first);
    data.resize(size_t(sc.count) * 8);
    for (uint32_t i = 0; i < sc.count; ++i) {
      const runtime::Segment& s = segments[sc.first + i];
      float* d = &data[size_t(i) * 8];
      d[0] = s.from.x, d[1] = s.from.y, d[2] = s.from.z, d[3] = s.width;
      d[4] = s.to.x, d[5] = s.to.y, d[6] = s.to.z;
      int32_t color = s.color;
      std::memcpy(&d[7], &color, 4);
    }
    glBindBuffer(GL_TEXTURE_BUFFER, sc.buffer);
    glBufferData(GL_TEXTURE_BUFFER, data.size() * sizeof(float), data.data(), GL_STATIC_DRAW);
    glBindTexture(GL_TEXTURE_BUFFER, sc.texture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, sc.buffer);
  }
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
  glBindTexture(GL_TEXTURE_BUFFER, 0);

  widthRuns.clear();
  for (uint32_t i = 0; i < segmentCount; ++i) {
    float w = lineWidth(segments[i].width);
    if (widthRuns.empty() || widthRuns.back().second != w) widthRuns.push_back({i, w});
  }
  widthRuns.push_back({segmentCount, 0});

  // Fragmented widths: index lists per width, per chunk.
  const bool fragmented = segmentCount >= kGroupMinimum && (widthRuns.size() - 1) * 16 > segmentCount;
  for (SegmentChunk& sc : chunks) {
    sc.groups.clear();
    if (!fragmented) continue;
    std::vector<float> widths;
    for (uint32_t i = 0; i < sc.count; ++i) widths.push_back(lineWidth(segments[sc.first + i].width));
    std::vector<float> distinct = widths;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if (distinct.size() > 64) continue;  // too many widths: quads
    for (float w : distinct) sc.groups.push_back({w, 0, {}});
    for (uint32_t i = 0; i < sc.count; ++i) {
      size_t k = std::lower_bound(distinct.begin(), distinct.end(), widths[i]) - distinct.begin();
      sc.groups[k].ids.push_back(i);
    }
    std::vector<uint32_t> idx;
    idx.reserve(size_t(sc.count) * 2);
    for (WidthGroup& wg : sc.groups) {
      wg.offset = (uint32_t)idx.size();
      for (uint32_t id : wg.ids) {
        idx.push_back(2 * id);
        idx.push_back(2 * id + 1);
      }
    }
    if (!sc.groupEbo) glGenBuffers(1, &sc.groupEbo);
    glBindVertexArray(emptyVao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, sc.groupEbo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(uint32_t), idx.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, quadEbo);
    glBindVertexArray(0);
  }

  uint32_t needed = std::min(segmentCount, perChunk);
  if (needed > quadEboSegments) {
    std::vector<uint32_t> idx(size_t(needed) * 6);
    for (uint32_t s = 0; s < needed; ++s) {
      uint32_t* d = &idx[size_t(s) * 6];
      d[0] = 4 * s, d[1] = 4 * s + 1, d[2] = 4 * s + 2, d[3] = 4 * s, d[4] = 4 * s + 2, d[5] = 4 * s + 3;
    }
    glBindVertexArray(emptyVao);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, idx.size() * sizeof(uint32_t), idx.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    quadEboSegments = needed;
  }
}

void SegmentBuffers::release() {
  glDeleteBuffers(1, &quadEbo);
  for (SegmentChunk& c : chunks) {
    glDeleteBuffers(1, &c.buffer);
    glDeleteTextures(1, &c.texture);
    if (c.groupEbo) glDeleteBuffers(1, &c.groupEbo);
  }
}

}  // namespace lcjit::viewer
