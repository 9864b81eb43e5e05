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
// Sections, in order (each begins with a `// ----` rule; Impl's parts with `// --- Name`):
//   Shaders · Shader programs · Renderer::Impl: GL objects and uploads (setGeometry, setTextures,
//   uploadPalette, lights, discs) · --- Drawing ranges (triangles, segments as lines or quads,
//   discs, painter's order, labels where the string has them) · --- Shadows · --- Labels (their
//   quads, a range of them drawn) · --- The frame (draw: passes, clipping, shadow map) · Label
//   fonts and the Renderer's public face. (The multi-view layout is runtime/turtle/ViewLayout.cpp's.)
#include "viewer/Renderer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <unordered_map>

#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <map>
#include <optional>
#include <tuple>

namespace lcjit::viewer {

using runtime::CameraMatrices;
using runtime::DrawBatch;
using runtime::Geometry;
using runtime::MeshVertex;
using runtime::RenderMode;
using runtime::ViewSettings;

static_assert(sizeof(MeshVertex) == 36, "MeshVertex is uploaded as is");

namespace {

constexpr int kMaxLights = 8;
constexpr uint32_t kGroupMinimum = 2048;  // fewer segments with fragmented widths: quads
enum Variant { kFlat = 0, kSmooth, kShadow, kDepth, kVariants };

// ---------------------------------------------------------------------------------------------
// Shaders

const char* kCommon = R"(
#define MAX_LIGHTS 8
uniform sampler2D uPalette;  // 256 x 11: row 0 flat colour; material rows at uMatBase..+4
layout(std140) uniform Colors { vec4 uColors[256]; };  // row 0 again: cheap to index per vertex
uniform int uMatBase;
uniform int uLit;
uniform int uNumLights;
uniform vec4 uLightPos[MAX_LIGHTS];      // eye space; w = 0: directional
uniform vec3 uLightSpotDir[MAX_LIGHTS];  // eye space
uniform vec2 uLightSpot[MAX_LIGHTS];     // exponent, cos(cutoff) (< -1: no spot)
uniform vec3 uLightAtt[MAX_LIGHTS];
uniform vec3 uLightAmb[MAX_LIGHTS];
uniform vec3 uLightDiff[MAX_LIGHTS];
uniform vec3 uLightSpec[MAX_LIGHTS];

vec4 pal(int row, int ci) { return texelFetch(uPalette, ivec2(clamp(ci, 0, 255), row), 0); }
// Indices 0..255, or RGB_COLOR | 0xRRGGBB: a colour as it is (runtime::kRgbColor).
vec4 flatColor(int ci) {
  if (ci >= RGB_COLOR) return vec4(float((ci >> 16) & 255), float((ci >> 8) & 255), float(ci & 255), 255.0) / 255.0;
  return uColors[clamp(ci, 0, 255)];
}

struct Terms { vec3 scene, amb, diff, spec; float alpha; };

// OpenGL's fixed-function lighting equation (infinite viewer, global ambient 0.2).
Terms lightTerms(int ci, vec3 P, vec3 N) {
  vec4 ma = pal(uMatBase, ci), md = pal(uMatBase + 1, ci), ms = pal(uMatBase + 2, ci);
  vec4 me = pal(uMatBase + 3, ci);
  float sh = pal(uMatBase + 4, ci).r;
  Terms t;
  t.scene = me.rgb + 0.2 * ma.rgb;
  t.amb = vec3(0); t.diff = vec3(0); t.spec = vec3(0);
  t.alpha = md.a;
  for (int i = 0; i < uNumLights; ++i) {
    vec3 L;
    float att = 1.0;
    if (uLightPos[i].w == 0.0) {
      L = normalize(uLightPos[i].xyz);
    } else {
      vec3 d = uLightPos[i].xyz - P;
      float dist = length(d);
      L = dist > 0.0 ? d / dist : vec3(0, 0, 1);
      att = 1.0 / max(uLightAtt[i].x + uLightAtt[i].y * dist + uLightAtt[i].z * dist * dist, 1e-20);
      if (uLightSpot[i].y >= -1.0) {
        float sd = dot(-L, normalize(uLightSpotDir[i]));
        att *= sd >= uLightSpot[i].y ? (uLightSpot[i].x == 0.0 ? 1.0 : pow(max(sd, 0.0), uLightSpot[i].x)) : 0.0;
      }
    }
    float nl = max(dot(N, L), 0.0);
    vec3 H = normalize(L + vec3(0, 0, 1));
    float nh = max(dot(N, H), 0.0);
    float pf = nl > 0.0 ? (sh == 0.0 ? 1.0 : pow(nh, sh)) : 0.0;
    t.amb += att * uLightAmb[i] * ma.rgb;
    t.diff += att * nl * uLightDiff[i] * md.rgb;
    t.spec += att * pf * uLightSpec[i] * ms.rgb;
  }
  return t;
}

vec4 litColor(int ci, vec3 P, vec3 N) {
  Terms t = lightTerms(ci, P, N);
  return vec4(clamp(t.scene + t.amb + t.diff + t.spec, 0.0, 1.0), t.alpha);
}
)";

// Varyings shared by the mesh and segment vertex shaders and the one fragment shader.
const char* kVaryingsVS = R"(
#if defined(FLAT)
flat out vec4 vFront; flat out vec4 vBack;
#elif defined(SMOOTH)
out vec4 vFront; out vec4 vBack;
#elif defined(SHADOW)
out vec3 vEyePos; out vec3 vEyeNormal; flat out int vColor; flat out int vUnlit; out vec4 vShadowCoord;
#endif
out vec2 vUV;
uniform mat4 uView, uProj, uPV, uShadowMatrix;
uniform int uOneSided;  // back faces lit as the front (lpfg after a terrain, see Geometry.h)

void shade(vec3 world, vec3 normal, int ci, bool front) {
  bool unlit = uLit == 0 || dot(normal, normal) == 0.0 || ci >= RGB_COLOR;
#if defined(FLAT) || defined(SMOOTH)
  if (unlit) {
    vFront = flatColor(ci); vBack = vFront;
  } else {
    vec3 eye = (uView * vec4(world, 1)).xyz;
    vec3 N = normalize(mat3(uView) * normal);
    vFront = litColor(ci, eye, N);
    vBack = front || uOneSided != 0 ? vFront : litColor(ci, eye, -N);
  }
#elif defined(SHADOW)
  vEyePos = (uView * vec4(world, 1)).xyz; vEyeNormal = mat3(uView) * normal; vColor = ci; vUnlit = unlit ? 1 : 0;
  vShadowCoord = uShadowMatrix * vec4(world, 1);
#endif
}
)";

