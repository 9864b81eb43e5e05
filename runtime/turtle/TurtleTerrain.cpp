// The Terrain module (manual §10.3): the view file's terrain drawn in the turtle's frame, as
// lpfg's screen turtle draws it (see Turtle.h, Terrain.h).
#include "runtime/Terrain.h"
#include "runtime/turtle/Turtle.h"
#include "runtime/files/Images.h"

namespace lcjit::runtime {

void Turtle::drawTerrain(const CameraPosition& camera) {
  const TurtleState& t = state_;
  // lpfg moves the GL matrix into the frame (position; −L, H, U) even without a terrain.
  frames_.push_back({out_->vertices.size(), out_->segments.size(), out_->discs.size(), out_->labels.size(), t.position,
                     -t.left, t.heading, t.up});
  if (!setup_.terrain) return;
  const int id = setup_.terrain->textureId();
  const Image* image = setup_.textures && id >= 0 && id < (int)setup_.textures->size() ? &(*setup_.textures)[id] : nullptr;
  setup_.terrain->draw(camera, t.color, image, *out_);
  out_->oneSidedLighting = true;
  // lpfg's bounding box takes the terrain as it is, outside the turtle's frame.
  setup_.terrain->addExtent(out_->extent);
}

void Turtle::placeInFrames() {
  if (!out_) {
    frames_.clear();
    return;
  }
  Geometry& g = *out_;
  // Later marks are inner frames: apply them first.
  for (auto m = frames_.rbegin(); m != frames_.rend(); ++m) {
    if (m->origin.x == 0 && m->origin.y == 0 && m->origin.z == 0 && m->x.x == 1 && m->x.y == 0 && m->x.z == 0 &&
        m->y.x == 0 && m->y.y == 1 && m->y.z == 0 && m->z.x == 0 && m->z.y == 0 && m->z.z == 1)
      continue;  // the initial turtle's frame: nothing moves
    auto turn = [&](V3f v) { return V3f(m->x * v.x + m->y * v.y + m->z * v.z); };
    auto place = [&](V3f p) { return V3f(m->origin + turn(p)); };
    for (size_t i = m->vertices; i < g.vertices.size(); ++i) {
      g.vertices[i].position = place(g.vertices[i].position);
      g.vertices[i].normal = turn(g.vertices[i].normal);
    }
    for (size_t i = m->segments; i < g.segments.size(); ++i) {
      g.segments[i].from = place(g.segments[i].from);
      g.segments[i].to = place(g.segments[i].to);
    }
    for (size_t i = m->discs; i < g.discs.size(); ++i) g.discs[i].center = place(g.discs[i].center);
    for (size_t i = m->labels; i < g.labels.size(); ++i) g.labels[i].position = place(g.labels[i].position);
  }
  frames_.clear();
}

}  // namespace lcjit::runtime
