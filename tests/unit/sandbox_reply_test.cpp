// The sandboxed window run's reply (app/sandbox/SandboxReply.h): what the child encodes is what the
// window decodes, and a reply that is truncated, garbage or inconsistent is an error.
#include "app/sandbox/SandboxReply.h"

#include <gtest/gtest.h>

#include <limits>

using namespace lcjit;

namespace {

app::SandboxReply sample() {
  app::SandboxReply r;
  r.steps = 4;
  r.derivationLength = 6;
  r.message = "m.l:3: warning-ish text";
  r.unanswered = "GetMouseStatus/GetTabletStatus";
  r.animation = {2, 5, 3, 250, true, false, true};
  r.hasPicture = true;
  runtime::Geometry& g = r.main;
  g.useTexture(0);
  for (int i = 0; i < 3; ++i) g.addVertex({V3f(float(i), 1, 2), V3f(0, 0, 1), V2f(0.5f, float(i)), 7});
  g.addTriangle(0, 1, 2);
  g.addSegment({V3f(0, 0, 0), V3f(1, 2, 3), 3, 5});
  g.addDisc({V3f(1, 1, 1), 0.5f, 2, runtime::rgbColor(1, 2, 3)});
  g.addLabel({V3f(1, 0, 0), "a label", 9});  // a batch of the drawing order too
  g.camera = runtime::CameraPose{V3f(1, 2, 3), V3f(0, 0, 1), V3f(0, 1, 0)};
  g.extent.add(V3f(-1, -2, -3));
  g.extent.add(V3f(4, 5, 6));
  viewer::ViewPane pane;
  pane.geometry.addSegment({V3f(0, 0, 0), V3f(0, 1, 0), 1, 2});
  pane.rect = {0.5f, 0, 0.5f, 1};
  pane.viewId = 1;
  r.panes.push_back(pane);
  r.view.projection = runtime::Projection::Perspective;
  r.view.scale = 1.5f;
  r.view.frontDistance = 0.25f;
  r.view.views.push_back({1, V3f(0, 0, 1), std::nullopt, std::nullopt, 30.f, std::nullopt, 2.f});
  r.view.windows.push_back({"side", 0.5f, 0, 0.5f, 1});
  r.view.lights.emplace_back().kind = runtime::Light::Kind::Point;
  r.view.textures = {"bark.png"};
  r.view.winFont = "Courier";
  r.palette.materials = true;
  r.palette.color[3] = {0.1f, 0.2f, 0.3f, 1};
  r.palette.material[4].shininess = 17;
  r.textures.push_back({2, 1, 0, {1, 2, 3, 4, 5, 6, 7, 8}});
  return r;
}

TEST(SandboxReply, RoundTrips) {
  app::SandboxReply in = sample();
  auto out = app::decodeSandboxReply(app::encodeSandboxReply(in));
  ASSERT_TRUE(bool(out)) << llvm::toString(out.takeError());
  EXPECT_EQ(out->steps, 4);
  EXPECT_EQ(out->derivationLength, 6);
  EXPECT_FALSE(out->derived);
  EXPECT_EQ(out->message, in.message);
  EXPECT_EQ(out->unanswered, in.unanswered);
  EXPECT_EQ(out->animation.firstFrame, 2);
  EXPECT_EQ(out->animation.lastFrame, 5);
  EXPECT_EQ(out->animation.step, 3);
  EXPECT_EQ(out->animation.swapIntervalMs, 250);
  EXPECT_TRUE(out->animation.hcenter);
  EXPECT_FALSE(out->animation.scale);
  EXPECT_TRUE(out->animation.newView);
  ASSERT_TRUE(out->hasPicture);
  const runtime::Geometry& g = out->main;
  ASSERT_EQ(g.vertices.size(), 3u);
  EXPECT_EQ(g.vertices[2].position.x, 2);
  EXPECT_EQ(g.vertices[2].uv.y, 2);
  EXPECT_EQ(g.vertices[1].color, 7);
  EXPECT_EQ(g.indices, (std::vector<uint32_t>{0, 1, 2}));
  ASSERT_EQ(g.runs.size(), 1u);
  EXPECT_EQ(g.runs[0].texture, 0);
  ASSERT_EQ(g.segments.size(), 1u);
  EXPECT_EQ(g.segments[0].to.z, 3);
  EXPECT_EQ(g.segments[0].width, 3);
  ASSERT_EQ(g.discs.size(), 1u);
  EXPECT_EQ(g.discs[0].color, runtime::rgbColor(1, 2, 3));
  ASSERT_EQ(g.labels.size(), 1u);
  EXPECT_EQ(g.labels[0].text, "a label");
  ASSERT_TRUE(g.camera.has_value());
  EXPECT_EQ(g.camera->position.y, 2);
  EXPECT_EQ(g.extent.max.z, 6);
  EXPECT_EQ(g.order.size(), in.main.order.size());
  ASSERT_EQ(out->panes.size(), 1u);
  EXPECT_EQ(out->panes[0].viewId, 1);
  EXPECT_EQ(out->panes[0].rect.left, 0.5f);
  EXPECT_EQ(out->panes[0].geometry.segments.size(), 1u);
  EXPECT_EQ(out->view.projection, runtime::Projection::Perspective);
  EXPECT_EQ(out->view.scale, 1.5f);
  EXPECT_EQ(out->view.frontDistance, 0.25f);
  EXPECT_FALSE(out->view.backDistance.has_value());
  ASSERT_EQ(out->view.views.size(), 1u);
  EXPECT_EQ(out->view.views[0].fov, 30.f);
  EXPECT_FALSE(out->view.views[0].up.has_value());
  EXPECT_EQ(out->view.views[0].scale, 2.f);
  ASSERT_EQ(out->view.windows.size(), 1u);
  EXPECT_EQ(out->view.windows[0].name, "side");
  ASSERT_EQ(out->view.lights.size(), 1u);
  EXPECT_EQ(out->view.lights[0].kind, runtime::Light::Kind::Point);
  EXPECT_EQ(out->view.textures, in.view.textures);
  EXPECT_EQ(out->view.winFont, "Courier");
  EXPECT_TRUE(out->palette.materials);
  EXPECT_EQ(out->palette.color[3][1], 0.2f);
  EXPECT_EQ(out->palette.material[4].shininess, 17);
  ASSERT_EQ(out->textures.size(), 1u);
  EXPECT_EQ(out->textures[0].rgba, in.textures[0].rgba);
}

TEST(SandboxReply, WithoutAPicture) {
  app::SandboxReply in;
  in.message = "m.l:7: error: production A(n) crashed in step 3";
  in.derived = true;
  auto out = app::decodeSandboxReply(app::encodeSandboxReply(in));
  ASSERT_TRUE(bool(out)) << llvm::toString(out.takeError());
  EXPECT_FALSE(out->hasPicture);
  EXPECT_TRUE(out->derived);
  EXPECT_EQ(out->message, in.message);
}

std::string refusal(const std::string& bytes) {
  auto out = app::decodeSandboxReply(bytes);
  if (out) return "";
  return llvm::toString(out.takeError());
}

TEST(SandboxReply, RefusesEveryTruncation) {
  std::string bytes = app::encodeSandboxReply(sample());
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_NE(refusal(bytes.substr(0, n)), "") << "accepted " << n << " of " << bytes.size() << " bytes";
  EXPECT_NE(refusal(bytes + "x"), "");
}

TEST(SandboxReply, RefusesGarbageAndLies) {
  EXPECT_NE(refusal(""), "");
  EXPECT_NE(refusal(std::string(64, '\xff')), "");
  std::string bytes = app::encodeSandboxReply(sample());
  // A length past the reply's end (the vertex count, after magic, version, stamp, steps,
  // length, derived, message, picture flag, no textures... found by its value instead):
  std::string huge = bytes;
  uint64_t three = 3, lots = uint64_t(1) << 60;
  size_t at = huge.find(std::string(reinterpret_cast<const char*>(&three), 8));
  ASSERT_NE(at, std::string::npos);
  huge.replace(at, 8, std::string(reinterpret_cast<const char*>(&lots), 8));
  EXPECT_NE(refusal(huge).find("past the reply's end"), std::string::npos) << refusal(huge);

  // An index past the vertices, a run without its texture, another build's reply.
  app::SandboxReply r = sample();
  r.main.indices[1] = 99;
  EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("triangle index"), std::string::npos);
  r = sample();
  r.main.runs[0].texture = 5;
  EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("texture"), std::string::npos);
  r = sample();
  r.main.order.push_back({runtime::DrawBatch::Kind::Segments, 0, 9});
  EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("batch"), std::string::npos);
  r = sample();
  r.main.order.push_back({runtime::DrawBatch::Kind::Labels, 1, 1});  // one label only
  EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("batch"), std::string::npos);
  r = sample();
  r.animation.step = 0;  // the window would never reach a next frame
  EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("animation"), std::string::npos);
  // A view's rectangle is a fraction of the picture: no size, or past it, is no view to draw.
  for (float width : {-0.5f, 2.f, std::numeric_limits<float>::quiet_NaN()}) {
    r = sample();
    r.panes[0].rect.width = width;
    EXPECT_NE(refusal(app::encodeSandboxReply(r)).find("rectangle"), std::string::npos) << width;
  }
  std::string other = app::encodeSandboxReply(sample());
  other[4] = 9;  // the version
  EXPECT_NE(refusal(other).find("another build"), std::string::npos);
}

}  // namespace
