// lpfg's OpenGL picture, restated for OpenGL 3.3 (see Renderer.h). The rules, with where lpfg
// has them (vlab, lpfg/):
//  - Lighting is on exactly when a materials file is used (GLEnv::DoInit enables GL_LIGHTING only
//    when `_materials.Set()`): with a colormap everything is drawn in flat colours in every render
//    mode; with materials everything (polygons, lines, discs) is lit in every render mode, labels
//    excepted (their colour is the emission).
//  - Render modes (GLEnv::DoInit): filled = GL_FLAT shading (one colour per face, the last
//    vertex's), shaded = GL_SMOOTH (Gouraud), wireframe = glPolygonMode(GL_LINE) + smooth,
//    `wireframe line width:`; shadows = shaders (shaders/main_fshader.glsl): per-fragment
//    lighting, shadow map from light 0, diffuse light mixed with the shadow colour where shadowed,
//    specular removed; the depth test is on in this mode (GLWidget::beginShadowMap enables it).
//  - Two-sided lighting (GL_LIGHT_MODEL_TWO_SIDE), local viewer off, global ambient 0.2 (GL's
//    default), glMaterial ambient/diffuse/specular/emission/shininess, alpha = 1 − transparency.
//  - Lights (lightsrc.cpp): default V: 0 0 1 with ambient, diffuse and specular 1; `stationary
//    lights: on` (default) positions lights with the initial view's translation only
//    (View::ResetOpenGL), i.e. fixed relative to the camera; off: in model space.
//  - Background: colour 0, or the emission of material 0 (GLEnv::ClearColor).
//  - Blending SRC_ALPHA/ONE_MINUS_SRC_ALPHA always on, alpha test > 0.1, no antialiasing by
//    default, GL_CULL_FACE only with `backface culling: on`, depth test only with `z buffer: on`
//    (off by default: painter's order, the interpretation order, Geometry::order).
//  - Pixel lines: glLineWidth(turtle width): aliased, rounded, ≥ 1 px. Lines lit (materials) use
//    GL's current normal, (0,0,1) in model space, front material.
//  - CircleFront/CircleFrontB: gluDisk (contour divisions slices) in the screen plane; its matrix
//    has determinant −1 so the disc is front-facing with its normal pointing away from the viewer
//    (lit discs therefore get ambient/emission only from a light at the viewer, as in lpfg).
//  - Textures: GL_MODULATE, GL_NEAREST, v = 0 at the image's bottom row.
//  - lpfg's terrain (TerrainPatch::draw, TerrainData::draw): a patch sets its own polygon mode
//    (TriangleRun::fill), and two-sided lighting stays off once a terrain is drawn
//    (Geometry::oneSidedLighting: back faces of everything else lit with the front normal).
//    Colours kRgbColor | 0xRRGGBB are drawn unlit as they are (the terrain's grid, glColor3f).
//  - Labels (GLWidget::renderText, a QPainter on the widget when the turtle meets the label):
//    drawn over what is drawn before them, and under what the string draws after them (with a z
//    buffer: where that passes the depth test; the label writes no depth), left end at the anchor,
//    baseline 2 px below it, QFont point size = `winfont:` size (96 dpi); Qt's glyphs, pixmap,
//    colour bytes and lpfg's alpha test as runtime/text/LabelText.h restates them (RasterLabel).
//
// Where each part lives (each section begins with a `// ----` rule; Impl's parts with `// --- Name`):
//   Shaders.cpp: Shaders (the GLSL) · Shader programs (compile, link, one per variant).
//   This file: Renderer::Impl: GL objects and uploads (setGeometry, setTextures, uploadPalette,
//     the passes' uniforms, discs) · --- Drawing ranges (triangles, segments as lines or quads,
//     discs, a range of labels, painter's order with labels where the string has them) ·
//     --- The frame (draw: passes, clipping, the shadow pass) · Label fonts and the Renderer's
//     public face.
//   SegmentBuffers.cpp: the segments' buffer textures, width runs and groups, quad indices.
//   Lights.cpp: Lights in eye space · The shadow map (its framebuffer, the light's camera).
//   LabelQuads.cpp: The atlas · The frame's quads · Drawing a range of them.
//   (The multi-view layout is runtime/turtle/ViewLayout.cpp's.)
#include "viewer/Renderer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "viewer/LabelQuads.h"
#include "viewer/Lights.h"
#include "viewer/SegmentBuffers.h"
#include "viewer/Shaders.h"

