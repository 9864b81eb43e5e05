// glTF 2.0 (.gltf + .bin, or .glb) through tinygltf.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include <tiny_gltf.h>

#include "runtime/export/ExportCommon.h"
#include "runtime/export/ExportFormats.h"
#include "runtime/files/TextLines.h"

namespace lcjit::runtime::exporting {
namespace {

// The glTF image type of a texture file by its extension: PNG and JPEG are glTF's; "" others.
std::string gltfImageType(const std::string& file) {
  const std::string ext = lowerExtension(file);
  return ext == "png" ? "image/png" : ext == "jpg" || ext == "jpeg" ? "image/jpeg" : "";
}

struct Builder {
  tinygltf::Model model;
  std::vector<unsigned char>& buf;
  Builder() : buf(model.buffers.emplace_back().data) {}

  int view(const void* data, size_t bytes, int target) {
    while (buf.size() % 4) buf.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buf.size();
    v.byteLength = bytes;
    v.target = target;
    const unsigned char* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    model.bufferViews.push_back(v);
    return (int)model.bufferViews.size() - 1;
  }
  int accessor(int view, size_t byteOffset, int componentType, size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = byteOffset;
    a.componentType = componentType;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
    return (int)model.accessors.size() - 1;
  }
  int positions(const std::vector<float>& xyz) {
    int v = view(xyz.data(), xyz.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
    int a = accessor(v, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, xyz.size() / 3, TINYGLTF_TYPE_VEC3);
    std::vector<double> lo(3, 1e300), hi(3, -1e300);
    for (size_t i = 0; i < xyz.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], (double)xyz[i]);
      hi[i % 3] = std::max(hi[i % 3], (double)xyz[i]);
    }
    model.accessors[a].minValues = lo;
    model.accessors[a].maxValues = hi;
    return a;
  }
};

}  // namespace

