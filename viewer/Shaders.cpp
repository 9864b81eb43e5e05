// The renderer's GLSL (330 core): lpfg's fixed-function pipeline restated (OpenGL's lighting
// equation, flat and Gouraud shading, two-sided lighting, GL_MODULATE textures, the alpha test),
// lpfg's shadow mode (shaders/main_fshader.glsl: the shadow map from light 0), segments as GL
// lines or screen-space quads, and labels as Qt draws their pixmaps. Renderer.cpp links them
// per variant on first use (Shaders.h).
//
// Sections, in order (each begins with a `// ----` rule): Shaders (the sources) · Shader
// programs (compile, link, one per variant).
#include "viewer/Shaders.h"

#include "runtime/text/LabelText.h"
#include "runtime/turtle/Geometry.h"

namespace lcjit::viewer {
namespace {

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

}  // namespace

GLuint linkProgram(int kind, int variant, std::string& error) {
  std::string prelude = std::string("#version 330 core\n") + variantDefine(variant) +
                        "#define RGB_COLOR " + std::to_string(runtime::kRgbColor) + "\n" + kCommon;
  const char* body = kind == 0 ? kMeshVS : kind == 1 ? kSegmentVS : kLineVS;
  GLuint id = link(prelude + kVaryingsVS + body, prelude + kFS, error);
  GLuint block = glGetUniformBlockIndex(id, "Colors");
  if (block != GL_INVALID_INDEX) glUniformBlockBinding(id, block, 0);
  return id;
}

GLuint linkTextProgram(std::string& error) {
  return link(std::string("#version 330 core\n") + kTextVS, std::string("#version 330 core\n") + kTextFS, error);
}

}  // namespace lcjit::viewer
