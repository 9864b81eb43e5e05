// Geometry as data: what the turtle interpretation produces (manual §5) and what renderers and
// exporters consume. Nothing here knows about OpenGL; colours are lpfg colour/material indices
// (0..255) resolved against a Palette by whoever draws, so a colormap change needs no
// re-interpretation.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

// Colours are lpfg colour/material indices 0..255, or kRgbColor | 0xRRGGBB: a colour drawn as it
// is, unlit, whatever the palette (what lpfg draws with glColor3f and lighting off, e.g. the
// terrain's grid).
constexpr int32_t kRgbColor = 0x1000000;
inline bool isRgbColor(int32_t c) { return c >= kRgbColor; }
inline int32_t rgbColor(uint8_t r, uint8_t g, uint8_t b) { return kRgbColor | (r << 16) | (g << 8) | b; }

struct MeshVertex {
  V3f position;
  V3f normal;  // unit length; (0,0,0) for vertices drawn unlit
  V2f uv;      // texture coordinates (0,0 when untextured)
  int32_t color = 1;
};

// How a run's triangles are drawn: as the render mode says (Default), or outlined (Lines) or
// filled (Solid) whatever it says, as lpfg's terrain patches switch glPolygonMode.
enum class PolygonFill : uint8_t { Default, Lines, Solid };

// A run of triangles sharing one texture (-1: untextured) and fill. Runs partition `indices`.
struct TriangleRun {
  uint32_t firstIndex = 0, indexCount = 0;
  int texture = -1;
  PolygonFill fill = PolygonFill::Default;
};

// `line style: pixel` segments (F, G, LineTo…): width is the turtle width, in pixels.
struct Segment {
  V3f from, to;
  float width = 1;
  int32_t color = 1;
};

// Screen-plane circles (CircleFront*, CircleFrontB): they face the camera, so they stay abstract
// until a view exists. inner = 0 for a filled disc.
struct Disc {
  V3f center;
  float inner = 0, outer = 0;
  int32_t color = 1;
};

struct Label {
  V3f position;
  std::string text;
  int32_t color = 1;
};

// The Camera module: the view looks from `position` along `heading` with `up` (manual §5.3.4).
struct CameraPose {
  V3f position, heading{0, 1, 0}, up{0, 0, 1};
};

struct Bounds {
  V3f min{1e30f, 1e30f, 1e30f}, max{-1e30f, -1e30f, -1e30f};
  bool empty() const { return min.x > max.x; }
  void add(V3f p) {
    if (p.x < min.x) min.x = p.x;
    if (p.y < min.y) min.y = p.y;
    if (p.z < min.z) min.z = p.z;
    if (p.x > max.x) max.x = p.x;
    if (p.y > max.y) max.y = p.y;
    if (p.z > max.z) max.z = p.z;
  }
  void add(const Bounds& b) {
    if (!b.empty()) {
      add(b.min);
      add(b.max);
    }
  }
  V3f center() const { return (min + max) * 0.5f; }
};

// Interpretation order across primitive kinds (painter order matters with `z buffer: off`, lpfg's
// default): each batch is a contiguous range of one kind (`first`/`count` count indices for
// triangles, elements for segments, discs and labels). Producers using addTriangle/addSegment/
// addDisc/addLabel get it for free. lpfg draws a label when its turtle meets it, so what is drawn
// after a label covers it, z buffer or not. If the batches do not cover every primitive (something
// pushed into the vectors directly), renderers ignore them and draw segments, then triangles, then
// discs, then labels.
struct DrawBatch {
  enum class Kind : uint8_t { Triangles, Segments, Discs, Labels } kind = Kind::Triangles;
  uint32_t first = 0, count = 0;
};

