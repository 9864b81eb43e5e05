// The renderer's lights and shadow map (Lights.cpp): the view file's lights in eye space, as the
// shaders' uniforms take them (what glLightfv would have stored), and the shadow map of lpfg's
// shadow mode, drawn from light 0. Internal to the renderer (Renderer.cpp).
#pragma once
#include <vector>

#include <epoxy/gl.h>
#include <glm/glm.hpp>

#include "runtime/files/ViewFile.h"
#include "runtime/turtle/Camera.h"

namespace lcjit::viewer {

struct EyeLight {
  glm::vec4 pos;
  glm::vec3 spotDir;
  glm::vec2 spot;
  glm::vec3 att, amb, diff, spec;
};


// Lights in eye space (what glLightfv would have stored); lpfg's default light when the view file
// has none, at most 8.
std::vector<EyeLight> eyeLights(const runtime::ViewSettings& view, const runtime::CameraMatrices& cam);

// The depth texture light 0 sees, and the framebuffer that draws it.
struct ShadowMap {
  GLuint shadowFbo = 0, shadowTex = 0;
  int shadowSize = 0;
  // A size × size map (clamped to 16..8192), made or remade; false when the framebuffer is not
  // complete.
  bool ensureShadowMap(int size);
  void release();  // the context must be current
};

// The light's view of the scene (GLWidget::beginShadowMap, made robust): light 0, orthographic
// around the framed volume for a directional light, a 90° frustum for a positional one.
void lightCamera(const EyeLight& l, const runtime::CameraMatrices& cam, glm::mat4& view, glm::mat4& proj);

}  // namespace lcjit::viewer
