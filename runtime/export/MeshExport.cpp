// Wavefront OBJ (+ MTL), PLY and STL.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"

namespace lcjit::runtime::exporting {
namespace {

uint8_t toByte(float c) { return (uint8_t)std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f); }

void writeMaterial(FileWriter& w, const Context& cx, MaterialKey key) {
  w.print("newmtl {}\n", materialName(key));
  if (const Material* lit = cx.material(key.color)) {
    const Material& m = *lit;
    w.print("Ka {} {} {}\n", m.ambient[0], m.ambient[1], m.ambient[2]);
    w.print("Kd {} {} {}\n", m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    w.print("Ks {} {} {}\n", m.specular[0], m.specular[1], m.specular[2]);
    if (m.emission[0] > 0 || m.emission[1] > 0 || m.emission[2] > 0)
      w.print("Ke {} {} {}\n", m.emission[0], m.emission[1], m.emission[2]);
    w.print("Ns {}\n", m.shininess);
    if (m.transparency > 0) w.print("d {}\n", 1 - m.transparency);
    bool specular = m.specular[0] > 0 || m.specular[1] > 0 || m.specular[2] > 0;
    w.print("illum {}\n", specular ? 2 : 1);
  } else {
    const Rgba c = cx.color(key.color);
    w.print("Ka 0 0 0\nKd {} {} {}\nKs 0 0 0\nNs 1\n", c[0], c[1], c[2]);
    if (c[3] < 1) w.print("d {}\n", c[3]);
    w.print("illum 1\n");
  }
  if (key.texture >= 0) {
    std::string file = cx.texturePath(key.texture);
    if (!file.empty()) w.print("map_Kd {}\n", file);
  }
  w.print("\n");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// OBJ: v (mesh vertices, then segment points), vt, vn, faces grouped by `usemtl`, `l` polylines.

llvm::Error writeObj(const Context& cx) {
  Mesh m = prepareMesh(cx);
  const Geometry& g = *m.g;
  Polylines lines = chainSegments(cx.geometry.segments);
  const std::string mtlPath = replaceExtension(cx.path, ".mtl");

  std::vector<MaterialKey> materials = usedMaterials(g);
  for (const Polyline& l : lines.lines) {
    MaterialKey k{colorKey(l.color), -1};
    if (std::find(materials.begin(), materials.end(), k) == materials.end()) materials.push_back(k);
  }

  {
    FileWriter mtl;
    if (auto e = mtl.open(mtlPath)) return e;
    mtl.print("# Materials written by lcjit: one per colour index (from the {}) and explicit colour\n\n",
              cx.palette.usesMaterials() ? "materials" : "colormap");
    for (MaterialKey k : materials) writeMaterial(mtl, cx, k);
    if (auto e = mtl.close()) return e;
  }

  FileWriter w;
  if (auto e = w.open(cx.path)) return e;
  const size_t nv = g.vertices.size();
  w.print("# OBJ written by lcjit: {} triangles, {} segments\n", g.triangleCount(), cx.geometry.segments.size());
  w.print("mtllib {}\n", baseName(mtlPath));
  for (const MeshVertex& v : g.vertices) w.print("v {} {} {}\n", z(v.position.x), z(v.position.y), z(v.position.z));
  for (const V3f& p : lines.points) w.print("v {} {} {}\n", z(p.x), z(p.y), z(p.z));
  if (m.textured)
    for (const MeshVertex& v : g.vertices) w.print("vt {} {}\n", z(v.uv.x), z(v.uv.y));
  for (const V3f& n : m.normals) w.print("vn {} {} {}\n", z(n.x), z(n.y), z(n.z));

  if (g.triangleCount()) {
    w.print("o plant\n");
    MaterialKey last{-1000, -1000};
    forEachTriangle(g, [&](size_t, uint32_t a, uint32_t b, uint32_t c, int texture) {
      MaterialKey k{colorKey(g.vertices[a].color), texture};
      if (!(k == last)) {
        w.print("usemtl {}\n", materialName(k));
        last = k;
      }
      ++a, ++b, ++c;
      if (m.textured) w.print("f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}\n", a, b, c);
      else w.print("f {0}//{0} {1}//{1} {2}//{2}\n", a, b, c);
    });
  }
  // Lines, one object per colour (a `usemtl` between `l` statements trips some readers).
  std::vector<int> colors;
  for (const Polyline& l : lines.lines)
    if (std::find(colors.begin(), colors.end(), colorKey(l.color)) == colors.end()) colors.push_back(colorKey(l.color));
  for (int color : colors) {
    std::string name = materialName({color, -1});
    w.print("o lines_{}\nusemtl {}\n", name, name);
    for (const Polyline& l : lines.lines) {
      if (colorKey(l.color) != color) continue;
      w.text("l");
      for (uint32_t i = 0; i < l.count; ++i) w.print(" {}", nv + l.first + i + 1);
      w.text("\n");
    }
  }
  return w.close();
}

// ---------------------------------------------------------------------------------------------
// PLY: vertex (x y z nx ny nz [s t] red green blue alpha), face (vertex_indices), edge.

llvm::Error writePly(const Context& cx) {
  Mesh m = prepareMesh(cx);
  const Geometry& g = *m.g;
  Polylines lines = chainSegments(cx.geometry.segments);
  const bool ascii = cx.in.ascii;
  const size_t nv = g.vertices.size(), np = lines.points.size();

  FileWriter w;
  if (auto e = w.open(cx.path, !ascii)) return e;
  w.print("ply\nformat {} 1.0\ncomment written by lcjit\n", ascii ? "ascii" : "binary_little_endian");
  if (m.textured) {
    // MeshLab's convention for the texture file (the first one used).
    for (const TriangleRun& r : g.runs)
      if (r.texture >= 0 && r.indexCount) {
        std::string file = cx.texturePath(r.texture);
        if (!file.empty()) {
          w.print("comment TextureFile {}\n", file);
          break;
        }
      }
  }
  w.print("element vertex {}\n", nv + np);
  w.text("property float x\nproperty float y\nproperty float z\n");
  w.text("property float nx\nproperty float ny\nproperty float nz\n");
  if (m.textured) w.text("property float s\nproperty float t\n");
  w.text("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n");
  w.print("element face {}\nproperty list uchar uint vertex_indices\n", g.triangleCount());
  w.print("element edge {}\nproperty int vertex1\nproperty int vertex2\n", lines.edgeCount());
  w.text("property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n");

  auto bytes = [&](int color) {
    const Rgba c = cx.color(color);
    return std::array<uint8_t, 4>{toByte(c[0]), toByte(c[1]), toByte(c[2]), toByte(c[3])};
  };
  auto vertex = [&](V3f p, V3f n, V2f uv, int color) {
    const auto c = bytes(color);
    if (ascii) {
      w.print("{} {} {} {} {} {}", z(p.x), z(p.y), z(p.z), z(n.x), z(n.y), z(n.z));
      if (m.textured) w.print(" {} {}", z(uv.x), z(uv.y));
      w.print(" {} {} {} {}\n", c[0], c[1], c[2], c[3]);
      return;
    }
    float f[8] = {p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
    w.write(f, m.textured ? 32 : 24);
    w.write(c.data(), 4);
  };
  for (size_t i = 0; i < nv; ++i) {
    const MeshVertex& v = g.vertices[i];
    vertex(v.position, m.normals[i], v.uv, v.color);
  }
  for (const Polyline& l : lines.lines)
    for (uint32_t i = 0; i < l.count; ++i) vertex(lines.points[l.first + i], V3f(0, 0, 0), V2f(0, 0), l.color);

  const auto& idx = g.indices;
  for (size_t t = 0; t + 2 < idx.size(); t += 3) {
    if (ascii) {
      w.print("3 {} {} {}\n", idx[t], idx[t + 1], idx[t + 2]);
    } else {
      uint8_t face[13];
      face[0] = 3;
      std::memcpy(face + 1, &idx[t], 12);
      w.write(face, 13);
    }
  }
  for (const Polyline& l : lines.lines) {
    const auto c = bytes(l.color);
    for (uint32_t i = 0; i + 1 < l.count; ++i) {
      int32_t a = int32_t(nv + l.first + i), b = a + 1;
      if (ascii) {
        w.print("{} {} {} {} {}\n", a, b, c[0], c[1], c[2]);
      } else {
        uint8_t edge[11];
        std::memcpy(edge, &a, 4);
        std::memcpy(edge + 4, &b, 4);
        std::memcpy(edge + 8, c.data(), 3);
        w.write(edge, 11);
      }
    }
  }
  return w.close();
}

// ---------------------------------------------------------------------------------------------
// STL: triangles only (STL cannot hold lines, points or text). Binary files carry the colour in
// the attribute word, VisCAM/SolidView style: bit 15 set, 5 bits each of red, green, blue.

llvm::Error writeStl(const Context& cx) {
  Mesh m = prepareMesh(cx);
  const Geometry& g = *m.g;
  const bool ascii = cx.in.ascii;
  FileWriter w;
  if (auto e = w.open(cx.path, !ascii)) return e;
  const size_t count = g.triangleCount();
  if (count == 0 && !g.segments.empty() && cx.in.note)
    *cx.in.note = fmt::format("{} holds no triangles: STL keeps only surfaces, and the model draws {} line "
                              "segments and no surface (.obj, .ply and .gltf keep lines)",
                              cx.path, g.segments.size());
  if (ascii) {
    w.text("solid lcjit\n");
  } else {
    char header[80] = {};
    std::string text = fmt::format("lcjit binary STL, {} triangles, VisCAM colours", count);
    std::memcpy(header, text.data(), std::min<size_t>(text.size(), 79));
    w.write(header, 80);
    uint32_t n = (uint32_t)count;
    w.put(n);
  }
  auto word = [&](int color) {
    const Rgba c = cx.color(color);
    auto five = [](float f) { return (uint16_t)std::lround(std::clamp(f, 0.0f, 1.0f) * 31); };
    return uint16_t(0x8000 | five(c[0]) << 10 | five(c[1]) << 5 | five(c[2]));
  };
  const auto& idx = g.indices;
  for (size_t t = 0; t < count; ++t) {
    const MeshVertex &a = g.vertices[idx[3 * t]], &b = g.vertices[idx[3 * t + 1]], &c = g.vertices[idx[3 * t + 2]];
    V3f n = (b.position - a.position) % (c.position - a.position);
    float l2 = n * n;
    n = l2 > 0 ? n / std::sqrt(l2) : V3f(0, 0, 0);
    if (ascii) {
      w.print(" facet normal {} {} {}\n  outer loop\n", z(n.x), z(n.y), z(n.z));
      for (const MeshVertex* v : {&a, &b, &c}) w.print("   vertex {} {} {}\n", z(v->position.x), z(v->position.y), z(v->position.z));
      w.text("  endloop\n endfacet\n");
    } else {
      float f[12] = {n.x, n.y, n.z, a.position.x, a.position.y, a.position.z, b.position.x, b.position.y,
                     b.position.z, c.position.x, c.position.y, c.position.z};
      uint8_t rec[50];
      std::memcpy(rec, f, 48);
      uint16_t attr = word(a.color);
      std::memcpy(rec + 48, &attr, 2);
      w.write(rec, 50);
    }
  }
  if (ascii) w.text("endsolid lcjit\n");
  return w.close();
}

}  // namespace lcjit::runtime::exporting