const char* kMeshVS = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUV;
layout(location = 3) in int aColor;
void main() {
  gl_Position = uPV * vec4(aPos, 1);
  vUV = aUV;
  shade(aPos, aNormal, aColor, false);
}
)";

// Segments as quads: four indexed vertices per segment, no attributes; the segment comes from a
// buffer texture. The quad covers what an aliased wide GL line covers: `w` pixels across the
// minor axis.
const char* kSegmentVS = R"(
uniform samplerBuffer uSegments;  // per segment: (from, width), (to, colour bits)
uniform vec2 uViewport;
const vec2 kCorner[4] = vec2[4](vec2(0, -1), vec2(1, -1), vec2(1, 1), vec2(0, 1));
void main() {
  int s = gl_VertexID >> 2;
  vec2 c = kCorner[gl_VertexID & 3];
  vec4 A = texelFetch(uSegments, 2 * s), B = texelFetch(uSegments, 2 * s + 1);
  float w = max(1.0, floor(A.w + 0.5));
  int ci = floatBitsToInt(B.w);
  vec4 pa = uPV * vec4(A.xyz, 1), pb = uPV * vec4(B.xyz, 1);
  float da = pa.z + pa.w, db = pb.z + pb.w;  // signed distances to the near plane
  vUV = vec2(0);
  if (da < 0.0 && db < 0.0) { gl_Position = vec4(2, 2, 2, 1); shade(A.xyz, vec3(0, 0, 1), ci, true); return; }
  if (da < 0.0) pa = mix(pa, pb, da / (da - db));
  else if (db < 0.0) pb = mix(pb, pa, db / (db - da));
  vec2 sa = pa.xy / pa.w * uViewport, sb = pb.xy / pb.w * uViewport;
  vec2 d = sb - sa;
  vec2 off = abs(d.x) >= abs(d.y) ? vec2(0, 1) : vec2(1, 0);
  vec4 p = c.x == 0.0 ? pa : pb;
  p.xy += off * (c.y * 0.5 * w) / uViewport * p.w;
  gl_Position = p;
  shade(c.x == 0.0 ? A.xyz : B.xyz, vec3(0, 0, 1), ci, true);
}
)";

// Segments as GL lines (runs of one width, when the driver has wide lines): vertex i is texel i.
// With uOrderDepth the depth is the segment's number (later = nearer) so that segments drawn
// grouped by width still show painter's order; the real depth then only clips.
const char* kLineVS = R"(
uniform samplerBuffer uSegments;
uniform int uOrderDepth;
uniform float uOrderScale;
uniform int uChunkFirst;
void main() {
  vec4 P = texelFetch(uSegments, gl_VertexID);
  int ci = floatBitsToInt(texelFetch(uSegments, gl_VertexID | 1).w);
  gl_Position = uPV * vec4(P.xyz, 1);
  gl_ClipDistance[0] = gl_Position.z + gl_Position.w;
  gl_ClipDistance[1] = gl_Position.w - gl_Position.z;
  if (uOrderDepth != 0)
    gl_Position.z = (1.0 - 2.0 * float(uChunkFirst + (gl_VertexID >> 1) + 1) * uOrderScale) * gl_Position.w;
  vUV = vec2(0);
  shade(P.xyz, vec3(0, 0, 1), ci, true);
}
)";

