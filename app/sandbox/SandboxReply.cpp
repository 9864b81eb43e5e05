// The sandboxed window run's reply (see SandboxReply.h). Parent and child are the same lcjit
// binary, so arrays of plain structs go as their bytes; the version and the struct sizes in the
// header catch a reply from another build. Enumerations and indices are checked on reading.
#include "app/sandbox/SandboxReply.h"

#include <cstring>
#include <optional>
#include <type_traits>

namespace lcjit::app {
namespace {

constexpr char kMagic[4] = {'L', 'C', 'S', 'R'};
constexpr uint32_t kVersion = 3;

// The layout the raw arrays depend on: a reply from a build where it differs is refused.
uint32_t layoutStamp() {
  return uint32_t(sizeof(runtime::MeshVertex) | sizeof(runtime::TriangleRun) << 6 | sizeof(runtime::Segment) << 12 |
                  sizeof(runtime::Disc) << 18 | sizeof(runtime::Light) << 24);
}

class Writer {
 public:
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void flag(bool b) { pod<uint8_t>(b); }
  void str(const std::string& s) {
    pod<uint64_t>(s.size());
    out.append(s);
  }
  template <class T>
  void pods(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod<uint64_t>(v.size());
    out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(std::string_view bytes) : p_(bytes.data()), end_(bytes.data() + bytes.size()) {}
  template <class T>
  bool pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (!need(sizeof v, "a value")) return false;
    std::memcpy(&v, p_, sizeof v);
    p_ += sizeof v;
    return true;
  }
  bool flag(bool& b) {
    uint8_t u = 0;
    if (!pod(u)) return false;
    if (u > 1) return bad("a flag is neither 0 nor 1");
    b = u;
    return true;
  }
  template <class E>
  bool enumeration(E& e, E last) {
    std::underlying_type_t<E> u{};
    if (!pod(u)) return false;
    if (u < 0 || u > static_cast<std::underlying_type_t<E>>(last)) return bad("an enumeration is out of range");
    e = E(u);
    return true;
  }
  bool count(uint64_t& n, size_t elementSize) {
    if (!pod(n)) return false;
    // Never more elements than the bytes left could hold: the allocation is bounded by the reply.
    if (n > uint64_t(end_ - p_) / (elementSize ? elementSize : 1)) return bad("a length is past the reply's end");
    return true;
  }
  bool str(std::string& s) {
    uint64_t n = 0;
    if (!count(n, 1)) return false;
    s.assign(p_, n);
    p_ += n;
    return true;
  }
  template <class T>
  bool pods(std::vector<T>& v) {
    uint64_t n = 0;
    if (!count(n, sizeof(T))) return false;
    v.resize(n);
    std::memcpy(v.data(), p_, n * sizeof(T));
    p_ += n * sizeof(T);
    return true;
  }
  bool bad(const std::string& why) {
    if (error.empty()) error = why;
    return false;
  }
  bool atEnd() const { return p_ == end_; }
  std::string error;