struct Geometry {
  std::vector<MeshVertex> vertices;
  std::vector<uint32_t> indices;  // triangles, three per face, counter-clockwise = front
  std::vector<TriangleRun> runs;
  std::vector<Segment> segments;
  std::vector<Disc> discs;
  std::vector<Label> labels;
  std::optional<CameraPose> camera;
  // lpfg's terrain turns two-sided lighting off when it is done, GL state that lasts into every
  // later frame: once a terrain was drawn, lpfg's pictures light everything but the terrain
  // one-sided (a back face with its front normal). Set: lit so, except runs with their own fill
  // (the terrain's) and unlit primitives.
  bool oneSidedLighting = false;
  // lpfg's bounding box, which framing uses: built by the turtle with lpfg's rules (f/g moves
  // count, MoveTo does not, labels and pixel widths do not). Empty: use bounds().
  Bounds extent;

  // Picking (MouseIns, manual §5.9): with trackSources set, each triangle, segment and disc
  // records `currentSource`, the string offset of the module whose interpretation drew it.
  bool trackSources = false;
  uint32_t currentSource = 0;
  std::vector<uint32_t> triangleSources, segmentSources, discSources;
  std::vector<DrawBatch> order;

  void clear() { *this = Geometry(); }
  size_t triangleCount() const { return indices.size() / 3; }
  bool empty() const { return indices.empty() && segments.empty() && discs.empty() && labels.empty(); }

  // Everything drawn: triangles, segment ends (widened by nothing: pixel widths have no model
  // size), discs with their radius, label anchors. This is lpfg's bounding box.
  Bounds bounds() const {
    Bounds b;
    for (const MeshVertex& v : vertices) b.add(v.position);
    for (const Segment& s : segments) {
      b.add(s.from);
      b.add(s.to);
    }
    for (const Disc& d : discs) {
      b.add(d.center - V3f(d.outer, d.outer, d.outer));
      b.add(d.center + V3f(d.outer, d.outer, d.outer));
    }
    for (const Label& l : labels) b.add(l.position);
    return b;
  }

  // What framing (the camera) fits: lpfg's box when the turtle built one, else bounds().
  Bounds framingBounds() const { return extent.empty() ? bounds() : extent; }

  // Starts a triangle run with `texture` and `fill` unless the last run already has them.
  void useTexture(int texture, PolygonFill fill = PolygonFill::Default) {
    if (runs.empty() || runs.back().texture != texture || runs.back().fill != fill) {
      if (!runs.empty() && runs.back().indexCount == 0) runs.back().texture = texture, runs.back().fill = fill;
      else runs.push_back({(uint32_t)indices.size(), 0, texture, fill});
    }
  }
  uint32_t addVertex(const MeshVertex& v) {
    vertices.push_back(v);
    return (uint32_t)vertices.size() - 1;
  }
  void addTriangle(uint32_t a, uint32_t b, uint32_t c) {
    if (runs.empty()) runs.push_back({(uint32_t)indices.size(), 0, -1});
    indices.push_back(a);
    indices.push_back(b);
    indices.push_back(c);
    runs.back().indexCount += 3;
    noteOrder(DrawBatch::Kind::Triangles, (uint32_t)indices.size() - 3, 3);
    if (trackSources) triangleSources.push_back(currentSource);
  }
  void addSegment(const Segment& s) {
    segments.push_back(s);
    noteOrder(DrawBatch::Kind::Segments, (uint32_t)segments.size() - 1, 1);
    if (trackSources) segmentSources.push_back(currentSource);
  }
  void addDisc(const Disc& d) {
    discs.push_back(d);
    noteOrder(DrawBatch::Kind::Discs, (uint32_t)discs.size() - 1, 1);
    if (trackSources) discSources.push_back(currentSource);
  }
  void addLabel(const Label& l) {
    labels.push_back(l);
    noteOrder(DrawBatch::Kind::Labels, (uint32_t)labels.size() - 1, 1);
  }
  // Records that [first, first+count) of `kind` comes next in drawing order.
  void noteOrder(DrawBatch::Kind kind, uint32_t first, uint32_t count) {
    if (!order.empty() && order.back().kind == kind && order.back().first + order.back().count == first)
      order.back().count += count;
    else
      order.push_back({kind, first, count});
  }
};

}  // namespace lcjit::runtime