const char* kFS = R"(
#if defined(FLAT)
flat in vec4 vFront; flat in vec4 vBack;
#elif defined(SMOOTH)
in vec4 vFront; in vec4 vBack;
#elif defined(SHADOW)
in vec3 vEyePos; in vec3 vEyeNormal; flat in int vColor; flat in int vUnlit; in vec4 vShadowCoord;
uniform sampler2DShadow uShadowMap;
uniform vec3 uShadowColor;
#endif
in vec2 vUV;
uniform sampler2D uTexture;
uniform int uTextured;
uniform int uForceFront;
uniform int uOneSided;
out vec4 oColor;
void main() {
  bool front = gl_FrontFacing || uForceFront != 0;
#if defined(DEPTH)
  if (uTextured != 0 && texture(uTexture, vUV).a <= 0.0) discard;
  oColor = vec4(1);
  return;
#elif defined(FLAT) || defined(SMOOTH)
  vec4 c = front ? vFront : vBack;
  if (uTextured != 0) c *= texture(uTexture, vUV);
#elif defined(SHADOW)
  vec4 c;
  if (vUnlit != 0) {
    c = flatColor(vColor);
    if (uTextured != 0) c *= texture(uTexture, vUV);
  } else {
    float vis = 0.0;
    for (float y = -1.5; y <= 1.5; y += 1.0)
      for (float x = -1.5; x <= 1.5; x += 1.0)
        vis += textureProj(uShadowMap, vShadowCoord + vec4(x, y, 0, 0) * 0.0005) < 1.0 ? 0.0 : 1.0;
    vis *= 0.0625;
    vec3 N = normalize(vEyeNormal);
    if (!front && uOneSided == 0) N = -N;
    Terms t = lightTerms(vColor, vEyePos, N);
    c = vec4(t.scene + t.amb + t.diff * (vis + (1.0 - vis) * uShadowColor), t.alpha);
    vec4 tex = uTextured != 0 ? texture(uTexture, vUV) : vec4(1);
    c *= tex;
    c.rgb += t.spec * vis;
    c = clamp(c, 0.0, 1.0);
  }
#endif
#if !defined(DEPTH)
  if (c.a <= 0.1) discard;
  oColor = c;
#endif
}
)";

const char* kTextVS = R"(
layout(location = 0) in vec2 aPos;  // window pixels, y down
layout(location = 1) in vec2 aUV;
layout(location = 2) in vec4 aColor;  // the label colour's bytes, 0-255
uniform vec2 uViewport;
out vec2 vUV; out vec4 vColor;
void main() {
  gl_Position = vec4(aPos.x / uViewport.x * 2.0 - 1.0, 1.0 - aPos.y / uViewport.y * 2.0, 0, 1);
  vUV = aUV; vColor = aColor;
}
)";
const char* kTextFS = R"(
in vec2 vUV; in vec4 vColor;
uniform sampler2D uAtlas;
out vec4 oColor;
// Qt's premultiplied pixel (LabelText.h premultiply(): x·a + (x·a >> 8) + 128 >> 8, exact in
// floats), blended ONE, ONE_MINUS_SRC_ALPHA; lpfg's alpha test drops coverage under 27/255
// (kMinDrawnCoverage).
void main() {
  float a = floor(texture(uAtlas, vUV).r * 255.0 + 0.5);
  if (a < 27.0) discard;
  vec3 t = vColor.rgb * a;
  oColor = vec4(floor((t + floor(t / 256.0) + 128.0) / 256.0) / 255.0, a / 255.0);
}
)";
static_assert(runtime::text::kMinDrawnCoverage == 27, "kTextFS's alpha test");

// ---------------------------------------------------------------------------------------------
// Shader programs (compile, link, one per variant)

struct Program {
  GLuint id = 0;
  int kind = 0, variant = 0;  // kind: 0 mesh, 1 segment quads, 2 segment lines
  uint64_t serial = 0;        // the pass whose uniforms it holds
  std::unordered_map<std::string, GLint> locations;
  GLint loc(const char* name) {
    auto it = locations.find(name);
    if (it != locations.end()) return it->second;
    GLint l = glGetUniformLocation(id, name);
    locations.emplace(name, l);
    return l;
  }
};

GLuint compile(GLenum type, const std::string& src, std::string& error) {
  GLuint s = glCreateShader(type);
  const char* p = src.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    if (error.empty()) error = std::string("shader compilation failed: ") + log;
  }
  return s;
}