 private:
  bool need(size_t n, const char* what) {
    if (size_t(end_ - p_) >= n) return true;
    return bad(std::string("it ends inside ") + what);
  }
  const char* p_;
  const char* end_;
};

void putGeometry(Writer& w, const runtime::Geometry& g) {
  w.pods(g.vertices);
  w.pods(g.indices);
  w.pods(g.runs);
  w.pods(g.segments);
  w.pods(g.discs);
  w.pod<uint64_t>(g.labels.size());
  for (const runtime::Label& l : g.labels) {
    w.pod(l.position);
    w.pod(l.color);
    w.str(l.text);
  }
  w.flag(g.camera.has_value());
  if (g.camera) w.pod(*g.camera);
  w.flag(g.oneSidedLighting);
  w.pod(g.extent);
  w.pods(g.order);
}

bool getGeometry(Reader& r, runtime::Geometry& g, size_t textures) {
  uint64_t labels = 0;
  if (!r.pods(g.vertices) || !r.pods(g.indices) || !r.pods(g.runs) || !r.pods(g.segments) || !r.pods(g.discs) ||
      !r.count(labels, sizeof(V3f) + 4 + 8))
    return false;
  g.labels.resize(labels);
  for (runtime::Label& l : g.labels)
    if (!r.pod(l.position) || !r.pod(l.color) || !r.str(l.text)) return false;
  bool camera = false;
  if (!r.flag(camera)) return false;
  if (camera && !r.pod(g.camera.emplace())) return false;
  if (!r.flag(g.oneSidedLighting) || !r.pod(g.extent) || !r.pods(g.order)) return false;
  // What the renderer indexes with must be inside what it indexes.
  if (g.indices.size() % 3) return r.bad("the triangle indices are not whole triangles");
  for (uint32_t i : g.indices)
    if (i >= g.vertices.size()) return r.bad("a triangle index is past the vertices");
  uint64_t next = 0;
  for (const runtime::TriangleRun& run : g.runs) {
    if (run.firstIndex != next || uint64_t(run.firstIndex) + run.indexCount > g.indices.size())
      return r.bad("the triangle runs do not partition the indices");
    if (run.texture < -1 || (run.texture >= 0 && size_t(run.texture) >= textures))
      return r.bad("a triangle run's texture is not one of the textures");
    if (uint8_t(run.fill) > uint8_t(runtime::PolygonFill::Solid)) return r.bad("an enumeration is out of range");
    next += run.indexCount;
  }
  if (next != g.indices.size()) return r.bad("the triangle runs do not partition the indices");
  for (const runtime::DrawBatch& b : g.order) {
    uint64_t size = b.kind == runtime::DrawBatch::Kind::Triangles  ? g.indices.size()
                    : b.kind == runtime::DrawBatch::Kind::Segments ? g.segments.size()
                    : b.kind == runtime::DrawBatch::Kind::Discs    ? g.discs.size()
                    : b.kind == runtime::DrawBatch::Kind::Labels   ? g.labels.size()
                                                                   : 0;
    if (uint8_t(b.kind) > uint8_t(runtime::DrawBatch::Kind::Labels)) return r.bad("an enumeration is out of range");
    if (uint64_t(b.first) + b.count > size) return r.bad("a drawing batch is past its primitives");
  }
  return true;
}

void putView(Writer& w, const runtime::ViewSettings& v) {
  w.pod(v.projection), w.pod(v.scale), w.pod(v.minZoom), w.pod(v.maxZoom), w.pod(v.lineStyle);
  w.flag(v.frontDistance.has_value()), w.pod(v.frontDistance.value_or(0));
  w.flag(v.backDistance.has_value()), w.pod(v.backDistance.value_or(0));
  w.pod(v.generateOnViewChange);
  w.pod<uint64_t>(v.views.size());
  for (const runtime::ViewDefinition& d : v.views) {
    w.pod(d.id);
    for (const std::optional<V3f>* o : {&d.dir, &d.up, &d.pan}) w.flag(o->has_value()), w.pod(o->value_or(V3f()));
    for (const std::optional<float>* o : {&d.fov, &d.shift, &d.scale}) w.flag(o->has_value()), w.pod(o->value_or(0.f));
  }
  w.pods(v.boxes);
  w.pod<uint64_t>(v.windows.size());
  for (const runtime::WindowDefinition& d : v.windows) {
    w.str(d.name);
    w.pod(d.left), w.pod(d.top), w.pod(d.width), w.pod(d.height);
  }
  w.pod(v.windowBorderSize), w.pod(v.windowBorderColor), w.flag(v.zBuffer), w.pod(v.renderMode);
  w.pods(v.lights);
  w.pod(v.shadowMapSize), w.pod(v.shadowColor), w.pod(v.shadowOffsetFactor), w.pod(v.shadowOffsetUnits);
  w.flag(v.stationaryLights), w.pod(v.contourSides), w.flag(v.backfaceCulling), w.flag(v.concavePolygons);
  w.pod(v.gradientDirection), w.pod(v.gradientMagnitude), w.pod(v.antialiasingSamples), w.pod(v.wireframeLineWidth);
  w.flag(v.cappedCylinders), w.flag(v.taperedCylinders), w.flag(v.automaticNormals), w.pod(v.postscriptLinecap);
  w.pod<uint64_t>(v.textures.size());
  for (const std::string& t : v.textures) w.str(t);
  w.str(v.font), w.str(v.winFont), w.pod(v.winFontSize), w.pod(v.winFontWeight), w.flag(v.winFontItalic);
  w.flag(v.correctedRotation), w.flag(v.correctedRotationGiven);
}

bool getView(Reader& r, runtime::ViewSettings& v) {
  using namespace runtime;
  bool front = false, back = false;
  float frontValue = 0, backValue = 0;
  uint64_t views = 0, windows = 0, textures = 0;
  bool ok = r.enumeration(v.projection, Projection::Perspective) && r.pod(v.scale) && r.pod(v.minZoom) &&
            r.pod(v.maxZoom) && r.enumeration(v.lineStyle, LineStyle::Cylinder) && r.flag(front) &&
            r.pod(frontValue) && r.flag(back) && r.pod(backValue) &&
            r.enumeration(v.generateOnViewChange, ViewSettings::Regenerate::Triggered) && r.count(views, 4 + 6);
  if (!ok) return false;
  v.views.resize(views);
  for (ViewDefinition& d : v.views) {
    if (!r.pod(d.id)) return false;
    for (std::optional<V3f>* o : {&d.dir, &d.up, &d.pan}) {
      bool has = false;
      V3f value;
      if (!r.flag(has) || !r.pod(value)) return false;
      if (has) *o = value;
    }
    for (std::optional<float>* o : {&d.fov, &d.shift, &d.scale}) {
      bool has = false;
      float value = 0;
      if (!r.flag(has) || !r.pod(value)) return false;
      if (has) *o = value;
    }
  }
  if (!r.pods(v.boxes) || !r.count(windows, 8 + 16)) return false;
  if (front) v.frontDistance = frontValue;
  if (back) v.backDistance = backValue;
  v.windows.resize(windows);
  for (WindowDefinition& d : v.windows)
    if (!r.str(d.name) || !r.pod(d.left) || !r.pod(d.top) || !r.pod(d.width) || !r.pod(d.height)) return false;
  ok = r.pod(v.windowBorderSize) && r.pod(v.windowBorderColor) && r.flag(v.zBuffer) &&
       r.enumeration(v.renderMode, RenderMode::Shadows) && r.pods(v.lights) && r.pod(v.shadowMapSize) &&
       r.pod(v.shadowColor) && r.pod(v.shadowOffsetFactor) && r.pod(v.shadowOffsetUnits) &&
       r.flag(v.stationaryLights) && r.pod(v.contourSides) && r.flag(v.backfaceCulling) &&
       r.flag(v.concavePolygons) && r.pod(v.gradientDirection) && r.pod(v.gradientMagnitude) &&
       r.pod(v.antialiasingSamples) && r.pod(v.wireframeLineWidth) && r.flag(v.cappedCylinders) &&
       r.flag(v.taperedCylinders) && r.flag(v.automaticNormals) && r.pod(v.postscriptLinecap) &&
       r.count(textures, 8);
  if (!ok) return false;
  v.textures.resize(textures);
  for (std::string& t : v.textures)
    if (!r.str(t)) return false;
  ok = r.str(v.font) && r.str(v.winFont) && r.pod(v.winFontSize) && r.pod(v.winFontWeight) &&
       r.flag(v.winFontItalic) && r.flag(v.correctedRotation) && r.flag(v.correctedRotationGiven);
  if (!ok) return false;
  for (const Light& l : v.lights)
    if (int(l.kind) < 0 || l.kind > Light::Kind::Spot) return r.bad("an enumeration is out of range");
  // The renderer's own bounds: a shadow map or multisampling past them is a GL error, not a picture.
  if (v.lights.size() > 8 || v.shadowMapSize < 1 || v.shadowMapSize > 16384 || v.antialiasingSamples < 0 ||
      v.antialiasingSamples > 16 || v.windowBorderSize < 0 || v.windowBorderSize > 10000)
    return r.bad("a view setting is out of range");
  return true;
}

}  // namespace

std::string encodeSandboxReply(const SandboxReply& reply) {
  Writer w;
  w.out.append(kMagic, 4);
  w.pod(kVersion);
  w.pod(layoutStamp());
  w.pod(reply.steps), w.pod(reply.derivationLength), w.flag(reply.derived);
  const SandboxReply::Animation& a = reply.animation;
  w.pod(a.firstFrame), w.pod(a.lastFrame), w.pod(a.step), w.pod(a.swapIntervalMs);
  w.flag(a.hcenter), w.flag(a.scale), w.flag(a.newView);
  w.str(reply.message);
  w.str(reply.unanswered);
  w.flag(reply.hasPicture);
  if (!reply.hasPicture) return w.out;
  w.pod<uint64_t>(reply.textures.size());
  for (const runtime::Image& t : reply.textures) {
    w.pod(t.width), w.pod(t.height);
    w.pods(t.rgba);
  }
  putGeometry(w, reply.main);
  w.pod<uint64_t>(reply.panes.size());
  for (const viewer::ViewPane& p : reply.panes) {
    putGeometry(w, p.geometry);
    w.pod(p.rect), w.pod(p.viewId);
  }
  putView(w, reply.view);
  w.flag(reply.palette.materials);
  w.pod(reply.palette.color);
  w.pod(reply.palette.material);
  return w.out;
}

llvm::Expected<SandboxReply> decodeSandboxReply(std::string_view bytes) {
  auto fail = [](const std::string& why) {
    return llvm::createStringError("the sandboxed run's reply is damaged: " + why);
  };
  if (bytes.size() < 12 || std::memcmp(bytes.data(), kMagic, 4) != 0) return fail("it does not start as one");
  Reader r(bytes.substr(4));
  uint32_t version = 0, stamp = 0;
  r.pod(version), r.pod(stamp);
  if (version != kVersion || stamp != layoutStamp()) return fail("it comes from another build of lcjit");
  SandboxReply reply;
  auto damaged = [&] { return fail(r.error.empty() ? std::string("it is malformed") : r.error); };
  if (!r.pod(reply.steps) || !r.pod(reply.derivationLength) || !r.flag(reply.derived)) return damaged();
  SandboxReply::Animation& a = reply.animation;
  if (!r.pod(a.firstFrame) || !r.pod(a.lastFrame) || !r.pod(a.step) || !r.pod(a.swapIntervalMs) ||
      !r.flag(a.hcenter) || !r.flag(a.scale) || !r.flag(a.newView))
    return damaged();
  // The window waits the swap interval and counts frames with these: keep them sane.
  if (a.firstFrame < 0 || a.lastFrame < 0 || a.step < 1 || a.swapIntervalMs < 0 || a.swapIntervalMs > 3600000)
    return fail("its animation settings are out of range");
  if (!r.str(reply.message) || !r.str(reply.unanswered) || !r.flag(reply.hasPicture)) return damaged();
  if (reply.hasPicture) {
    uint64_t textures = 0, panes = 0;
    if (!r.count(textures, 16)) return damaged();
    reply.textures.resize(textures);
    for (runtime::Image& t : reply.textures) {
      if (!r.pod(t.width) || !r.pod(t.height) || !r.pods(t.rgba)) return damaged();
      if (t.width < 0 || t.height < 0 || t.rgba.size() != uint64_t(t.width) * uint64_t(t.height) * 4)
        return fail("a texture's size is not its pixels'");
    }
    if (!getGeometry(r, reply.main, textures) || !r.count(panes, 8)) return damaged();
    reply.panes.resize(panes);
    for (viewer::ViewPane& p : reply.panes) {
      if (!getGeometry(r, p.geometry, textures) || !r.pod(p.rect) || !r.pod(p.viewId)) return damaged();
      // Fractions of the window's picture, as interpretViews keeps them (NaN fails too).
      for (float f : {p.rect.left, p.rect.top, p.rect.width, p.rect.height})
        if (!(f >= 0 && f <= 1)) return fail("a view's rectangle lies outside the picture");
    }
    if (!getView(r, reply.view) || !r.flag(reply.palette.materials) || !r.pod(reply.palette.color) ||
        !r.pod(reply.palette.material))
      return damaged();
  }
  if (!r.atEnd()) return fail("there are bytes past its end");
  return std::move(reply);
}

}  // namespace lcjit::app
