// POV-Ray 3.7 scene: the renderer's camera (explicit right-handed vectors, no look_at, so the
// picture is not mirrored), the view file's lights, background colour 0, one texture per colour
// used (lpfg's names s001…; rgb_FF8000 for an explicit colour), the triangles as one mesh2,
// segments as cylinders sized from their pixel width, discs facing the camera, labels as text.
#include <algorithm>
#include <cmath>
#include <unordered_map>


#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"
#include "runtime/text/LabelText.h"

namespace lcjit::runtime::exporting {
namespace {

struct P3 {
  V3f v;
};
struct P2 {
  V2f v;
};

}  // namespace
}  // namespace lcjit::runtime::exporting

template <> struct fmt::formatter<lcjit::runtime::exporting::P3> {
  constexpr auto parse(format_parse_context& ctx) { return ctx.begin(); }
  auto format(const lcjit::runtime::exporting::P3& p, format_context& ctx) const {
    return fmt::format_to(ctx.out(), "<{},{},{}>", p.v.x + 0.0f, p.v.y + 0.0f, p.v.z + 0.0f);
  }
};
template <> struct fmt::formatter<lcjit::runtime::exporting::P2> {
  constexpr auto parse(format_parse_context& ctx) { return ctx.begin(); }
  auto format(const lcjit::runtime::exporting::P2& p, format_context& ctx) const {
    return fmt::format_to(ctx.out(), "<{},{}>", p.v.x + 0.0f, p.v.y + 0.0f);
  }
};