GLuint link(const std::string& vs, const std::string& fs, std::string& error) {
  GLuint v = compile(GL_VERTEX_SHADER, vs, error), f = compile(GL_FRAGMENT_SHADER, fs, error);
  GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    if (error.empty()) error = std::string("shader link failed: ") + log;
  }
  return p;
}

const char* variantDefine(int v) {
  switch (v) {
    case kFlat: return "#define FLAT\n";
    case kSmooth: return "#define SMOOTH\n";
    case kShadow: return "#define SHADOW\n";
    default: return "#define DEPTH\n";
  }
}

struct EyeLight {
  glm::vec4 pos;
  glm::vec3 spotDir;
  glm::vec2 spot;
  glm::vec3 att, amb, diff, spec;
};

// A million segments are 2M texels; GL 3.3 only promises 64K texels per buffer texture.
// Segments of one rounded width, for drawing fragmented widths as a few GL_LINES draws.
struct WidthGroup {
  float width = 1;
  uint32_t offset = 0;        // first index in the chunk's group index buffer
  std::vector<uint32_t> ids;  // chunk-local segment numbers, increasing
};

struct SegmentChunk {
  GLuint buffer = 0, texture = 0;
  uint32_t first = 0, count = 0;
  GLuint groupEbo = 0;
  std::vector<WidthGroup> groups;  // empty unless the widths are fragmented
};

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

}  // namespace

// ---------------------------------------------------------------------------------------------
// Renderer::Impl: GL objects, uploads of the geometry, palette and textures

struct Renderer::Impl {
  bool initialized = false;
  bool failed = false;
  Program mesh[kVariants], segment[kVariants], lines[kVariants], text;
  GLuint quadEbo = 0;
  uint32_t quadEboSegments = 0;
  float maxLineWidth = 1;
  // Runs of segments of one rounded width: (first segment, width); a sentinel ends the list.
  std::vector<std::pair<uint32_t, float>> widthRuns;
  GLuint meshVao = 0, meshVbo = 0, meshEbo = 0;
  size_t meshVboSize = 0, meshEboSize = 0;
  GLuint discVao = 0, discVbo = 0;
  size_t discVboSize = 0;
  GLuint emptyVao = 0;
  GLuint textVao = 0, textVbo = 0;
  size_t textVboSize = 0;
  GLuint paletteTex = 0, colorsUbo = 0;
  GLuint shadowFbo = 0, shadowTex = 0;
  int shadowSize = 0;
  std::vector<GLuint> textures;
  std::vector<SegmentChunk> chunks;
  GLint maxTexelsBuffer = 65536;

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