namespace lcjit::viewer {

using runtime::CameraMatrices;
using runtime::DrawBatch;
using runtime::Geometry;
using runtime::MeshVertex;
using runtime::RenderMode;
using runtime::ViewSettings;

static_assert(sizeof(MeshVertex) == 36, "MeshVertex is uploaded as is");

// ---------------------------------------------------------------------------------------------
// Renderer::Impl: GL objects, uploads of the geometry, palette and textures

struct Renderer::Impl {
  bool initialized = false;
  bool failed = false;
  Program mesh[kVariants], segment[kVariants], lines[kVariants], text;
  float maxLineWidth = 1;
  GLuint meshVao = 0, meshVbo = 0, meshEbo = 0;
  size_t meshVboSize = 0, meshEboSize = 0;
  GLuint discVao = 0, discVbo = 0;
  size_t discVboSize = 0;
  GLuint emptyVao = 0;
  GLuint paletteTex = 0, colorsUbo = 0;
  std::vector<GLuint> textures;
  SegmentBuffers segs;  // SegmentBuffers.h
  ShadowMap shadowMap;  // Lights.h

  // CPU-side copies of what is built per frame or needed to order the draws.
  std::vector<runtime::TriangleRun> runs;
  std::vector<DrawBatch> order;
  bool orderComplete = false;  // `order` covers every primitive (else it is not used)
  bool labelsInOrder = false;  // some of `order`'s batches are labels
  bool oneSided = false;       // Geometry::oneSidedLighting
  std::vector<runtime::Disc> discs;
  std::vector<runtime::Label> labels;
  uint32_t indexCount = 0, segmentCount = 0;
  std::vector<uint32_t> discFirstVertex;  // per disc, and one past the end
  RenderPalette palette;
  bool paletteDirty = true;

  LabelQuads labelQuads;  // LabelQuads.h: the atlas and this frame's quads

  std::string* error = nullptr;
  RenderStats* stats = nullptr;

  void fail(const std::string& message) {
    if (error->empty()) *error = message;
  }

