// The lights as the shaders take them and lpfg's shadow map (Lights.h): the view file's lights
// in eye space, and the depth texture light 0 sees in shadow mode (GLWidget::beginShadowMap).
//
// Sections, in order (each begins with a `// ----` rule): Lights in eye space · The shadow map
// (its framebuffer, the light's camera).
#include "viewer/Lights.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace lcjit::viewer {

using runtime::CameraMatrices;
using runtime::ViewSettings;

namespace {
constexpr int kMaxLights = 8;  // the shaders' MAX_LIGHTS
}  // namespace

// ---------------------------------------------------------------------------------------------
// Lights in eye space

// Lights in eye space (what glLightfv would have stored).
std::vector<EyeLight> eyeLights(const ViewSettings& view, const CameraMatrices& cam) {
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

// ---------------------------------------------------------------------------------------------
// The shadow map

bool ShadowMap::ensureShadowMap(int size) {
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
void lightCamera(const EyeLight& l, const CameraMatrices& cam, glm::mat4& view, glm::mat4& proj) {
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

void ShadowMap::release() {
  if (shadowTex) glDeleteTextures(1, &shadowTex);
  if (shadowFbo) glDeleteFramebuffers(1, &shadowFbo);
}

}  // namespace lcjit::viewer