  LabelAtlas labelAtlas;
  // This frame's label quads in textVbo (prepareLabels): label i's six vertices (none when it is
  // not drawn) from labelFirstVertex[i]; empty when no label is drawn.
  std::vector<uint32_t> labelFirstVertex;
  glm::vec2 labelViewport{1, 1};

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
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexelsBuffer);
    if (maxTexelsBuffer < 2) maxTexelsBuffer = 65536;

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
    glGenBuffers(1, &quadEbo);
    glBindVertexArray(emptyVao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, quadEbo);
    glBindVertexArray(0);
    GLfloat range[2] = {1, 1};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    maxLineWidth = range[1];
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if (flags & GL_CONTEXT_FLAG_FORWARD_COMPATIBLE_BIT) maxLineWidth = 1;  // wide lines removed (macOS)

    glGenVertexArrays(1, &textVao);
    glGenBuffers(1, &textVbo);
    glBindVertexArray(textVao);
    glBindBuffer(GL_ARRAY_BUFFER, textVbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 32, (void*)0);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 32, (void*)8);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, 32, (void*)16);
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glEnableVertexAttribArray(2);
    glBindVertexArray(0);

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

    // Segments: 32 bytes each, in chunks that fit a buffer texture.
    segmentCount = (uint32_t)g.segments.size();
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
        const runtime::Segment& s = g.segments[sc.first + i];
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
      float w = lineWidth(g.segments[i].width);
      if (widthRuns.empty() || widthRuns.back().second != w) widthRuns.push_back({i, w});
    }
    widthRuns.push_back({segmentCount, 0});

    // Fragmented widths: index lists per width, per chunk.
    const bool fragmented = segmentCount >= kGroupMinimum && (widthRuns.size() - 1) * 16 > segmentCount;
    for (SegmentChunk& sc : chunks) {
      sc.groups.clear();
      if (!fragmented) continue;
      std::vector<float> widths;
      for (uint32_t i = 0; i < sc.count; ++i) widths.push_back(lineWidth(g.segments[sc.first + i].width));
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

  // An aliased GL line's width: rounded, at least 1.
  static float lineWidth(float w) { return std::max(1.0f, std::floor(w + 0.5f)); }

  void setTextures(const std::vector<TextureImage>& images) {
    init();
    if (!textures.empty()) glDeleteTextures((GLsizei)textures.size(), textures.data());
    textures.assign(images.size(), 0);
    if (images.empty()) return;
    glGenTextures((GLsizei)textures.size(), textures.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    std::vector<uint8_t> flipped;
    for (size_t i = 0; i < images.size(); ++i) {
      const TextureImage& im = images[i];
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

  // Lights in eye space (what glLightfv would have stored).
  static std::vector<EyeLight> eyeLights(const ViewSettings& view, const CameraMatrices& cam) {
    std::vector<runtime::Light> lights = view.lights;
    if (lights.empty()) {
      runtime::Light d;  // lpfg's default light: V: 0 0 1, ambient/diffuse/specular white
      d.kind = runtime::Light::Kind::Directional;
      d.position = V3f(0, 0, 1);
      d.ambient = {1, 1, 1};
      d.diffuse = {1, 1, 1};
      d.specular = {1, 1, 1};
      lights.push_back(d);
    }
    if (lights.size() > kMaxLights) lights.resize(kMaxLights);
    const glm::mat4 m = view.stationaryLights ? cam.stationaryLights : cam.view;
    std::vector<EyeLight> out;
    for (const runtime::Light& l : lights) {
      EyeLight e;
      glm::vec3 p(l.position.x, l.position.y, l.position.z);
      if (l.kind == runtime::Light::Kind::Directional) {
        glm::vec3 d = glm::mat3(m) * p;
        if (glm::length(d) > 0) d = glm::normalize(d);
        e.pos = glm::vec4(d, 0);
      } else {
        e.pos = m * glm::vec4(p, 1);
        if (e.pos.w != 0) e.pos /= e.pos.w;
      }
      e.spotDir = glm::mat3(m) * glm::vec3(l.spotDirection.x, l.spotDirection.y, l.spotDirection.z);
      bool spot = l.kind != runtime::Light::Kind::Directional && l.spotCutoff != 180;
      e.spot = glm::vec2(l.spotExponent, spot ? std::cos(glm::radians(std::clamp(l.spotCutoff, 0.0f, 90.0f))) : -2.0f);
      e.att = glm::vec3(l.attenuation[0], l.attenuation[1], l.attenuation[2]);
      e.amb = glm::vec3(l.ambient.r, l.ambient.g, l.ambient.b);
      e.diff = glm::vec3(l.diffuse.r, l.diffuse.g, l.diffuse.b);
      e.spec = glm::vec3(l.specular.r, l.specular.g, l.specular.b);
      out.push_back(e);
    }
    return out;
  }

  // Programs are linked on first use (llvmpipe compiles each one it is given).
  bool ensureLinked(Program& p) {
    if (p.id) return true;
    if (failed) return false;
    std::string err;
    if (&p == &text) {
      p.id = link(std::string("#version 330 core\n") + kTextVS, std::string("#version 330 core\n") + kTextFS, err);
    } else {
      std::string prelude = std::string("#version 330 core\n") + variantDefine(p.variant) +
                            "#define RGB_COLOR " + std::to_string(runtime::kRgbColor) + "\n" + kCommon;
      const char* body = p.kind == 0 ? kMeshVS : p.kind == 1 ? kSegmentVS : kLineVS;
      p.id = link(prelude + kVaryingsVS + body, prelude + kFS, err);
      GLuint block = glGetUniformBlockIndex(p.id, "Colors");
      if (block != GL_INVALID_INDEX) glUniformBlockBinding(p.id, block, 0);
    }
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
    glUniform2f(p.loc("uViewport"), depthPass ? shadowSize * 0.5f : cam.width * 0.5f,
                depthPass ? shadowSize * 0.5f : cam.height * 0.5f);
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
  // (cleared first) when the z buffer is off. False when the chunks have no groups.
  bool drawGrouped(const Pass& pass, uint32_t first, uint32_t count) {
    uint32_t end = first + count;
    for (const SegmentChunk& c : chunks)
      if (std::max(first, c.first) < std::min(end, c.first + c.count) && c.groups.empty()) return false;
    for (const SegmentChunk& c : chunks)
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
    for (const SegmentChunk& c : chunks) {
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
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, quadEbo);
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
    auto run = std::upper_bound(widthRuns.begin(), widthRuns.end(), first,
                                [](uint32_t v, const std::pair<uint32_t, float>& r) { return v < r.first; });
    if (run != widthRuns.begin()) --run;
    size_t nRuns = 0;
    bool linesOk = true;
    for (auto r = run; r != widthRuns.end() && r->first < end && r->second > 0; ++r) {
      ++nRuns;
      linesOk = linesOk && r->second <= maxLineWidth;
    }
    const bool asLines = linesOk && nRuns * 16 <= count + 15;
    if (!asLines && linesOk && count >= kGroupMinimum && !translucent && drawGrouped(pass, first, count)) return;
    useSegments(pass, asLines);
    glBindVertexArray(emptyVao);
    glUniform1i((asLines ? pass.lineProg : pass.segProg)->loc("uForceFront"), 1);
    for (const SegmentChunk& c : chunks) {
      uint32_t a = std::max(first, c.first), b = std::min(end, c.first + c.count);
      if (a >= b) continue;
      glActiveTexture(GL_TEXTURE3);
      glBindTexture(GL_TEXTURE_BUFFER, c.texture);
      if (!asLines) {
        glDrawElements(GL_TRIANGLES, GLsizei(b - a) * 6, GL_UNSIGNED_INT, (void*)(size_t(a - c.first) * 6 * sizeof(uint32_t)));
        ++stats->drawCalls;
        continue;
      }
      for (auto r = run; r != widthRuns.end() && r->first < b && r->second > 0; ++r) {
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
        if (!painterOrder) {
          lo[k] = std::min(lo[k], b.first);
          hi[k] = std::max(hi[k], b.first + b.count);
          continue;
        }
        switch (b.kind) {
          case DrawBatch::Kind::Triangles:
            drawTriangles(pass, b.first, std::min(b.count, indexCount > b.first ? indexCount - b.first : 0));
            break;
          case DrawBatch::Kind::Segments:
            drawSegments(pass, b.first, std::min(b.count, segmentCount > b.first ? segmentCount - b.first : 0));
            break;
          case DrawBatch::Kind::Discs: drawDiscs(pass, b.first, b.count); break;
          case DrawBatch::Kind::Labels: break;
        }
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

  // --- Shadows ---------------------------------------------------------------------------------

  bool ensureShadowMap(int size) {
    size = std::clamp(size, 16, 8192);
    if (shadowFbo && shadowSize == size) return true;
    if (!shadowTex) glGenTextures(1, &shadowTex);
    glBindTexture(GL_TEXTURE_2D, shadowTex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    const float ones[4] = {1, 1, 1, 1};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, ones);
    glBindTexture(GL_TEXTURE_2D, 0);
    if (!shadowFbo) glGenFramebuffers(1, &shadowFbo);
    glBindFramebuffer(GL_FRAMEBUFFER, shadowFbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadowTex, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    bool ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    shadowSize = size;
    return ok;
  }

  // The light's view of the scene (GLWidget::beginShadowMap, made robust): light 0, orthographic
  // around the framed volume for a directional light, a 90° frustum for a positional one.
  static void lightCamera(const EyeLight& l, const CameraMatrices& cam, glm::mat4& view, glm::mat4& proj) {
    glm::mat4 inv = glm::inverse(cam.view);
    runtime::Bounds b = cam.bounds;
    glm::vec3 center = b.empty() ? cam.lookAt : glm::vec3(b.center().x, b.center().y, b.center().z);
    float r = b.empty() ? 1.0f : 0.5f * glm::length(glm::vec3(b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z));
    if (!(r > 1e-6f)) r = 1e-3f;
    glm::vec3 dir;
    glm::vec3 eyeOrLight;
    if (l.pos.w == 0) {
      dir = -glm::normalize(glm::mat3(inv) * glm::vec3(l.pos));  // from the light into the scene
      eyeOrLight = center - 2.0f * r * dir;
    } else {
      eyeOrLight = glm::vec3(inv * glm::vec4(glm::vec3(l.pos), 1));
      glm::vec3 sd = glm::mat3(inv) * l.spotDir;
      dir = glm::length(sd) > 0 ? glm::normalize(sd) : glm::normalize(center - eyeOrLight);
    }
    glm::vec3 up(0, 1, 0);
    if (std::fabs(glm::dot(up, dir)) > 0.99f) up = glm::vec3(0, 0, 1);
    view = glm::lookAt(eyeOrLight, eyeOrLight + dir, up);
    if (l.pos.w == 0) {
      proj = glm::ortho(-r, r, -r, r, r * 0.5f, r * 3.5f);
    } else {
      float farClip = glm::length(center - eyeOrLight) + 2 * r;
      proj = glm::perspective(glm::radians(90.0f), 1.0f, farClip * 1e-3f, farClip);
    }
  }

  // --- Labels ----------------------------------------------------------------------------------

  // Pictures are shelf-packed into the atlas as they first appear; a full atlas doubles and
  // everything is packed again.
  bool packLabel(const std::string& text, const std::vector<uint8_t>& bits) {
    LabelAtlas& a = labelAtlas;
    LabelImage& im = a.images[text];
    if (im.width == 0) return true;
    const int size = a.atlasSize;
    if (im.width + 2 > size) return false;
    if (a.x + im.width + 1 > size) a.x = 1, a.y += a.rowHeight + 1, a.rowHeight = 0;
    if (a.y + im.height + 1 > size) return false;
    im.x = a.x, im.y = a.y;
    for (int r = 0; r < im.height; ++r)
      std::memcpy(&a.pixels[size_t(im.y + r) * size + im.x], &bits[size_t(r) * im.width], (size_t)im.width);
    a.x += im.width + 1;
    a.rowHeight = std::max(a.rowHeight, im.height);
    a.dirty = true;
    return true;
  }

  // The picture of a label text, drawn and packed the first time.
  const LabelImage& labelImage(const std::string& text) {
    LabelAtlas& a = labelAtlas;
    if (auto it = a.images.find(text); it != a.images.end()) return it->second;
    runtime::text::Fonts& fonts = runtime::text::Fonts::shared();
    runtime::text::GlyphBitmap b =
        fonts.labelBitmap(fonts.shape(text, a.spec, (float)runtime::text::pixelSizeForPoints(a.points)), a.points);
    LabelImage& im = a.images[text];
    im.left = b.left, im.top = b.top, im.width = b.width, im.height = b.height;
    if (a.pixels.empty()) a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
    bool fits = packLabel(text, b.pixels);
    while (!fits && a.atlasSize < 4096) {
      a.atlasSize *= 2;
      a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
      a.x = a.y = 1, a.rowHeight = 0;
      fits = packLabel(text, b.pixels);
      for (auto& [t, bits] : a.bitmaps) fits = fits && packLabel(t, bits);
    }
    if (!fits) {  // the largest atlas is full: start it afresh (labels already placed this frame are skipped)
      a.images.clear(), a.bitmaps.clear();
      std::fill(a.pixels.begin(), a.pixels.end(), 0);
      a.x = a.y = 1, a.rowHeight = 0;
      LabelImage& fresh = a.images[text];
      fresh.left = b.left, fresh.top = b.top, fresh.width = b.width, fresh.height = b.height;
      if (!packLabel(text, b.pixels)) fresh.width = 0;
      a.bitmaps[text] = std::move(b.pixels);
      return fresh;
    }
    a.bitmaps[text] = std::move(b.pixels);
    return im;
  }

  void uploadAtlas() {
    LabelAtlas& a = labelAtlas;
    if (!a.atlas) glGenTextures(1, &a.atlas);
    glBindTexture(GL_TEXTURE_2D, a.atlas);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (a.pixels.empty()) a.pixels.assign(size_t(a.atlasSize) * a.atlasSize, 0);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, a.atlasSize, a.atlasSize, 0, GL_RED, GL_UNSIGNED_BYTE, a.pixels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    a.dirty = false;
  }

  // Each label's picture at its anchor's pixel (runtime/text: lpfg's pixmap, its left end 5 px
  // before the anchor, the baseline 2 px below it): the quads of the frame's labels, uploaded
  // before anything is drawn, since drawAll draws them where the string has them.
  void prepareLabels(const ViewSettings& view, const CameraMatrices& cam, const RenderOptions& options) {
    labelFirstVertex.clear();
    if (labels.empty() || !options.drawLabels) return;
    runtime::text::FontSpec spec = labelFont(view);
    spec.file = options.fontFile;
    // A new font, or an atlas grown mostly of texts earlier frames had (an animated counter's):
    // drawn afresh.
    if (!(spec == labelAtlas.spec) || labelAtlas.points != view.winFontSize ||
        labelAtlas.images.size() > 4 * labels.size() + 1024)
      labelAtlas = LabelAtlas{.spec = spec, .points = view.winFontSize, .atlas = labelAtlas.atlas};
    // Quads first (they may grow the atlas), the texture coordinates once the atlas is final.
    struct Quad {
      int x, y;  // the anchor's pixel
      const std::string* text;
      std::array<float, 4> col;
    };
    std::vector<std::optional<Quad>> quads(labels.size());
    bool any = false;
    for (size_t i = 0; i < labels.size(); ++i) {
      const runtime::Label& l = labels[i];
      glm::vec4 c = cam.projection * cam.view * glm::vec4(l.position.x, l.position.y, l.position.z, 1);
      if (c.w <= 0) continue;
      glm::vec3 w = runtime::projectToWindow(cam, l.position);
      if (labelImage(l.text).width == 0) continue;
      auto col = palette.textColor(l.color);
      std::array<float, 4> bytes{};
      for (int k = 0; k < 3; ++k) bytes[k] = (float)runtime::text::colorByte(col[k]);
      quads[i] = Quad{(int)std::round(w.x), (int)std::round(w.y), &l.text, bytes};
      any = true;
    }
    if (!any) return;
    if (labelAtlas.dirty || !labelAtlas.atlas) uploadAtlas();
    std::vector<float> v;
    v.reserve(labels.size() * 48);
    labelFirstVertex.reserve(labels.size() + 1);
    const float n = 1.0f / labelAtlas.atlasSize;
    for (const std::optional<Quad>& q : quads) {
      labelFirstVertex.push_back(uint32_t(v.size() / 8));
      if (!q) continue;
      auto it = labelAtlas.images.find(*q->text);
      if (it == labelAtlas.images.end() || it->second.width == 0) continue;
      const LabelImage& im = it->second;
      float x0 = float(q->x + im.left), y0 = float(q->y - im.top), x1 = x0 + im.width, y1 = y0 + im.height;
      float s0 = im.x * n, t0 = im.y * n, s1 = (im.x + im.width) * n, t1 = (im.y + im.height) * n;
      float quad[6][4] = {{x0, y0, s0, t0}, {x1, y0, s1, t0}, {x1, y1, s1, t1},
                          {x0, y0, s0, t0}, {x1, y1, s1, t1}, {x0, y1, s0, t1}};
      for (auto& p : quad) v.insert(v.end(), {p[0], p[1], p[2], p[3], q->col[0], q->col[1], q->col[2], 1.0f});
    }
    labelFirstVertex.push_back(uint32_t(v.size() / 8));
    if (v.empty()) {
      labelFirstVertex.clear();
      return;
    }
    glBindBuffer(GL_ARRAY_BUFFER, textVbo);
    if (v.size() * sizeof(float) > textVboSize) {
      textVboSize = v.size() * sizeof(float);
      glBufferData(GL_ARRAY_BUFFER, textVboSize, v.data(), GL_STREAM_DRAW);
    } else {
      glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(float), v.data());
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    labelViewport = {(float)cam.width, (float)cam.height};
  }

  // Labels [first, first+count) over what is drawn so far, as lpfg's QPainter draws its pixmap (no
  // depth test, no depth written); the state the other draws expect is theirs again afterwards.
  void drawLabelRange(uint32_t first, uint32_t count) {
    if (labelFirstVertex.empty() || first >= labels.size()) return;
    const uint32_t end = std::min<uint32_t>(first + count, (uint32_t)labels.size());
    const uint32_t a = labelFirstVertex[first], b = labelFirstVertex[end];
    if (a >= b || !ensureLinked(text)) return;
    glUseProgram(text.id);
    glUniform2f(text.loc("uViewport"), labelViewport.x, labelViewport.y);
    glUniform1i(text.loc("uAtlas"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, labelAtlas.atlas);
    glBindVertexArray(textVao);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    clipDistances(false);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // Qt's premultiplied pixmap
    glDrawArrays(GL_TRIANGLES, GLint(a), GLsizei(b - a));
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    ++stats->drawCalls;
    glBindVertexArray(0);
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
      shadowOk = ensureShadowMap(view.shadowMapSize);
      lightCamera(lights[0], cam, lightView, lightProj);
      const glm::mat4 bias(0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 0.5f, 0, 0.5f, 0.5f, 0.5f, 1);
      shadowMatrix = bias * lightProj * lightView;
      if (shadowOk) {
        glBindFramebuffer(GL_FRAMEBUFFER, shadowFbo);
        glViewport(0, 0, shadowSize, shadowSize);
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
      glBindTexture(GL_TEXTURE_2D, shadowOk ? shadowTex : 0);
      glActiveTexture(GL_TEXTURE0);
    }
    prepareLabels(view, cam, options);
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
    GLuint vaos[] = {meshVao, discVao, emptyVao, textVao};
    glDeleteVertexArrays(4, vaos);
    GLuint bufs[] = {meshVbo, meshEbo, discVbo, textVbo, quadEbo};
    glDeleteBuffers(5, bufs);
    for (SegmentChunk& c : chunks) {
      glDeleteBuffers(1, &c.buffer);
      glDeleteTextures(1, &c.texture);
      if (c.groupEbo) glDeleteBuffers(1, &c.groupEbo);
    }
    if (!textures.empty()) glDeleteTextures((GLsizei)textures.size(), textures.data());
    glDeleteBuffers(1, &colorsUbo);
    GLuint tex[] = {paletteTex, shadowTex, labelAtlas.atlas};
    glDeleteTextures(3, tex);
    if (shadowFbo) glDeleteFramebuffers(1, &shadowFbo);
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
void Renderer::setTextures(const std::vector<TextureImage>& textures) { impl_->setTextures(textures); }
void Renderer::setPalette(const RenderPalette& palette) {
  impl_->palette = palette;
  impl_->paletteDirty = true;
}
void Renderer::draw(const ViewSettings& view, const CameraMatrices& camera, const RenderOptions& options) {
  impl_->draw(view, camera, options);
}

}  // namespace lcjit::viewer