  void init() {
    if (initialized) return;
    initialized = true;
    for (int v = 0; v < kVariants; ++v) {
      mesh[v].kind = 0, segment[v].kind = 1, lines[v].kind = 2;
      mesh[v].variant = segment[v].variant = lines[v].variant = v;
    }

    glGenVertexArrays(1, &meshVao);
    glGenBuffers(1, &meshVbo);
    glGenBuffers(1, &meshEbo);
    setupMeshVao(meshVao, meshVbo);
    glBindVertexArray(meshVao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, meshEbo);
    glBindVertexArray(0);
    glGenVertexArrays(1, &discVao);
    glGenBuffers(1, &discVbo);
    setupMeshVao(discVao, discVbo);
    glGenVertexArrays(1, &emptyVao);
    segs.init(emptyVao);
    GLfloat range[2] = {1, 1};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    maxLineWidth = range[1];
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if (flags & GL_CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT) maxLineWidth = 1;  // wide lines removed (macOS)

    labelQuads.init();

    glGenBuffers(1, &colorsUbo);
    glBindBuffer(GL_UNIFORM_BUFFER, colorsUbo);
    glBufferData(GL_UNIFORM_BUFFER, 256 * 16, nullptr, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    glGenTextures(1, &paletteTex);
    glBindTexture(GL_TEXTURE_2D, paletteTex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 256, 11, 0, GL_RGBA, GL_FLOAT, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);
  }

  static void setupMeshVao(GLuint vao, GLuint vbo) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex), (void*)offsetof(MeshVertex, position));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex), (void*)offsetof(MeshVertex, normal));
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(MeshVertex), (void*)offsetof(MeshVertex, uv));
    glVertexAttribIPointer(3, 1, GL_INT, sizeof(MeshVertex), (void*)offsetof(MeshVertex, color));
    for (int i = 0; i < 4; ++i) glEnableVertexAttribArray(i);
    glBindVertexArray(0);
  }

  static void upload(GLenum target, GLuint buffer, size_t& capacity, const void* data, size_t size) {
    glBindBuffer(target, buffer);
    if (size > capacity || size < capacity / 4) {
      glBufferData(target, std::max<size_t>(size, 1), data, GL_STATIC_DRAW);
      capacity = std::max<size_t>(size, 1);
    } else if (size) {
      glBufferSubData(target, 0, size, data);
    }
  }

  void setGeometry(const Geometry& g) {
    init();
    glBindVertexArray(0);
    upload(GL_ARRAY_BUFFER, meshVbo, meshVboSize, g.vertices.data(), g.vertices.size() * sizeof(MeshVertex));
    glBindVertexArray(meshVao);
    upload(GL_ELEMENT_ARRAY_BUFFER, meshEbo, meshEboSize, g.indices.data(), g.indices.size() * sizeof(uint32_t));
    glBindVertexArray(0);
    indexCount = (uint32_t)g.indices.size();
    runs = g.runs;
    oneSided = g.oneSidedLighting;
    if (runs.empty() && indexCount) runs.push_back({0, indexCount, -1});
    order = g.order;
    {
      uint64_t covered[4] = {0, 0, 0, 0};
      for (const DrawBatch& b : order) covered[int(b.kind)] += b.count;
      orderComplete = covered[0] == g.indices.size() && covered[1] == g.segments.size() &&
                      covered[2] == g.discs.size() && covered[3] == g.labels.size();
      labelsInOrder = covered[3] > 0;
    }
    discs = g.discs;
    labels = g.labels;

    segmentCount = (uint32_t)g.segments.size();
    segs.upload(g.segments, emptyVao);
  }

  void setTextures(const std::vector<runtime::Image>& images) {
    init();
    if (!textures.empty()) glDeleteTextures((GLsizei)textures.size(), textures.data());
    textures.assign(images.size(), 0);
    if (images.empty()) return;
    glGenTextures((GLsizei)textures.size(), textures.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    std::vector<uint8_t> flipped;
    for (size_t i = 0; i < images.size(); ++i) {
      const runtime::Image& im = images[i];
      glBindTexture(GL_TEXTURE_2D, textures[i]);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
      if (im.width <= 0 || im.height <= 0 || im.rgba.size() < size_t(im.width) * im.height * 4) {
        const uint8_t white[4] = {255, 255, 255, 255};
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
        continue;
      }
      size_t row = size_t(im.width) * 4;
      flipped.resize(row * im.height);
      for (int y = 0; y < im.height; ++y)
        std::memcpy(&flipped[row * y], &im.rgba[row * (im.height - 1 - y)], row);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, im.width, im.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, flipped.data());
    }
    glBindTexture(GL_TEXTURE_2D, 0);
  }

  // Rows: 0 flat colour; 1..5 the materials (ambient, diffuse, specular, emission, shininess);
  // 6..10 materials made from the colormap for shadow mode (GL's default material tinted).
  void uploadPalette() {
    std::vector<float> t(256 * 11 * 4, 0.0f);
    auto put = [&](int row, int i, const float* c, float a) {
      float* d = &t[(size_t(row) * 256 + i) * 4];
      d[0] = c[0], d[1] = c[1], d[2] = c[2], d[3] = a;
    };
    for (int i = 0; i < 256; ++i) {
      const auto& col = palette.color[i];
      put(0, i, col.data(), col[3]);
      const runtime::Material& m = palette.material[i];
      float alpha = 1.0f - m.transparency;  // lpfg: every alpha of the material
      put(1, i, m.ambient, alpha);
      put(2, i, m.diffuse, alpha);
      put(3, i, m.specular, alpha);
      put(4, i, m.emission, alpha);
      float sh[3] = {std::clamp(m.shininess, 0.0f, 128.0f), 0, 0};
      put(5, i, sh, 1);
      float amb[3] = {0.2f * col[0], 0.2f * col[1], 0.2f * col[2]};
      float dif[3] = {0.8f * col[0], 0.8f * col[1], 0.8f * col[2]};
      float zero[3] = {0, 0, 0};
      put(6, i, amb, col[3]);
      put(7, i, dif, col[3]);
      put(8, i, zero, col[3]);
      put(9, i, zero, col[3]);
      put(10, i, zero, 1);
    }
    glBindTexture(GL_TEXTURE_2D, paletteTex);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 256, 11, GL_RGBA, GL_FLOAT, t.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindBuffer(GL_UNIFORM_BUFFER, colorsUbo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, 256 * 16, t.data());
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    paletteDirty = false;
    translucent = false;
    for (int i = 0; i < 256; ++i)
      translucent = translucent || (palette.materials ? palette.material[i].transparency > 0 : palette.color[i][3] < 1);
  }

  // Programs are linked on first use (llvmpipe compiles each one it is given).
  bool ensureLinked(Program& p) {
    if (p.id) return true;
    if (failed) return false;
    std::string err;
    p.id = &p == &text ? linkTextProgram(err) : linkProgram(p.kind, p.variant, err);
    if (!err.empty()) {
      failed = true;
      fail(err);
      return false;
    }
    return true;
  }

  // What the programs of one pass share; set into each program the first time the pass uses it.
  struct PassParams {
    const CameraMatrices* cam = nullptr;
    const std::vector<EyeLight>* lights = nullptr;
    const ViewSettings* view = nullptr;
    bool lit = false, depthPass = false;
    int matBase = 1;
    glm::mat4 shadowMatrix{1}, lightView{1}, lightProj{1};
  } params;
  uint64_t passSerial = 0;

  void beginPass(const PassParams& p) {
    params = p;
    ++passSerial;
  }

  // Links if needed, binds, and sets the pass's uniforms once per pass.
  bool use(Program& p) {
    if (!ensureLinked(p)) return false;
    glUseProgram(p.id);
    if (p.serial != passSerial) {
      p.serial = passSerial;
      setFrameUniforms(p, *params.cam, *params.lights, params.lit, params.matBase, params.shadowMatrix, *params.view,
                       params.depthPass, params.lightView, params.lightProj);
    }
    return true;
  }

  void setFrameUniforms(Program& p, const CameraMatrices& cam, const std::vector<EyeLight>& lights, bool lit,
                        int matBase, const glm::mat4& shadowMatrix, const ViewSettings& view, bool depthPass,
                        const glm::mat4& lightView, const glm::mat4& lightProj) {
    glUniformMatrix4fv(p.loc("uView"), 1, GL_FALSE, glm::value_ptr(depthPass ? lightView : cam.view));
    glUniformMatrix4fv(p.loc("uProj"), 1, GL_FALSE, glm::value_ptr(depthPass ? lightProj : cam.projection));
    glm::mat4 pv = depthPass ? lightProj * lightView : cam.projection * cam.view;
    glUniformMatrix4fv(p.loc("uPV"), 1, GL_FALSE, glm::value_ptr(pv));
    glUniformMatrix4fv(p.loc("uShadowMatrix"), 1, GL_FALSE, glm::value_ptr(shadowMatrix));
    glUniform2f(p.loc("uViewport"), depthPass ? shadowMap.shadowSize * 0.5f : cam.width * 0.5f,
                depthPass ? shadowMap.shadowSize * 0.5f : cam.height * 0.5f);
    glUniform1i(p.loc("uPalette"), 1);
    glUniform1i(p.loc("uTexture"), 0);
    glUniform1i(p.loc("uShadowMap"), 2);
    glUniform1i(p.loc("uSegments"), 3);
    glUniform1i(p.loc("uMatBase"), matBase);
    glUniform1i(p.loc("uLit"), lit ? 1 : 0);
    glUniform1i(p.loc("uNumLights"), (GLint)lights.size());
    glUniform3f(p.loc("uShadowColor"), view.shadowColor.r, view.shadowColor.g, view.shadowColor.b);
    glUniform1i(p.loc("uTextured"), 0);
    glUniform1i(p.loc("uForceFront"), 0);
    glUniform1i(p.loc("uOrderDepth"), 0);
    for (size_t i = 0; i < lights.size(); ++i) {
      std::string idx = "[" + std::to_string(i) + "]";
      const EyeLight& l = lights[i];
      glUniform4fv(p.loc(("uLightPos" + idx).c_str()), 1, glm::value_ptr(l.pos));
      glUniform3fv(p.loc(("uLightSpotDir" + idx).c_str()), 1, glm::value_ptr(l.spotDir));
      glUniform2fv(p.loc(("uLightSpot" + idx).c_str()), 1, glm::value_ptr(l.spot));
      glUniform3fv(p.loc(("uLightAtt" + idx).c_str()), 1, glm::value_ptr(l.att));
      glUniform3fv(p.loc(("uLightAmb" + idx).c_str()), 1, glm::value_ptr(l.amb));
      glUniform3fv(p.loc(("uLightDiff" + idx).c_str()), 1, glm::value_ptr(l.diff));
      glUniform3fv(p.loc(("uLightSpec" + idx).c_str()), 1, glm::value_ptr(l.spec));
    }
  }

  // Camera-facing discs for this frame (gluDisk: `slices` sectors, one loop).
  void buildDiscs(const CameraMatrices& cam, int slices) {
    discFirstVertex.assign(1, 0);
    if (discs.empty()) return;
    glm::vec3 dir = glm::normalize(cam.viewDirection);
    glm::vec3 up = cam.up - dir * glm::dot(cam.up, dir);
    up = glm::length(up) > 0 ? glm::normalize(up) : glm::vec3(0, 1, 0);
    glm::vec3 right = glm::normalize(glm::cross(dir, up));
    std::vector<MeshVertex> v;
    v.reserve(discs.size() * slices * 3);
    std::vector<glm::vec2> ring(slices + 1);
    for (int i = 0; i <= slices; ++i) {
      float a = 2.0f * 3.14159265358979f * float(i % slices) / float(slices);
      ring[i] = {std::cos(a), std::sin(a)};
    }
    auto vert = [&](const runtime::Disc& d, float r, glm::vec2 cs) {
      MeshVertex m;
      glm::vec3 p = glm::vec3(d.center.x, d.center.y, d.center.z) + r * (cs.x * right + cs.y * up);
      m.position = V3f(p.x, p.y, p.z);
      m.normal = V3f(dir.x, dir.y, dir.z);  // lpfg: pointing away from the viewer (see above)
      m.uv = V2f(0, 0);
      m.color = d.color;
      return m;
    };
    for (const runtime::Disc& d : discs) {
      float inner = std::max(0.0f, d.inner), outer = std::max(0.0f, d.outer);
      if (outer > inner) {
        for (int i = 0; i < slices; ++i) {
          if (inner == 0) {
            v.push_back(vert(d, 0, ring[i]));
            v.push_back(vert(d, outer, ring[i]));
            v.push_back(vert(d, outer, ring[i + 1]));
          } else {
            v.push_back(vert(d, inner, ring[i]));
            v.push_back(vert(d, outer, ring[i]));
            v.push_back(vert(d, outer, ring[i + 1]));
            v.push_back(vert(d, inner, ring[i]));
            v.push_back(vert(d, outer, ring[i + 1]));
            v.push_back(vert(d, inner, ring[i + 1]));
          }
        }
      }
      discFirstVertex.push_back((uint32_t)v.size());
    }
    glBindBuffer(GL_ARRAY_BUFFER, discVbo);
    if (v.size() * sizeof(MeshVertex) > discVboSize) {
      discVboSize = v.size() * sizeof(MeshVertex);
      glBufferData(GL_ARRAY_BUFFER, discVboSize, v.data(), GL_STREAM_DRAW);
    } else if (!v.empty()) {
      glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(MeshVertex), v.data());
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }

  // --- Drawing ranges -------------------------------------------------------------------------

  struct Pass {
    Program* meshProg;
    Program* segProg;
    Program* lineProg;
    bool wireframe;
    bool culling;
    bool depthPass;
  };
  int currentProgram = -1;  // 0 mesh, 1 segment quads, 2 segment lines
  bool depthTestOn = false;
  bool targetHasDepth = true;  // the framebuffer drawn into has a depth buffer
  bool translucent = false;   // some colour is not opaque: blending order matters

  float wireframeWidth = 1;
  static void clipDistances(bool on) {
    if (on) {
      glEnable(GL_CLIP_DISTANCE0);
      glEnable(GL_CLIP_DISTANCE1);
    } else {
      glDisable(GL_CLIP_DISTANCE0);
      glDisable(GL_CLIP_DISTANCE1);
    }
  }
  void useMesh(const Pass& pass) {
    if (currentProgram == 0) return;
    currentProgram = 0;
    use(*pass.meshProg);
    clipDistances(false);
    if (pass.wireframe) {
      glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      glLineWidth(wireframeWidth);
    }
    if (pass.culling) glEnable(GL_CULL_FACE);
  }
  void useSegments(const Pass& pass, bool asLines) {
    if (currentProgram == (asLines ? 2 : 1)) return;
    currentProgram = asLines ? 2 : 1;
    use(asLines ? *pass.lineProg : *pass.segProg);
    clipDistances(asLines);  // only the line shader writes gl_ClipDistance
    // Lines are never culled and never drawn as outlines.
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_CULL_FACE);
  }

  void drawTriangles(const Pass& pass, uint32_t first, uint32_t count) {
    if (count == 0) return;
    useMesh(pass);
    glBindVertexArray(meshVao);
    uint32_t end = first + count;
    // Runs are sorted by firstIndex and partition the indices.
    auto it = std::upper_bound(runs.begin(), runs.end(), first,
                               [](uint32_t v, const runtime::TriangleRun& r) { return v < r.firstIndex; });
    if (it != runs.begin()) --it;
    const GLint texLoc = pass.meshProg->loc("uTextured"), oneSidedLoc = pass.meshProg->loc("uOneSided");
    for (; it != runs.end() && it->firstIndex < end; ++it) {
      uint32_t a = std::max(first, it->firstIndex), b = std::min(end, it->firstIndex + it->indexCount);
      if (a >= b) continue;
      bool textured = it->texture >= 0 && size_t(it->texture) < textures.size();
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, textured ? textures[it->texture] : 0);
      glUniform1i(texLoc, textured ? 1 : 0);
      glUniform1i(oneSidedLoc, oneSided && it->fill == runtime::PolygonFill::Default ? 1 : 0);
      // A run with its own fill (lpfg's terrain patches) switches the polygon mode for itself.
      const bool ownFill = it->fill != runtime::PolygonFill::Default &&
                           (it->fill == runtime::PolygonFill::Lines) != pass.wireframe;
      if (ownFill) {
        glPolygonMode(GL_FRONT_AND_BACK, pass.wireframe ? GL_FILL : GL_LINE);
        if (!pass.wireframe) glLineWidth(1);
      }
      glDrawElements(GL_TRIANGLES, b - a, GL_UNSIGNED_INT, (void*)(size_t(a) * sizeof(uint32_t)));
      if (ownFill) glPolygonMode(GL_FRONT_AND_BACK, pass.wireframe ? GL_LINE : GL_FILL);
      ++stats->drawCalls;
    }
  }

  // Fragmented widths as GL lines grouped by width; painter's order kept through the depth buffer
  // (cleared first) when the z buffer is off. False when the segs.chunks have no groups.
  bool drawGrouped(const Pass& pass, uint32_t first, uint32_t count) {
    uint32_t end = first + count;
    for (const SegmentChunk& c : segs.chunks)
      if (std::max(first, c.first) < std::min(end, c.first + c.count) && c.groups.empty()) return false;
    for (const SegmentChunk& c : segs.chunks)
      for (const WidthGroup& wg : c.groups)
        if (wg.width > maxLineWidth) return false;
    if (!depthTestOn && !targetHasDepth) return false;
    useSegments(pass, true);
    Program* p = pass.lineProg;
    glUniform1i(p->loc("uForceFront"), 1);
    const bool order = !depthTestOn;
    if (order && !targetHasDepth) return false;
    if (order) {
      glDepthMask(GL_TRUE);
      glClear(GL_DEPTH_BUFFER_BIT);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glUniform1i(p->loc("uOrderDepth"), 1);
      glUniform1f(p->loc("uOrderScale"), 1.0f / float(segmentCount + 2));
    }
    for (const SegmentChunk& c : segs.chunks) {
      uint32_t a = std::max(first, c.first), b = std::min(end, c.first + c.count);
      if (a >= b) continue;
      glActiveTexture(GL_TEXTURE3);
      glBindTexture(GL_TEXTURE_BUFFER, c.texture);
      glUniform1i(p->loc("uChunkFirst"), (GLint)c.first);
      glBindVertexArray(emptyVao);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, c.groupEbo);
      for (const WidthGroup& wg : c.groups) {
        auto lo = std::lower_bound(wg.ids.begin(), wg.ids.end(), a - c.first);
        auto hi = std::lower_bound(wg.ids.begin(), wg.ids.end(), b - c.first);
        if (lo == hi) continue;
        glLineWidth(wg.width);
        size_t offset = wg.offset + size_t(lo - wg.ids.begin()) * 2;
        glDrawElements(GL_LINES, GLsizei(hi - lo) * 2, GL_UNSIGNED_INT, (void*)(offset * sizeof(uint32_t)));
        ++stats->drawCalls;
      }
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, segs.quadEbo);
    }
    glActiveTexture(GL_TEXTURE0);
    if (order) {
      glUniform1i(p->loc("uOrderDepth"), 0);
      glDisable(GL_DEPTH_TEST);
    }
    return true;
  }

  // Segments [first, first+count): as GL lines, one draw per run of one width, when runs are long
  // (GL_LINES costs a third of the vertices), else as quads in one draw.
  void drawSegments(const Pass& pass, uint32_t first, uint32_t count) {
    if (count == 0) return;
    uint32_t end = first + count;
    auto run = std::upper_bound(segs.widthRuns.begin(), segs.widthRuns.end(), first,
                                [](uint32_t v, const std::pair<uint32_t, float>& r) { return v < r.first; });
    if (run != segs.widthRuns.begin()) --run;
    size_t nRuns = 0;
    bool linesOk = true;
    for (auto r = run; r != segs.widthRuns.end() && r->first < end && r->second > 0; ++r) {
      ++nRuns;
      linesOk = linesOk && r->second <= maxLineWidth;
    }
    const bool asLines = linesOk && nRuns * 16 <= count + 15;
    if (!asLines && linesOk && count >= kGroupMinimum && !translucent && drawGrouped(pass, first, count)) return;
    useSegments(pass, asLines);
    glBindVertexArray(emptyVao);
    glUniform1i((asLines ? pass.lineProg : pass.segProg)->loc("uForceFront"), 1);
    for (const SegmentChunk& c : segs.chunks) {
      uint32_t a = std::max(first, c.first), b = std::min(end, c.first + c.count);
      if (a >= b) continue;
      glActiveTexture(GL_TEXTURE3);
      glBindTexture(GL_TEXTURE_BUFFER, c.texture);
      if (!asLines) {
        glDrawElements(GL_TRIANGLES, GLsizei(b - a) * 6, GL_UNSIGNED_INT, (void*)(size_t(a - c.first) * 6 * sizeof(uint32_t)));
        ++stats->drawCalls;
        continue;
      }
      for (auto r = run; r != segs.widthRuns.end() && r->first < b && r->second > 0; ++r) {
        uint32_t ra = std::max(a, r->first), rb = std::min(b, (r + 1)->first);
        if (ra >= rb) continue;
        glLineWidth(r->second);
        glDrawArrays(GL_LINES, GLint(ra - c.first) * 2, GLsizei(rb - ra) * 2);
        ++stats->drawCalls;
      }
    }
    glActiveTexture(GL_TEXTURE0);
  }

  void drawDiscs(const Pass& pass, uint32_t first, uint32_t count) {
    if (count == 0 || first >= discs.size()) return;
    count = std::min<uint32_t>(count, (uint32_t)discs.size() - first);
    useMesh(pass);
    glBindVertexArray(discVao);
    glUniform1i(pass.meshProg->loc("uTextured"), 0);
    glUniform1i(pass.meshProg->loc("uOneSided"), oneSided ? 1 : 0);
    uint32_t a = discFirstVertex[first], b = discFirstVertex[first + count];
    if (b > a) {
      glDrawArrays(GL_TRIANGLES, a, b - a);
      ++stats->drawCalls;
    }
  }

  // Everything, in lpfg's order where it shows: batch by batch in painter's order; with a z buffer
  // and opaque colours, each kind at once, except that labels (withLabels: the picture's pass, not
  // the shadow map's) split the drawing where the string has them, since what comes after a label
  // covers it. Without a (complete) order: lines, polygons, discs, then labels.
  void drawAll(const Pass& pass, bool painterOrder, bool withLabels = false) {
    currentProgram = -1;
    if (orderComplete && (painterOrder || (withLabels && labelsInOrder))) {
      constexpr uint32_t kNone = ~0u;
      uint32_t lo[3] = {kNone, kNone, kNone}, hi[3] = {0, 0, 0};  // since the last label, by kind
      auto flush = [&] {
        if (lo[1] != kNone) drawSegments(pass, lo[1], std::min(hi[1], segmentCount) - std::min(lo[1], segmentCount));
        if (lo[0] != kNone) drawTriangles(pass, lo[0], std::min(hi[0], indexCount) - std::min(lo[0], indexCount));
        if (lo[2] != kNone) drawDiscs(pass, lo[2], hi[2] - lo[2]);
        for (int k = 0; k < 3; ++k) lo[k] = kNone, hi[k] = 0;
      };
      uint32_t covered[3] = {0, 0, 0};
      for (const DrawBatch& b : order) {
        if (b.kind == DrawBatch::Kind::Labels) {
          flush();
          if (withLabels) drawLabelRange(b.first, b.count);
          continue;
        }
        const int k = int(b.kind);
        covered[k] = std::max(covered[k], b.first + b.count);
        lo[k] = std::min(lo[k], b.first);
        hi[k] = std::max(hi[k], b.first + b.count);
        if (painterOrder) flush();  // batch by batch
      }
      flush();
      if (covered[0] < indexCount) drawTriangles(pass, covered[0], indexCount - covered[0]);
      if (covered[1] < segmentCount) drawSegments(pass, covered[1], segmentCount - covered[1]);
      if (covered[2] < discs.size()) drawDiscs(pass, covered[2], (uint32_t)discs.size() - covered[2]);
    } else {
      // No (complete) order from the producer: lines first, then polygons over them (an
      // L-system's branches before its leaves), then discs.
      drawSegments(pass, 0, segmentCount);
      drawTriangles(pass, 0, indexCount);
      drawDiscs(pass, 0, (uint32_t)discs.size());
      if (withLabels) drawLabelRange(0, (uint32_t)labels.size());
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_CULL_FACE);
  }

  // Labels [first, first+count) over what is drawn so far, as lpfg's QPainter draws its pixmap (no
  // depth test, no depth written); the state the other draws expect is theirs again afterwards.
  void drawLabelRange(uint32_t first, uint32_t count) {
    const auto [a, b] = labelQuads.vertexRange(first, count);
    if (a >= b || !ensureLinked(text)) return;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    clipDistances(false);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    labelQuads.drawQuads(text, a, b);
    ++stats->drawCalls;
    currentProgram = -1;  // the next draw binds its program and state afresh
    if (depthTestOn) glEnable(GL_DEPTH_TEST);
  }

  // --- The frame -------------------------------------------------------------------------------

  void draw(const ViewSettings& view, const CameraMatrices& cam, const RenderOptions& options) {
    init();
    if (failed) return;
    *stats = RenderStats{};
    stats->triangles = indexCount / 3;
    stats->segments = segmentCount;
    stats->discs = discs.size();
    stats->labels = labels.size();
    if (paletteDirty) uploadPalette();

    GLint prevFbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prevFbo);
    {
      GLint type = GL_NONE, bits = 0;
      GLenum attachment = prevFbo ? GL_DEPTH_ATTACHMENT : GL_DEPTH;
      glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
      if (type != GL_NONE)
        glGetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, attachment, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE, &bits);
      targetHasDepth = type != GL_NONE && bits > 0;
      glGetError();  // a default framebuffer without depth may answer GL_INVALID_OPERATION
    }

    const bool shadows = view.renderMode == RenderMode::Shadows;
    const bool wireframe = view.renderMode == RenderMode::Wireframe;
    std::vector<EyeLight> lights = eyeLights(view, cam);
    int slices = view.contourSides >= 3 ? view.contourSides : 16;
    buildDiscs(cam, slices);

    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, paletteTex);
    glActiveTexture(GL_TEXTURE0);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, colorsUbo);

    glm::mat4 shadowMatrix(1), lightView(1), lightProj(1);
    bool shadowOk = false;
    if (shadows) {
      shadowOk = shadowMap.ensureShadowMap(view.shadowMapSize);
      lightCamera(lights[0], cam, lightView, lightProj);
      const glm::mat4 bias(0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 0.5f, 0, 0.5f, 0.5f, 0.5f, 1);
      shadowMatrix = bias * lightProj * lightView;
      if (shadowOk) {
        glBindFramebuffer(GL_FRAMEBUFFER, shadowMap.shadowFbo);
        glViewport(0, 0, shadowMap.shadowSize, shadowMap.shadowSize);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(view.shadowOffsetFactor, view.shadowOffsetUnits);
        beginPass({&cam, &lights, &view, true, true, 1, shadowMatrix, lightView, lightProj});
        depthTestOn = true;
        Pass depth{&mesh[kDepth], &segment[kDepth], &lines[kDepth], false, false, true};
        drawAll(depth, false);
        glDisable(GL_POLYGON_OFFSET_FILL);
        glBindFramebuffer(GL_FRAMEBUFFER, prevFbo);
      } else {
        fail("cannot create the shadow map framebuffer");
      }
    }

    glViewport(options.viewportX, options.viewportY, cam.width, cam.height);
    if (options.clear) {
      // Only this view's rectangle (multi-view windows share one framebuffer).
      glEnable(GL_SCISSOR_TEST);
      glScissor(options.viewportX, options.viewportY, cam.width, cam.height);
      auto bg = palette.background();
      glClearColor(bg[0], bg[1], bg[2], options.backgroundAlpha);
      glClearDepth(1.0);
      glDepthMask(GL_TRUE);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      glDisable(GL_SCISSOR_TEST);
    }
    const bool depthTest = view.zBuffer || shadows;
    depthTestOn = depthTest;
    if (depthTest) {
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
    } else {
      glDisable(GL_DEPTH_TEST);
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    if (wireframe) {
      GLfloat range[2] = {1, 1};
      glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
      wireframeWidth = std::clamp(std::round(view.wireframeLineWidth), range[0], std::max(range[0], std::min(range[1], maxLineWidth)));
    }

    Variant v = shadows ? kShadow : view.renderMode == RenderMode::Filled ? kFlat : kSmooth;
    bool lit = palette.materials || shadows;
    int matBase = palette.materials ? 1 : 6;
    if (shadows) {
      glActiveTexture(GL_TEXTURE2);
      glBindTexture(GL_TEXTURE_2D, shadowOk ? shadowMap.shadowTex : 0);
      glActiveTexture(GL_TEXTURE0);
    }
    labelQuads.prepareLabels(labels, palette, view, cam, options);
    beginPass({&cam, &lights, &view, lit, false, matBase, shadowMatrix, lightView, lightProj});
    Pass pass{&mesh[v], &segment[v], &lines[v], wireframe, view.backfaceCulling, false};
    drawAll(pass, !depthTest || translucent, true);  // blending needs lpfg's order even with a z buffer
    if (wireframe) glLineWidth(1);

    glUseProgram(0);
    glBindVertexArray(0);
    for (int unit : {3, 2, 1, 0}) {
      glActiveTexture(GL_TEXTURE0 + unit);
      glBindTexture(GL_TEXTURE_2D, 0);
      glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_CLIP_DISTANCE1);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) fail("OpenGL error " + std::to_string(e) + " while drawing");
  }

  void release() {
    if (!initialized) return;
    for (Program* ps : {mesh, segment, lines})
      for (int v = 0; v < kVariants; ++v)
        if (ps[v].id) glDeleteProgram(ps[v].id);
    if (text.id) glDeleteProgram(text.id);
    GLuint vaos[] = {meshVao, discVao, emptyVao};
    glDeleteVertexArrays(3, vaos);
    GLuint bufs[] = {meshVbo, meshEbo, discVbo};
    glDeleteBuffers(3, bufs);
    segs.release();
    labelQuads.release();
    if (!textures.empty()) glDeleteTextures((GLsizei)textures.size(), textures.data());
    glDeleteBuffers(1, &colorsUbo);
    glDeleteTextures(1, &paletteTex);
    shadowMap.release();
  }
};

// ---------------------------------------------------------------------------------------------
// Label fonts (fontconfig) and the Renderer's public face

runtime::text::FontSpec labelFont(const ViewSettings& view) {
  return {.family = view.winFont, .weight = view.winFontWeight, .italic = view.winFontItalic};
}

std::string labelFontFile(const ViewSettings& view) { return runtime::text::Fonts::shared().primaryFile(labelFont(view)); }

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {
  impl_->error = &error_;
  impl_->stats = &stats_;
}
Renderer::~Renderer() { impl_->release(); }

void Renderer::setGeometry(const Geometry& geometry) { impl_->setGeometry(geometry); }
void Renderer::setTextures(const std::vector<runtime::Image>& textures) { impl_->setTextures(textures); }
void Renderer::setPalette(const RenderPalette& palette) {
  impl_->palette = palette;
  impl_->paletteDirty = true;
}
void Renderer::draw(const ViewSettings& view, const CameraMatrices& camera, const RenderOptions& options) {
  impl_->draw(view, camera, options);
}

}  // namespace lcjit::viewer
