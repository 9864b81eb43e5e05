// The OpenGL renderer: draws a runtime::Geometry the way lpfg draws it (vlab lpfg/glenv.cpp,
// glturtle.cpp, glwidget.cpp, view.cpp, lightsrc.cpp, material.cpp, shaders/*.glsl). A consumer of
// data, like Dear ImGui's backends: upload a Geometry into buffers, draw it with a palette, a view
// file and a camera. It knows nothing of turtles. Shared by the headless renderer (Headless.h) and
// the interactive viewer; the caller owns the GL context and the framebuffer.
//
// GL level: OpenGL 3.3 core (or any compatibility context ≥ 3.3), GLSL 330, through libepoxy.
// That is what Mesa's llvmpipe gives through EGL with no display, what GLFW gives on every
// desktop (macOS stops at 4.1 core), and shaders are needed anyway for lpfg's shadow mode. lpfg's
// fixed-function pipeline is restated in shaders: per-vertex OpenGL lighting (GL_FLAT in filled
// mode, Gouraud in shaded/wireframe), two-sided lighting, infinite viewer, global ambient 0.2,
// GL_MODULATE textures with GL_NEAREST, alpha test > 0.1, SRC_ALPHA blending. Pixel-style lines
// (`line style: pixel`, glLineWidth(width) in lpfg) come from one buffer texture and are drawn
//  - as GL_LINES with glLineWidth, one draw per run of equal (rounded) width, when runs are long;
//  - grouped by width when widths change every few segments, painter's order then kept through
//    the depth buffer (segment number as depth) when the z buffer is off;
//  - else (short batches, translucent colours, no wide lines as in macOS core profiles) as
//    screen-space quads covering what an aliased wide GL line covers.
// A million segments take ~0.2 s to draw on llvmpipe with two cores.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/turtle/Camera.h"
#include "runtime/turtle/Geometry.h"
#include "runtime/turtle/ViewLayout.h"
#include "runtime/files/Palette.h"
#include "runtime/files/Images.h"
#include "runtime/files/ViewFile.h"
#include "runtime/text/LabelText.h"

namespace lcjit::viewer {

// Colours as the renderer consumes them: resolved from a runtime::Palette (fromPalette) or built
// directly. Default: lpfg's colormap without a .map file (0 black, 1..255 white).
struct RenderPalette {
  bool materials = false;                      // a .mat file: everything drawn lit
  std::array<std::array<float, 4>, 256> color;  // flat (unlit) colour per index
  std::array<runtime::Material, 256> material;

  RenderPalette() {
    for (auto& c : color) c = {1, 1, 1, 1};
    color[0] = {0, 0, 0, 1};
  }
  // Background: colour 0, or the emission of material 0 (lpfg GLEnv::ClearColor).
  std::array<float, 4> background() const {
    if (materials) return {material[0].emission[0], material[0].emission[1], material[0].emission[2], 1};
    return color[0];
  }
  // Label colour: the colour, or the material's emission (lpfg GLEnv::GetTextColor).
  std::array<float, 4> textColor(int i) const {
    i = i < 0 ? 0 : i > 255 ? 255 : i;
    if (materials) return {material[i].emission[0], material[i].emission[1], material[i].emission[2], 1};
    return color[i];
  }
  // Inline so that code not calling it needs no Palette.cpp.
  static RenderPalette fromPalette(const runtime::Palette& p) {
    RenderPalette r;
    r.materials = p.usesMaterials();
    for (int i = 0; i < 256; ++i) {
      r.color[i] = p.color(i);
      r.material[i] = p.material(i);
    }
    return r;
  }
};

struct RenderOptions {
  bool drawLabels = true;
  // A font file for labels; empty: fontconfig's match for `winfont:` (labelFontFile). Either
  // way, characters the face lacks come from fontconfig's fallback faces.
  std::string fontFile;
  bool clear = true;             // clear to the background colour first
  float backgroundAlpha = 1;     // lpfg clears with alpha 0; 1 gives an opaque image
  // Where the camera's width × height go in the framebuffer (lower-left corner, GL pixels):
  // multi-view windows draw each view into its own rectangle.
  int viewportX = 0, viewportY = 0;
};

struct RenderStats {
  size_t triangles = 0, segments = 0, discs = 0, labels = 0, drawCalls = 0;
};

// The font file RenderOptions::fontFile = "" stands for, and the request it is fontconfig's
// match for (the view file's `winfont:`).
std::string labelFontFile(const runtime::ViewSettings& view);
runtime::text::FontSpec labelFont(const runtime::ViewSettings& view);

class Renderer {
 public:
  // Needs a current OpenGL ≥ 3.3 context; GL objects are created lazily on first use.
  Renderer();
  ~Renderer();  // the context must still be current
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads the geometry (buffers are reused when large enough). Discs and labels are kept on the
  // CPU: they face the camera, so they are built per frame.
  void setGeometry(const runtime::Geometry& geometry);
  // Texture i is the `texture:` entry i of the view file; TriangleRun::texture indexes it. Each
  // is uploaded bottom row first, as lpfg hands them to glTexImage2D (v = 0: the image's bottom).
  void setTextures(const std::vector<runtime::Image>& textures);
  void setPalette(const RenderPalette& palette);

  // Draws into the bound framebuffer, viewport (0,0,camera.width,camera.height). Leaves the GL
  // state as it found it except for bindings, the viewport, the clear colour and enables.
  void draw(const runtime::ViewSettings& view, const runtime::CameraMatrices& camera,
            const RenderOptions& options = {});

  // Empty when all went well; else the first shader/GL problem met (the picture may be partial).
  const std::string& lastError() const { return error_; }
  const RenderStats& stats() const { return stats_; }

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::string error_;
  RenderStats stats_;
};

// Multi-view (manual §7.3): the views and their layout, shared with the 2D exporters.
using runtime::paneRects;
using runtime::ViewPane;

}  // namespace lcjit::viewer