llvm::Error writeGltf(const Context& cx, bool binary) {
  Mesh m = prepareMesh(cx);
  const Geometry& g = *m.g;
  Polylines lines = chainSegments(cx.geometry.segments);
  Builder b;
  tinygltf::Model& model = b.model;
  model.asset.version = "2.0";
  model.asset.generator = "lcjit";

  // Materials: one per (colour, texture) used, named as in the OBJ export.
  std::unordered_map<int64_t, int> materialOf;  // MaterialKey::packed → material
  std::unordered_map<int, int> textureOf;   // texture index → glTF texture (-1: no file)
  auto material = [&](MaterialKey key) {
    auto [it, added] = materialOf.emplace(key.packed(), (int)model.materials.size());
    if (!added) return it->second;
    tinygltf::Material mat;
    mat.name = materialName(key);
    mat.doubleSided = true;
    auto& pbr = mat.pbrMetallicRoughness;
    pbr.metallicFactor = 0;
    float alpha;
    if (const Material* lit = cx.material(key.color)) {
      const Material& mm = *lit;
      alpha = 1 - mm.transparency;
      pbr.baseColorFactor = {mm.diffuse[0], mm.diffuse[1], mm.diffuse[2], alpha};
      pbr.roughnessFactor = std::clamp(std::sqrt(2.0 / (mm.shininess + 2.0)), 0.0, 1.0);
      if (mm.emission[0] > 0 || mm.emission[1] > 0 || mm.emission[2] > 0)
        mat.emissiveFactor = {std::min(1.0f, mm.emission[0]), std::min(1.0f, mm.emission[1]),
                              std::min(1.0f, mm.emission[2])};
    } else {
      const Rgba c = cx.color(key.color);
      alpha = c[3];
      pbr.baseColorFactor = {c[0], c[1], c[2], c[3]};
      pbr.roughnessFactor = 1;
    }
    if (alpha < 1) mat.alphaMode = "BLEND";
    if (key.texture >= 0) {
      auto [t, newTexture] = textureOf.emplace(key.texture, -1);
      if (newTexture) {
        std::string file = cx.texturePath(key.texture);
        if (!file.empty()) {
          tinygltf::Image image;
          // A .glb carries its textures (PNG and JPEG, the images glTF holds): the one file is
          // what users take to Blender or a web viewer. A .gltf, or another image format,
          // refers to the file, relative to the output's folder.
          image.uri = file;
          if (std::string mime = gltfImageType(file); binary && !mime.empty()) {
            if (auto bytes = textfile::readFile(cx.textureFile(key.texture))) {
              image.bufferView = b.view((*bytes)->getBufferStart(), (*bytes)->getBufferSize(), 0);
              image.mimeType = mime;
              image.uri.clear();
            } else {
              llvm::consumeError(bytes.takeError());  // unreadable: it stays a reference
            }
          }
          model.images.push_back(image);
          if (model.samplers.empty()) {
            tinygltf::Sampler s;
            s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
            s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
            model.samplers.push_back(s);
          }
          tinygltf::Texture tex;
          tex.source = (int)model.images.size() - 1;
          tex.sampler = 0;
          model.textures.push_back(tex);
          t->second = (int)model.textures.size() - 1;
        }
      }
      if (t->second >= 0) pbr.baseColorTexture.index = t->second;
    }
    model.materials.push_back(mat);
    return it->second;
  };

  tinygltf::Mesh mesh;
  mesh.name = "plant";
  const size_t nv = g.vertices.size();
  if (g.triangleCount()) {
    std::vector<float> data(nv * 3);
    for (size_t i = 0; i < nv; ++i) std::memcpy(&data[3 * i], &g.vertices[i].position, 12);
    int position = b.positions(data);
    for (size_t i = 0; i < nv; ++i) std::memcpy(&data[3 * i], &m.normals[i], 12);
    int normal = b.accessor(b.view(data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER), 0,
                            TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC3);
    int texcoord = -1;
    if (m.textured) {
      data.resize(nv * 2);
      for (size_t i = 0; i < nv; ++i) {
        data[2 * i] = g.vertices[i].uv.x;
        data[2 * i + 1] = 1 - g.vertices[i].uv.y;  // glTF's v runs down the image
      }
      texcoord = b.accessor(b.view(data.data(), data.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER), 0,
                            TINYGLTF_COMPONENT_TYPE_FLOAT, nv, TINYGLTF_TYPE_VEC2);
    }
    data = {};

    // Triangles bucketed by material, each bucket one primitive over a slice of one index view.
    std::vector<MaterialKey> keys = usedMaterials(g);
    std::unordered_map<int64_t, int> slot;
    for (size_t i = 0; i < keys.size(); ++i) slot[keys[i].packed()] = (int)i;
    std::vector<size_t> count(keys.size() + 1, 0);
    std::vector<int> triSlot(g.triangleCount());
    {
      MaterialKey last{-1000, -1000};
      int s = 0;
      forEachTriangle(g, [&](size_t t, uint32_t a, uint32_t, uint32_t, int texture) {
        MaterialKey k{colorKey(g.vertices[a].color), texture};
        if (!(k == last)) s = slot[k.packed()], last = k;
        triSlot[t] = s;
        count[s + 1] += 3;
      });
    }
    std::vector<size_t> start(keys.size() + 1, 0);
    for (size_t i = 1; i <= keys.size(); ++i) start[i] = start[i - 1] + count[i];
    std::vector<uint32_t> sorted(start[keys.size()]);
    {
      std::vector<size_t> at(start.begin(), start.end() - 1);
      for (size_t t = 0; t < triSlot.size(); ++t) {
        size_t& p = at[triSlot[t]];
        std::memcpy(&sorted[p], &g.indices[3 * t], 12);
        p += 3;
      }
    }
    triSlot = {};
    int indexView = b.view(sorted.data(), sorted.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    for (size_t i = 0; i < keys.size(); ++i) {
      tinygltf::Primitive p;
      p.mode = TINYGLTF_MODE_TRIANGLES;
      p.attributes["POSITION"] = position;
      p.attributes["NORMAL"] = normal;
      if (texcoord >= 0) p.attributes["TEXCOORD_0"] = texcoord;
      p.indices = b.accessor(indexView, start[i] * 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, count[i + 1],
                             TINYGLTF_TYPE_SCALAR);
      p.material = material(keys[i]);
      mesh.primitives.push_back(p);
    }
  }

  if (!lines.lines.empty()) {
    std::vector<float> xyz(lines.points.size() * 3);
    for (size_t i = 0; i < lines.points.size(); ++i) std::memcpy(&xyz[3 * i], &lines.points[i], 12);
    int position = b.positions(xyz);
    // Edges grouped by colour: one LINES primitive per colour.
    std::vector<int> colors;
    for (const Polyline& l : lines.lines)
      if (std::find(colors.begin(), colors.end(), colorKey(l.color)) == colors.end()) colors.push_back(colorKey(l.color));
    std::vector<uint32_t> idx;
    std::vector<std::pair<size_t, size_t>> ranges;
    for (int c : colors) {
      size_t first = idx.size();
      for (const Polyline& l : lines.lines)
        if (colorKey(l.color) == c)
          for (uint32_t i = 0; i + 1 < l.count; ++i) {
            idx.push_back(l.first + i);
            idx.push_back(l.first + i + 1);
          }
      ranges.push_back({first, idx.size() - first});
    }
    int indexView = b.view(idx.data(), idx.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    for (size_t i = 0; i < colors.size(); ++i) {
      tinygltf::Primitive p;
      p.mode = TINYGLTF_MODE_LINE;
      p.attributes["POSITION"] = position;
      p.indices = b.accessor(indexView, ranges[i].first * 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                             ranges[i].second, TINYGLTF_TYPE_SCALAR);
      p.material = material({colors[i], -1});
      mesh.primitives.push_back(p);
    }
  }

  tinygltf::Scene scene;
  scene.name = "lcjit";
  if (!mesh.primitives.empty()) {
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = "plant";
    node.mesh = 0;
    model.nodes.push_back(node);
    scene.nodes.push_back(0);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.buffers[0].name = "geometry";
  if (b.buf.empty()) model.buffers.clear();
  // .gltf: the buffer beside it as NAME.gltf.bin, not tinygltf's NAME.bin, which is also the
  // binary string lpfg and lcjit write for `-out NAME.bin`: saving both must keep both.
  if (!binary && !model.buffers.empty())
    model.buffers[0].uri = std::filesystem::path(cx.path).filename().string() + ".bin";

  tinygltf::TinyGLTF gltf;
  gltf.SetImageWriter(nullptr, nullptr);  // images stay references to the texture files
  if (binary)
    return support::writeWholeFile(cx.path, [&](std::ostream& out) {
      gltf.WriteGltfSceneToStream(&model, out, false, true);
      return llvm::Error::success();
    });
  support::ReplacingFile file(cx.path);
  // A clear error for an unwritable path before tinygltf tries.
  if (std::FILE* probe = std::fopen(file.writePath().c_str(), "w")) std::fclose(probe);
  else return fileError(cx.path, std::strerror(errno));
  // The .bin buffer is written beside it under the name its uri gives (above), not the new
  // file's.
  if (!gltf.WriteGltfSceneToFile(&model, file.writePath(), false, false, true, false))
    return fileError(cx.path, "tinygltf could not write it or its .bin buffer");
  return file.commit();
}

}  // namespace lcjit::runtime::exporting