namespace lcjit::runtime::exporting {
namespace {

const char* imageType(const std::string& file) {
  std::string ext = lowerExtension(file);
  if (ext == "png") return "png";
  if (ext == "jpg" || ext == "jpeg") return "jpeg";
  if (ext == "tga") return "tga";
  if (ext == "gif") return "gif";
  if (ext == "bmp") return "bmp";
  if (ext == "ppm") return "ppm";
  if (ext == "pgm") return "pgm";
  if (ext == "tif" || ext == "tiff") return "tiff";
  if (ext == "exr") return "exr";
  if (ext == "hdr") return "hdr";
  return nullptr;
}

// A string literal: valid UTF-8 (the scene says charset utf8), quotes and backslashes escaped,
// controls dropped.
std::string povString(std::string_view s) {
  std::string out;
  for (char c : text::cleanUtf8(s)) {
    if (c == '"' || c == '\\') out += '\\';
    if ((unsigned char)c >= 0x20) out += c;
  }
  return out;
}

}  // namespace

llvm::Error writePov(const Context& cx) {
  const Geometry& g = cx.geometry;
  const CameraMatrices& cam = cx.camera();
  const CameraFrame f = cameraFrame(cam);
  const V3f dir = -f.back;
  Bounds bounds = g.bounds();
  if (bounds.empty()) bounds.add(V3f(0, 0, 0));
  const V3f centre = bounds.center();
  const float radius = std::max(1e-3f, (bounds.max - bounds.min).Length() / 2);
  const float W = (float)std::max(1, cam.width);
  const glm::mat4& P = cam.projection;
  const V3f eye = toV3(cam.eye);

  FileWriter w;
  if (auto e = w.open(cx.path)) return e;
  w.print("// POV-Ray scene written by lcjit: {} triangles, {} segments, {} discs, {} labels\n", g.triangleCount(),
          g.segments.size(), g.discs.size(), g.labels.size());
  w.print("// render: povray +I{} +W{} +H{} +A\n#version 3.7;\n", baseName(cx.path), cam.width, cam.height);

  // lpfg draws colormap colours (and explicit ones) unlit (flat: emission only here) and
  // materials lit.
  std::vector<Light> lights = cx.view.lights;
  if (lights.empty()) lights.push_back(Light());
  Rgb ambient{0.2f, 0.2f, 0.2f};  // OpenGL's global ambient, plus every light's
  for (const Light& l : lights) ambient.r += l.ambient.r, ambient.g += l.ambient.g, ambient.b += l.ambient.b;
  w.print("global_settings {{ assumed_gamma 1.0 ambient_light srgb <{},{},{}> charset utf8 }}\n", ambient.r, ambient.g,
          ambient.b);
  const Rgba& bg = cx.color(0);
  w.print("background {{ srgb <{},{},{}> }}\n\n", bg[0], bg[1], bg[2]);

  // Camera. Ray through image point (sx, sy) ∈ [-½, ½]²: direction + sx·right + sy·up.
  const float viewWidth = 2 / P[0][0], viewHeight = 2 / P[1][1];
  w.print("camera {{\n");
  if (cam.perspective) {
    V3f d = dir + f.right * (P[2][0] / P[0][0]) + f.up * (P[2][1] / P[1][1]);  // off-centre frustum
    w.print("  perspective\n  location {}\n  direction {}\n", P3{eye}, P3{d});
  } else {
    // Rays start on the plane through `location`: put it in front of everything drawn.
    V3f c = eye + f.right * (-P[3][0] / P[0][0]) + f.up * (-P[3][1] / P[1][1]);
    float tmin = 0;
    for (int i = 0; i < 8; ++i) {
      V3f corner((i & 1) ? bounds.max.x : bounds.min.x, (i & 2) ? bounds.max.y : bounds.min.y,
                 (i & 4) ? bounds.max.z : bounds.min.z);
      tmin = std::min(tmin, (corner - c) * dir);
    }
    c = c + dir * (tmin - 0.01f * radius);
    w.print("  orthographic\n  location {}\n  direction {}\n", P3{c}, P3{dir});
  }
  w.print("  right {}\n  up {}\n}}\n\n", P3{f.right * viewWidth}, P3{f.up * viewHeight});

  // Lights. Stationary ones (lpfg's default) are placed through the initial view's translation
  // only, so they stay fixed relative to the camera; the others are in model space.
  const glm::mat4 toModel = lightToModel(cx);
  auto toModelDir = [&](V3f d) { return toV3(glm::mat3(toModel) * toGlm(d)); };
  auto toModelPoint = [&](V3f p) {
    glm::vec4 q = toModel * glm::vec4(toGlm(p), 1);
    return V3f(q.x, q.y, q.z);
  };
  if (!cx.palette.usesMaterials())
    w.text("// colormap mode: drawn unlit, as lpfg does; the lights matter only for materials\n");
  for (const Light& l : lights) {
    const Rgb& c = l.diffuse;
    if (l.kind == Light::Kind::Directional) {
      V3f d = unit(toModelDir(l.position));
      w.print("light_source {{ {}, srgb <{},{},{}> parallel point_at {} }}\n", P3{centre + d * (100 * radius)}, c.r,
              c.g, c.b, P3{centre});
    } else {
      V3f p = toModelPoint(l.position);
      w.print("light_source {{ {}, srgb <{},{},{}>", P3{p}, c.r, c.g, c.b);
      if (l.kind == Light::Kind::Spot && l.spotCutoff < 180) {
        V3f d = unit(toModelDir(l.spotDirection));
        float cutoff = std::min(l.spotCutoff, 90.0f);
        w.print(" spotlight point_at {} radius {} falloff {} tightness {}", P3{p + d}, cutoff * 0.8f, cutoff,
                std::min(100.0f, l.spotExponent));
      }
      w.print(" }}\n");
    }
  }
  w.text("\n");

  // Textures: one per (colour, texture) of the triangles and per colour of segments and discs;
  // labels get their own (lpfg's text colour).
  std::vector<MaterialKey> keys = usedMaterials(g);
  auto need = [&](int color) {
    MaterialKey k{colorKey(color), -1};
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  };
  for (const Segment& s : g.segments) need(s.color);
  for (const Disc& d : g.discs) need(d.color);
  const char* flat = "ambient 0 diffuse 0 emission 1";
  for (MaterialKey k : keys) {
    std::string pigment, finish;
    if (const Material* lit = cx.material(k.color)) {
      const Material& m = *lit;
      pigment = fmt::format("srgbt <{},{},{},{}>", m.diffuse[0], m.diffuse[1], m.diffuse[2], m.transparency);
      float spec = (m.specular[0] + m.specular[1] + m.specular[2]) / 3;
      finish = fmt::format("ambient srgb <{},{},{}> diffuse 1", m.ambient[0], m.ambient[1], m.ambient[2]);
      if (spec > 0) finish += fmt::format(" phong {} phong_size {}", spec, std::max(1.0f, m.shininess));
      if (m.emission[0] > 0 || m.emission[1] > 0 || m.emission[2] > 0)
        finish += fmt::format(" emission srgb <{},{},{}>", m.emission[0], m.emission[1], m.emission[2]);
    } else {
      const Rgba col = cx.color(k.color);
      pigment = fmt::format("srgbt <{},{},{},{}>", col[0], col[1], col[2], 1 - col[3]);
      finish = flat;
    }
    std::string file = k.texture >= 0 ? cx.texturePath(k.texture) : std::string();
    const char* type = file.empty() ? nullptr : imageType(file);
    if (type)
      w.print("#declare {} = texture {{ uv_mapping pigment {{ image_map {{ {} \"{}\" interpolate 2 }} }} finish {{ {} }} }}\n",
              materialName(k), type, povString(file), finish);
    else
      w.print("#declare {} = texture {{ pigment {{ {} }} finish {{ {} }} }}\n", materialName(k), pigment, finish);
  }
  std::vector<int> labelColors;
  for (const Label& l : g.labels)
    if (std::find(labelColors.begin(), labelColors.end(), colorKey(l.color)) == labelColors.end())
      labelColors.push_back(colorKey(l.color));
  for (int c : labelColors) {
    const Rgba t = cx.textColor(c);
    w.print("#declare text_{} = texture {{ pigment {{ srgb <{},{},{}> }} finish {{ {} }} }}\n",
            materialName({c, -1}), t[0], t[1], t[2], flat);
  }
  w.text("\n");

  // The triangles: one mesh2 with a texture per face.
  if (g.triangleCount()) {
    const std::vector<V3f> normals = unitNormals(g);  // discs are written as discs below
    const size_t nv = g.vertices.size();
    bool textured = false;
    for (const TriangleRun& r : g.runs)
      if (r.texture >= 0 && r.indexCount) textured = true;
    w.print("mesh2 {{\n  vertex_vectors {{ {}", nv);
    for (const MeshVertex& v : g.vertices) w.print(",\n    {}", P3{v.position});
    w.print("\n  }}\n  normal_vectors {{ {}", nv);
    for (size_t i = 0; i < nv; ++i) w.print(",\n    {}", P3{normals[i]});
    w.text("\n  }\n");
    if (textured) {
      w.print("  uv_vectors {{ {}", nv);
      for (const MeshVertex& v : g.vertices) w.print(",\n    {}", P2{v.uv});
      w.text("\n  }\n");
    }
    std::unordered_map<int64_t, int> slot;
    std::vector<MaterialKey> meshKeys = usedMaterials(g);
    w.print("  texture_list {{ {}", meshKeys.size());
    for (size_t i = 0; i < meshKeys.size(); ++i) {
      slot[meshKeys[i].packed()] = (int)i;
      w.print(",\n    texture {{ {} }}", materialName(meshKeys[i]));
    }
    w.print("\n  }}\n  face_indices {{ {}", g.triangleCount());
    MaterialKey last{-1000, -1000};
    int s = 0;
    forEachTriangle(g, [&](size_t, uint32_t a, uint32_t b, uint32_t c, int texture) {
      MaterialKey k{colorKey(g.vertices[a].color), texture};
      if (!(k == last)) s = slot[k.packed()], last = k;
      w.print(",\n    <{},{},{}>,{}", a, b, c, s);
    });
    w.text("\n  }\n");
    w.text("}\n\n");
  }

  // Pixel-wide segments: cylinders as wide as the segment looks in the picture.
  auto pixelSize = [&](V3f p) {
    float ortho = viewWidth / W;
    if (!cam.perspective) return ortho;
    float depth = std::max(1e-6f, (p - eye) * dir);
    return depth * viewWidth / W;
  };
  for (const Segment& s : g.segments) {
    if (sameVector(s.from, s.to)) continue;
    float r = std::max(1e-6f, 0.5f * s.width * pixelSize((s.from + s.to) * 0.5f));
    w.print("cylinder {{ {}, {}, {} texture {{ {} }} }}\n", P3{s.from}, P3{s.to}, r, materialName({colorKey(s.color), -1}));
  }
  for (const Disc& d : g.discs) {
    w.print("disc {{ {}, {}, {}", P3{d.center}, P3{f.back}, d.outer);
    if (d.inner > 0) w.print(", {}", d.inner);
    w.print(" texture {{ {} }} }}\n", materialName({colorKey(d.color), -1}));
  }
  for (const Label& l : g.labels) {
    float h = cx.view.winFontSize * pixelSize(l.position);
    V3f x = f.right * h, y = f.up * h, z = f.back * h;
    w.print("text {{ ttf \"timrom.ttf\" \"{}\" 0.01, 0 texture {{ {} }} matrix <{},{},{}, {},{},{}, {},{},{}, {},{},{}> }}\n",
            povString(l.text), "text_" + materialName({colorKey(l.color), -1}), x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z,
            l.position.x, l.position.y, l.position.z);
  }
  return w.close();
}

}  // namespace lcjit::runtime::exporting
