// The renderer's shader programs (Shaders.cpp holds their GLSL): one program per kind of
// primitive and variant of lpfg's render modes, linked on first use, with its uniform locations
// cached. Internal to the renderer (Renderer.cpp, LabelQuads.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>

#include <epoxy/gl.h>

namespace lcjit::viewer {

// Flat: filled mode (GL_FLAT); smooth: shaded and wireframe (Gouraud); shadow: shadow mode's
// per-fragment lighting; depth: the shadow map's pass.
enum Variant { kFlat = 0, kSmooth, kShadow, kDepth, kVariants };

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

// Compiles and links a variant of a kind of program (0 mesh, 1 segment quads, 2 segment lines),
// its Colors block bound to uniform buffer 0; the first problem goes to `error` (kept if set).
GLuint linkProgram(int kind, int variant, std::string& error);
// The labels' program (their quads over the picture).
GLuint linkTextProgram(std::string& error);

}  // namespace lcjit::viewer
