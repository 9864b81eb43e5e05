// The interactive window (viewer/Window.h) on an X server: Xvfb, started by the test when DISPLAY
// is unset. Input is injected through the functions GLFW's callbacks call; every check looks at
// the picture (pixels, extents, centroids) or at what the menu called.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cctype>
#include <filesystem>
#include <thread>
#include <tuple>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "runtime/turtle/Camera.h"
#include "viewer/Window.h"

using namespace lcjit;
using namespace lcjit::runtime;
using namespace lcjit::viewer;

namespace {

// ---------------------------------------------------------------------------------------------
// An X display: the caller's, or our own Xvfb (-displayfd picks a free display number).

pid_t xvfbPid = 0;
std::string displayProblem;

class XDisplay : public ::testing::Environment {
 public:
  void SetUp() override {
    if (const char* d = std::getenv("DISPLAY"); d && *d) return;
    int fds[2];
    if (pipe(fds) != 0) {
      displayProblem = "no DISPLAY and pipe() failed";
      return;
    }
    pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      prctl(PR_SET_PDEATHSIG, SIGTERM);  // no stray server if the test dies
      std::string fd = std::to_string(fds[1]);
      int devnull = open("/dev/null", O_WRONLY);
      if (devnull >= 0) dup2(devnull, 2);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
             "-noreset", (char*)nullptr);
      _exit(127);
    }
    close(fds[1]);
    if (pid < 0) {
      close(fds[0]);
      displayProblem = "no DISPLAY and fork() failed";
      return;
    }
    std::string number;
    char c;
    while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (number.empty()) {
      int status = 0;
      waitpid(pid, &status, 0);
      displayProblem = "no DISPLAY and Xvfb could not start (is the xvfb package installed?)";
      return;
    }
    xvfbPid = pid;
    setenv("DISPLAY", (":" + number).c_str(), 1);
  }
  void TearDown() override {
    if (xvfbPid > 0) {
      kill(xvfbPid, SIGTERM);
      int status = 0;
      waitpid(xvfbPid, &status, 0);
    }
  }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new XDisplay);

// ---------------------------------------------------------------------------------------------
// The scene: a red square (colour 2) in the z = 0 plane, a green bar (colour 3) in front of it
// along x, and a blue segment (colour 4). Background black (colour 0).

const std::array<uint8_t, 3> kRed{255, 0, 0}, kGreen{0, 255, 0}, kBlue{0, 0, 255};

void quad(Geometry& g, V3f a, V3f b, V3f c, V3f d, int color) {
  V3f n(0, 0, 0);  // unlit
  uint32_t i0 = g.addVertex({a, n, {0, 0}, color}), i1 = g.addVertex({b, n, {0, 0}, color});
  uint32_t i2 = g.addVertex({c, n, {0, 0}, color}), i3 = g.addVertex({d, n, {0, 0}, color});
  g.addTriangle(i0, i1, i2);
  g.addTriangle(i0, i2, i3);
}

Geometry scene(V3f offset = V3f(0, 0, 0)) {
  Geometry g;
  quad(g, V3f(-1, -1, 0) + offset, V3f(1, -1, 0) + offset, V3f(1, 1, 0) + offset, V3f(-1, 1, 0) + offset, 2);
  quad(g, V3f(-0.8f, -0.1f, 0.5f) + offset, V3f(0.8f, -0.1f, 0.5f) + offset, V3f(0.8f, 0.1f, 0.5f) + offset,
       V3f(-0.8f, 0.1f, 0.5f) + offset, 3);
  g.addSegment({V3f(-1, -1.2f, 0) + offset, V3f(1, -1.2f, 0) + offset, 3, 4});
  return g;
}

RenderPalette palette() {
  RenderPalette p;
  p.color[2] = {1, 0, 0, 1};
  p.color[3] = {0, 1, 0, 1};
  p.color[4] = {0, 0, 1, 1};
  return p;
}

// `scale: 0.5`: the model fills half the window, so zooming in keeps it inside.
ViewSettings zview() {
  ViewSettings v;
  v.zBuffer = true;
  v.scale = 0.5f;
  return v;
}

struct Blob {
  int count = 0;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  double cx = 0, cy = 0;
  int width() const { return count ? x1 - x0 + 1 : 0; }
  int height() const { return count ? y1 - y0 + 1 : 0; }
};

Blob find(const Image& img, std::array<uint8_t, 3> color) {
  Blob b;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      auto p = img.pixel(x, y);
      if (std::abs(p[0] - color[0]) < 30 && std::abs(p[1] - color[1]) < 30 && std::abs(p[2] - color[2]) < 30) {
        ++b.count;
        b.x0 = std::min(b.x0, x);
        b.y0 = std::min(b.y0, y);
        b.x1 = std::max(b.x1, x);
        b.y1 = std::max(b.y1, y);
        b.cx += x;
        b.cy += y;
      }
    }
  if (b.count) {
    b.cx /= b.count;
    b.cy /= b.count;
  }
  return b;
}

int differingPixels(const Image& a, const Image& b) {
  int n = 0;
  for (size_t i = 0; i + 3 < a.rgba.size(); i += 4)
    if (std::memcmp(&a.rgba[i], &b.rgba[i], 3) != 0) ++n;
  return n;
}

struct Counters {
  int newModel = 0, newLsystem = 0, newRun = 0, newView = 0, newRendering = 0, exit = 0, saveAs = 0;
  std::string savedPath;
};

MenuActions allActions(Counters& c) {
  MenuActions a;
  a.newModel = [&c] { ++c.newModel; };
  a.newLsystem = [&c] { ++c.newLsystem; };
  a.newRun = [&c] { ++c.newRun; };
  a.newView = [&c] { ++c.newView; };
  a.newRendering = [&c] { ++c.newRendering; };
  a.exit = [&c] { ++c.exit; };
  a.saveAs = [&c](const std::string& p) {
    ++c.saveAs;
    c.savedPath = p;
  };
  return a;
}

class WindowTest : public ::testing::Test {
 protected:
  static constexpr int kSize = 400;
  std::unique_ptr<Window> w;
  MenuActions none;

  void SetUp() override {
    if (!displayProblem.empty()) GTEST_SKIP() << displayProblem;
    WindowOptions o;
    o.width = o.height = kSize;
    o.title = "lcjit window test";
    o.vsync = false;
    auto e = Window::create(o);
    if (!e) GTEST_SKIP() << "no window: " << llvm::toString(e.takeError());
    w = std::move(*e);
    w->setScene(scene(), zview(), palette(), {});
    ASSERT_TRUE(w->frame(none));
  }

  Image grab() {
    auto e = w->grabImage();
    if (!e) {
      ADD_FAILURE() << llvm::toString(e.takeError());
      return {};
    }
    return std::move(*e);
  }

  // A drag: press at (x, y) with mods, move in `steps` steps to (x + dx, y + dy), release.
  void drag(int button, int mods, double x, double y, double dx, double dy, const MenuActions& a, int steps = 10) {
    w->injectCursor(x, y);
    w->injectMouseButton(button, GLFW_PRESS, mods);
    for (int i = 1; i <= steps; ++i) {
      w->injectCursor(x + dx * i / steps, y + dy * i / steps);
      if (i % 3 == 0) w->frame(a);  // frames in between, as in real use
    }
    w->injectMouseButton(button, GLFW_RELEASE, mods);
    w->frame(a);
  }

  void click(double x, double y, const MenuActions& a, int button = GLFW_MOUSE_BUTTON_LEFT) {
    w->injectCursor(x, y);
    w->frame(a);
    w->injectMouseButton(button, GLFW_PRESS, 0);
    w->frame(a);
    w->injectMouseButton(button, GLFW_RELEASE, 0);
    w->frame(a);
  }

  // Opens the main menu with a right click at (x, y) and clicks the item `label`.
  void chooseMenuItem(const std::string& label, const MenuActions& a, double x = 60, double y = 60) {
    click(x, y, a, GLFW_MOUSE_BUTTON_RIGHT);
    w->frame(a);
    ASSERT_TRUE(w->menuOpen());
    auto r = w->menuItemRect(label);
    ASSERT_TRUE(r.has_value()) << label;
    EXPECT_GE((*r)[0], x - 1);  // the menu opens at the pointer
    EXPECT_GE((*r)[1], y - 1);
    click(((*r)[0] + (*r)[2]) / 2, ((*r)[1] + (*r)[3]) / 2, a);
  }
};

// ---------------------------------------------------------------------------------------------

TEST_F(WindowTest, ShowsTheSceneFramedLikeLpfg) {
  EXPECT_EQ(w->framebufferSize(), std::make_pair(kSize, kSize));
  ViewSettings v;  // lpfg's default scale, 0.9
  v.zBuffer = true;
  w->setScene(scene(), v, palette(), {});
  Image img = grab();
  ASSERT_EQ(img.width, kSize);
  Blob red = find(img, kRed), green = find(img, kGreen), blue = find(img, kBlue);
  // The framed box is 2 × 2.2 (the segment at y = -1.2): its height fills 90% of the window.
  EXPECT_NEAR(red.height(), kSize * 0.9 * 2 / 2.2, 2);
  EXPECT_NEAR(red.width(), kSize * 0.9 * 2 / 2.2, 2);
  EXPECT_NEAR(red.cx, kSize / 2.0, 1);
  EXPECT_NEAR(red.cy, kSize / 2.0 - kSize * 0.9 * 0.1 / 2.2, 1);
  EXPECT_GT(green.count, 1000);
  EXPECT_GT(blue.count, 100);
  EXPECT_TRUE(w->renderer().lastError().empty()) << w->renderer().lastError();
  auto p = img.pixel(2, 2);
  EXPECT_EQ(p[0] + p[1] + p[2], 0);  // background colour 0
}

TEST_F(WindowTest, SaveImageWritesWhatTheWindowShows) {
  auto dir = std::filesystem::temp_directory_path() / ("lcjit_window_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"a.png", "a.jpg", "a.bmp"}) {
    std::string path = (dir / name).string();
    ASSERT_FALSE(bool(w->saveImage(path))) << path;
    EXPECT_GT(std::filesystem::file_size(path), 1000u) << path;
  }
  llvm::Error bad = w->saveImage((dir / "a.txt").string());
  EXPECT_TRUE(bool(bad));
  llvm::consumeError(std::move(bad));
  // The saved picture is the window's: the menu is not in it.
  Image plain = grab();
  click(180, 180, none, GLFW_MOUSE_BUTTON_RIGHT);
  ASSERT_TRUE(w->menuOpen());
  EXPECT_EQ(differingPixels(plain, grab()), 0);
  std::filesystem::remove_all(dir);
}

TEST_F(WindowTest, LeftDragRotatesAboutTheBoxCentre) {
  Image before = grab();
  Blob red0 = find(before, kRed);
  // 300 pixels to the right: −0.2°/pixel about up = 60°: the square's width halves.
  drag(GLFW_MOUSE_BUTTON_LEFT, 0, 50, 200, 300, 0, none);
  Image after = grab();
  if (std::getenv("LCJIT_WINDOW_TEST_DUMP")) {
    (void)writeImage(before, "/tmp/rot_before.png");
    (void)writeImage(after, "/tmp/rot_after.png");
  }
  EXPECT_GT(differingPixels(before, after), 10000);
  Blob red1 = find(after, kRed);
  EXPECT_NEAR(double(red1.width()) / red0.width(), 0.5, 0.04);
  EXPECT_NEAR(red1.height(), red0.height(), 2);
  // The green bar, 0.5 in front, moves right: the eye went round to the left.
  EXPECT_NEAR(find(after, kGreen).cx - find(before, kGreen).cx, 0.25 * std::sin(glm::radians(60.0)) * kSize / 4.4, 2);
  // Rotation about the box centre: it stays in the middle of the window.
  glm::vec3 c = projectToWindow(w->camera(), V3f(0, -0.1f, 0.25f));
  EXPECT_NEAR(c.x, kSize / 2.0, 0.5);
  EXPECT_NEAR(c.y, kSize / 2.0, 0.5);
  // Vertical drag upward: about the screen's horizontal axis; the height shrinks.
  w->resetView();
  drag(GLFW_MOUSE_BUTTON_LEFT, 0, 200, 350, 0, -300, none);
  Blob red2 = find(grab(), kRed);
  EXPECT_NEAR(double(red2.height()) / red0.height(), 0.5, 0.04);
  EXPECT_NEAR(red2.width(), red0.width(), 2);
}

TEST_F(WindowTest, RotationCentreIsTheBoxCentreOffOrigin) {
  w->setScene(scene(V3f(5, 7, -3)), zview(), palette(), {});
  drag(GLFW_MOUSE_BUTTON_LEFT, 0, 100, 100, 137, 91, none);
  glm::vec3 c = projectToWindow(w->camera(), V3f(5, 7 - 0.1f, -3 + 0.25f));
  EXPECT_NEAR(c.x, kSize / 2.0, 0.5);
  EXPECT_NEAR(c.y, kSize / 2.0, 0.5);
  Blob red = find(grab(), kRed);
  EXPECT_NEAR(red.cx, kSize / 2.0, 25);
}

TEST_F(WindowTest, WheelZooms) {
  Blob red0 = find(grab(), kRed);
  w->injectCursor(200, 200);
  for (int i = 0; i < 3; ++i) w->injectScroll(0, 1);  // 3 notches up: ×1.01^30
  w->frame(none);
  Blob red1 = find(grab(), kRed);
  EXPECT_NEAR(double(red1.width()) / red0.width(), std::pow(1.01, 30), 0.02);
  EXPECT_NEAR(red1.cx, red0.cx, 1.5);  // about the centre
  for (int i = 0; i < 6; ++i) w->injectScroll(0, -1);
  w->frame(none);
  Blob red2 = find(grab(), kRed);
  EXPECT_NEAR(double(red2.width()) / red0.width(), std::pow(1.01, -30), 0.02);
}

TEST_F(WindowTest, CtrlOrAltLeftAndMiddleDragZoom) {
  Blob red0 = find(grab(), kRed);
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_CONTROL, 200, 300, 0, -50, none);  // up: zoom in
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), std::pow(1.01, 50), 0.02);
  w->resetView();
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_ALT, 200, 300, 0, -50, none);
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), std::pow(1.01, 50), 0.02);
  w->resetView();
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_SUPER, 200, 100, 0, 40, none);  // Command; down: out
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), std::pow(1.01, -40), 0.02);
  w->resetView();
  drag(GLFW_MOUSE_BUTTON_MIDDLE, 0, 200, 300, 0, -50, none);
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), std::pow(1.01, 50), 0.02);
}

TEST_F(WindowTest, ZoomStaysWithinTheViewFilesLimits) {
  ViewSettings v = zview();
  v.minZoom = 1.0f;  // lpfg's zoom limits bound its internal scale, 1/`scale:` = 2 here
  v.maxZoom = 4.0f;
  w->setScene(scene(), v, palette(), {});
  w->frame(none);
  Blob red0 = find(grab(), kRed);
  for (int i = 0; i < 100; ++i) w->injectScroll(0, 1);
  w->frame(none);
  const double in = 2.0 / 1.0;
  EXPECT_NEAR(w->adjustment().zoom, in, 1e-4);
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), in, 0.02);
  // Back out by the same amount the limit allowed: no "stored" zoom beyond the limit.
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_CONTROL, 200, 100, 0, 10, none);
  EXPECT_NEAR(w->adjustment().zoom, in / std::pow(1.01, 10), 1e-3);
  for (int i = 0; i < 300; ++i) w->injectScroll(0, -1);
  w->frame(none);
  const double out = 2.0 / 4.0;
  EXPECT_NEAR(w->adjustment().zoom, out, 1e-4);
  EXPECT_NEAR(double(find(grab(), kRed).width()) / red0.width(), out, 0.02);
}

TEST_F(WindowTest, ShiftLeftDragPans) {
  Blob red0 = find(grab(), kRed);
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_SHIFT, 100, 100, 50, 30, none);
  Blob red1 = find(grab(), kRed);
  EXPECT_NEAR(red1.cx - red0.cx, 50, 1.5);  // the model follows the pointer
  EXPECT_NEAR(red1.cy - red0.cy, 30, 1.5);
  EXPECT_NEAR(red1.width(), red0.width(), 1);
  // Panning does not change the orientation; a rotation afterwards is about the panned point.
  EXPECT_EQ(w->adjustment().rotation, glm::mat4(1));
}

TEST_F(WindowTest, ShiftMiddleDragRolls) {
  Blob green0 = find(grab(), kGreen);
  ASSERT_GT(green0.width(), 3 * green0.height());
  drag(GLFW_MOUSE_BUTTON_MIDDLE, GLFW_MOD_SHIFT, 100, 200, 90, 0, none);  // 90°
  Blob green1 = find(grab(), kGreen);
  EXPECT_NEAR(green1.height(), green0.width(), 3);
  EXPECT_NEAR(green1.width(), green0.height(), 3);
  // The blue segment, below the square, is now on a side of it.
  Blob blue = find(grab(), kBlue);
  EXPECT_NEAR(std::abs(blue.cx - kSize / 2.0), 1.1 * kSize / 4.4, 3);
  EXPECT_LT(std::abs(blue.cy - kSize / 2.0), 40);
}

TEST_F(WindowTest, CtrlMiddleDragChangesTheFrustumInPerspective) {
  // Parallel projection: nothing.
  Image before = grab();
  drag(GLFW_MOUSE_BUTTON_MIDDLE, GLFW_MOD_CONTROL, 200, 300, 0, -60, none);
  EXPECT_EQ(differingPixels(before, grab()), 0);
  EXPECT_EQ(w->frustumFactor(), 1.0f);
  // Perspective: moving up brings the eye closer (near distance ×1.01^-60); the nearer green
  // bar grows relative to the red square behind it.
  ViewSettings v = zview();
  v.projection = Projection::Perspective;
  w->setScene(scene(), v, palette(), {});
  w->frame(none);
  Blob red0 = find(grab(), kRed), green0 = find(grab(), kGreen);
  float z0 = w->camera().zShift;
  drag(GLFW_MOUSE_BUTTON_MIDDLE, GLFW_MOD_CONTROL, 200, 300, 0, -60, none);
  EXPECT_NEAR(w->frustumFactor(), std::pow(1.01, -60), 1e-3);
  EXPECT_LT(w->camera().zShift, z0);
  Blob red1 = find(grab(), kRed), green1 = find(grab(), kGreen);
  EXPECT_GT(red1.width(), red0.width() + 10);
  EXPECT_GT(double(green1.width()) / red1.width(), double(green0.width()) / red0.width() + 0.005);
}

TEST_F(WindowTest, SetSceneKeepsTheViewResetViewRestoresIt) {
  Image start = grab();
  drag(GLFW_MOUSE_BUTTON_LEFT, 0, 100, 200, 120, 40, none);
  Image rotated = grab();
  w->setScene(scene(), zview(), palette(), {});  // e.g. New run: the same picture again
  w->frame(none);
  EXPECT_EQ(differingPixels(rotated, grab()), 0);
  w->resetView();
  w->frame(none);
  EXPECT_EQ(differingPixels(start, grab()), 0);
}

TEST_F(WindowTest, RightClickMenuCallsTheChosenItemOnce) {
  Counters c;
  MenuActions a = allActions(c);
  Image before = grab();
  chooseMenuItem("New view", a);
  EXPECT_EQ(c.newView, 1);
  EXPECT_EQ(c.newModel + c.newLsystem + c.newRun + c.newRendering + c.exit + c.saveAs, 0);
  EXPECT_FALSE(w->menuOpen());
  for (int i = 0; i < 3; ++i) w->frame(a);
  EXPECT_EQ(c.newView, 1);
  // Clicking in the menu did not rotate the view.
  EXPECT_EQ(differingPixels(before, grab()), 0);
  chooseMenuItem("New model", a, 150, 120);
  chooseMenuItem("New rendering", a, 10, 10);
  EXPECT_EQ(c.newModel, 1);
  EXPECT_EQ(c.newRendering, 1);
  EXPECT_EQ(c.newView, 1);
}

TEST_F(WindowTest, DisabledItemsCallNothing) {
  Counters c;
  MenuActions a = allActions(c);
  a.newRun = nullptr;  // greyed out
  chooseMenuItem("New run", a);
  EXPECT_EQ(c.newModel + c.newLsystem + c.newRun + c.newView + c.newRendering + c.exit + c.saveAs, 0);
  // With no actions at all, every item is inert; Save needs a name.
  w->frame(none);
  click(5, 5, none);  // close the menu if still open
  chooseMenuItem("New view", none);
  chooseMenuItem("Save", none);
  EXPECT_FALSE(w->saveDialogOpen());
  EXPECT_EQ(c.newView, 0);
}

TEST_F(WindowTest, SaveAndSaveAs) {
  auto dir = std::filesystem::temp_directory_path() / ("lcjit_window_s" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  Counters c;
  MenuActions a = allActions(c);
  a.saveName = (dir / "model.png").string();
  chooseMenuItem("Save", a);
  EXPECT_TRUE(std::filesystem::exists(dir / "model.png"));
  EXPECT_EQ(c.saveAs, 0);
  // Save as…: the dialog, prefilled with the name; an image name is written by the window…
  a.saveName = (dir / "other.bmp").string();
  chooseMenuItem("Save as...", a);
  w->frame(a);
  w->frame(a);  // the dialog sizes itself on its first frame
  ASSERT_TRUE(w->saveDialogOpen());
  auto ok = w->menuItemRect("Save##dialog");
  ASSERT_TRUE(ok.has_value());
  click(((*ok)[0] + (*ok)[2]) / 2, ((*ok)[1] + (*ok)[3]) / 2, a);
  EXPECT_TRUE(std::filesystem::exists(dir / "other.bmp"));
  EXPECT_TRUE(w->lastSaveError().empty()) << w->lastSaveError();
  EXPECT_EQ(c.saveAs, 0);
  // …any other through MenuActions::saveAs; typed text and Enter.
  a.saveName = "";
  chooseMenuItem("Save as...", a);
  w->frame(a);
  w->frame(a);
  ASSERT_TRUE(w->saveDialogOpen());
  for (char ch : std::string("tree.obj")) w->injectChar(ch);
  w->frame(a);
  w->injectKey(GLFW_KEY_ENTER, GLFW_PRESS, 0);
  w->frame(a);
  w->injectKey(GLFW_KEY_ENTER, GLFW_RELEASE, 0);
  w->frame(a);
  EXPECT_EQ(c.saveAs, 1);
  EXPECT_EQ(c.savedPath, "tree.obj");
  EXPECT_FALSE(w->saveDialogOpen());
  std::filesystem::remove_all(dir);
}

// A slow frame (a loaded machine) sees several input events at once: Ctrl+A, typing and Enter
// in the Save as dialog all come between two frames, and a right click's press and release
// between two others. None is lost: Ctrl+A still selects (Ctrl is not taken as released before
// A), the text replaces the prefilled name, Enter saves, and the right click opens the menu.
TEST_F(WindowTest, InputBetweenTwoFramesIsTakenInOrder) {
  Counters c;
  MenuActions a = allActions(c);
  a.saveName = "model.png";
  chooseMenuItem("Save as...", a);
  w->frame(a);
  w->frame(a);
  ASSERT_TRUE(w->saveDialogOpen());
  auto field = w->menuItemRect("##file");
  ASSERT_TRUE(field.has_value());
  click(((*field)[0] + (*field)[2]) / 2, ((*field)[1] + (*field)[3]) / 2, a);  // cursor at the end
  w->injectKey(GLFW_KEY_LEFT_CONTROL, GLFW_PRESS, GLFW_MOD_CONTROL);
  w->injectKey(GLFW_KEY_A, GLFW_PRESS, GLFW_MOD_CONTROL);
  w->injectKey(GLFW_KEY_A, GLFW_RELEASE, GLFW_MOD_CONTROL);
  w->injectKey(GLFW_KEY_LEFT_CONTROL, GLFW_RELEASE, 0);
  for (char ch : std::string("tree.obj")) {
    w->injectKey(std::toupper(ch), GLFW_PRESS, 0);
    w->injectChar(ch);
    w->injectKey(std::toupper(ch), GLFW_RELEASE, 0);
  }
  w->injectKey(GLFW_KEY_ENTER, GLFW_PRESS, 0);
  w->injectKey(GLFW_KEY_ENTER, GLFW_RELEASE, 0);
  for (int i = 0; i < 60 && c.saveAs == 0; ++i) w->frame(a);
  EXPECT_EQ(c.saveAs, 1);
  EXPECT_EQ(c.savedPath, "tree.obj");
  EXPECT_FALSE(w->saveDialogOpen());

  w->injectCursor(60, 60);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, 0);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_RIGHT, GLFW_RELEASE, 0);
  for (int i = 0; i < 4; ++i) w->frame(a);
  EXPECT_TRUE(w->menuOpen());
}

// Opens a submenu of the main menu (a click on its label) and clicks its item `label`.
TEST_F(WindowTest, RefreshModeMenuSetsTheMode) {
  std::vector<bool> set;
  MenuActions a;
  a.setRefreshMode = [&set](bool monitoring) { set.push_back(monitoring); };
  auto pick = [&](const std::string& item) {
    click(60, 60, a, GLFW_MOUSE_BUTTON_RIGHT);
    w->frame(a);
    auto sub = w->menuItemRect("Refresh mode");
    ASSERT_TRUE(sub.has_value());
    click(((*sub)[0] + (*sub)[2]) / 2, ((*sub)[1] + (*sub)[3]) / 2, a);
    w->frame(a);
    auto r = w->menuItemRect(item);
    ASSERT_TRUE(r.has_value()) << item;
    click(((*r)[0] + (*r)[2]) / 2, ((*r)[1] + (*r)[3]) / 2, a);
  };
  pick("Triggered/Continuous");
  a.monitoring = true;
  pick("Explicit");
  EXPECT_EQ(set, (std::vector<bool>{true, false}));
  EXPECT_FALSE(w->menuOpen());
}

TEST_F(WindowTest, PanelsOpenFromTheMenuAndReportEdits) {
  std::vector<std::pair<size_t, float>> changes;
  std::vector<size_t> presses;
  MenuActions a;
  Panel p;
  p.title = "Parameters";
  PanelControl steps;
  steps.label = "STEPS";
  steps.value = 3, steps.min = 0, steps.max = 10, steps.step = 1;
  PanelControl on, off;
  on.kind = off.kind = PanelControl::Kind::Toggle;
  on.label = "On", off.label = "Off";
  on.group = off.group = 0;
  on.value = 1;
  p.controls = {steps, on, off};
  p.buttons = {"Save values"};
  p.changed = [&changes](size_t i, float v) { changes.emplace_back(i, v); };
  p.pressed = [&presses](size_t b) { presses.push_back(b); };
  a.panels = {p};
  EXPECT_FALSE(w->panelOpen("Parameters"));
  // Panels > Parameters opens it.
  click(60, 60, a, GLFW_MOUSE_BUTTON_RIGHT);
  w->frame(a);
  auto sub = w->menuItemRect("Panels");
  ASSERT_TRUE(sub.has_value());
  click(((*sub)[0] + (*sub)[2]) / 2, ((*sub)[1] + (*sub)[3]) / 2, a);
  w->frame(a);
  auto item = w->menuItemRect("Parameters");
  ASSERT_TRUE(item.has_value());
  click(((*item)[0] + (*item)[2]) / 2, ((*item)[1] + (*item)[3]) / 2, a);
  w->frame(a);
  ASSERT_TRUE(w->panelOpen("Parameters"));
  w->frame(a);
  auto slider = w->panelItemRect("Parameters", "STEPS");
  ASSERT_TRUE(slider.has_value());
  // A click at the slider's right end gives its maximum, snapped to whole steps.
  Image before = grab();
  click((*slider)[2] - 2, ((*slider)[1] + (*slider)[3]) / 2, a);
  ASSERT_FALSE(changes.empty());
  EXPECT_EQ(changes.back().first, 0u);
  EXPECT_FLOAT_EQ(changes.back().second, 10.0f);
  // Clicking in the panel did not turn the view.
  w->showPanel("Parameters", false);
  w->frame(a);
  EXPECT_EQ(differingPixels(before, grab()), 0);
  w->showPanel("Parameters", true);
  w->frame(a);
  changes.clear();
  auto off2 = w->panelItemRect("Parameters", "Off");
  ASSERT_TRUE(off2.has_value());
  click((*off2)[0] + 6, ((*off2)[1] + (*off2)[3]) / 2, a);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].first, 2u);  // the group's other button is turned on
  EXPECT_FLOAT_EQ(changes[0].second, 1.0f);
  auto save = w->panelItemRect("Parameters", "Save values");
  ASSERT_TRUE(save.has_value());
  click(((*save)[0] + (*save)[2]) / 2, ((*save)[1] + (*save)[3]) / 2, a);
  EXPECT_EQ(presses, std::vector<size_t>{0});
}

TEST_F(WindowTest, ExitEndsTheLoop) {
  Counters c;
  MenuActions a = allActions(c);
  click(60, 60, a, GLFW_MOUSE_BUTTON_RIGHT);
  w->frame(a);
  auto r = w->menuItemRect("Exit");
  ASSERT_TRUE(r.has_value());
  w->injectCursor(((*r)[0] + (*r)[2]) / 2, ((*r)[1] + (*r)[3]) / 2);
  EXPECT_TRUE(w->frame(a));
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  EXPECT_TRUE(w->frame(a));
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  EXPECT_FALSE(w->frame(a));
  EXPECT_EQ(c.exit, 1);
}

TEST(WindowOptionsTest, SizeRelativeSizeAndPosition) {
  if (!displayProblem.empty()) GTEST_SKIP() << displayProblem;
  WindowOptions o;
  o.relW = 0.25f;  // of Xvfb's 1280×1024 (or the caller's screen)
  o.relH = 0.5f;
  o.borderless = true;
  auto e = Window::create(o);
  if (!e) GTEST_SKIP() << "no window: " << llvm::toString(e.takeError());
  GLFWmonitor* m = glfwGetPrimaryMonitor();
  ASSERT_NE(m, nullptr);
  const GLFWvidmode* mode = glfwGetVideoMode(m);
  EXPECT_EQ((*e)->windowSize(), std::make_pair(int(std::lround(0.25 * mode->width)), int(std::lround(0.5 * mode->height))));
  EXPECT_TRUE((*e)->frame({}));  // no scene yet: draws the background
}

// Rotating a million segments: frames per second at 800×800 (LCJIT_WINDOW_BENCH=<frames> to run).
TEST(WindowBenchmark, RotateAMillionSegments) {
  if (!std::getenv("LCJIT_WINDOW_BENCH")) GTEST_SKIP() << "set LCJIT_WINDOW_BENCH=<frames>";
  if (!displayProblem.empty()) GTEST_SKIP() << displayProblem;
  WindowOptions o;
  o.vsync = false;
  if (const char* size = std::getenv("LCJIT_WINDOW_BENCH_SIZE")) o.width = o.height = std::atoi(size);
  auto e = Window::create(o);
  if (!e) GTEST_SKIP() << "no window: " << llvm::toString(e.takeError());
  Window& w = **e;
  Geometry g;
  // A random walk of a million unit-ish segments in a cube, widths 1, colours 1..8.
  uint32_t s = 12345;
  auto rnd = [&s] {
    s = s * 1664525u + 1013904223u;
    return float(s >> 8) / float(1 << 24) - 0.5f;
  };
  V3f p(0, 0, 0);
  for (int i = 0; i < 1000000; ++i) {
    V3f q(p.x + rnd() * 0.05f, p.y + rnd() * 0.05f, p.z + rnd() * 0.05f);
    q = V3f(std::clamp(q.x, -1.f, 1.f), std::clamp(q.y, -1.f, 1.f), std::clamp(q.z, -1.f, 1.f));
    g.addSegment({p, q, 1, 1 + i % 8});
    p = q;
  }
  RenderPalette pal;
  for (int i = 1; i <= 8; ++i) pal.color[i] = {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1) * 0.5f + 0.5f, 1};
  ViewSettings v;
  v.zBuffer = std::getenv("LCJIT_WINDOW_BENCH_Z") != nullptr;
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  auto t = Clock::now();
  w.setScene(g, v, pal, {});
  glFinish();
  std::printf("[bench] setScene (upload): %.3f s\n", since(t));
  MenuActions none;
  t = Clock::now();
  w.frame(none);
  glFinish();
  std::printf("[bench] first frame: %.3f s\n", since(t));
  w.injectCursor(100, 400);
  w.injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  const int frames = std::max(1, std::atoi(std::getenv("LCJIT_WINDOW_BENCH")));
  auto t0 = Clock::now();
  for (int i = 1; i <= frames; ++i) {
    t = Clock::now();
    w.injectCursor(100 + 5 * i, 400 + 2 * i);
    w.frame(none);
    if (i <= 3) std::printf("[bench] frame %d: %.3f s\n", i, since(t));
  }
  glFinish();
  double sec = since(t0);
  w.injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  std::printf("[bench] %s: %d frames of 1M segments at %dx%d while rotating: %.1f fps (%.1f ms/frame), %zu draw calls\n",
              w.glRenderer().c_str(), frames, w.framebufferSize().first, w.framebufferSize().second, frames / sec,
              1000 * sec / frames, w.renderer().stats().drawCalls);
  EXPECT_TRUE(w.renderer().lastError().empty());
}

}  // namespace

TEST_F(WindowTest, UserMenuOpensWithTwoModifiersAndReportsTheCode) {
  int chosen = -1, calls = 0;
  MenuActions a;
  a.userMenu = {{"Grow", 7}, {"Prune", 9}};
  a.userChoice = [&](int code) { chosen = code, ++calls; };
  w->injectCursor(50, 50);
  w->frame(a);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT);
  w->frame(a);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_RIGHT, GLFW_RELEASE, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT);
  w->frame(a);
  ASSERT_TRUE(w->userMenuOpen());
  EXPECT_FALSE(w->menuOpen());  // not the main menu
  auto r = w->menuItemRect("Prune");
  ASSERT_TRUE(r.has_value());
  click(((*r)[0] + (*r)[2]) / 2, ((*r)[1] + (*r)[3]) / 2, a);
  EXPECT_EQ(chosen, 9);
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(w->userMenuOpen());
}

// A broken edit's diagnostics stay over the picture (top left) until a good reload clears them,
// and do not take the mouse: a drag that starts on them still rotates the view.
TEST_F(WindowTest, MessageOverlayShowsUntilClearedAndLetsTheMouseThrough) {
  MenuActions none;
  w->frame(none);
  EXPECT_FALSE(w->messageRect().has_value());
  w->setMessage("model.l:3:1: error: unknown module 'Oops'\n    3 | axiom: Oops;\n      |        ^");
  w->frame(none);
  w->frame(none);  // ImGui sizes an auto-resizing window from the frame before
  auto r = w->messageRect();
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR((*r)[0], 8, 1);
  EXPECT_NEAR((*r)[1], 8, 1);
  EXPECT_GT((*r)[3] - (*r)[1], 3 * 12);  // three lines of text
  EXPECT_GT((*r)[2] - (*r)[0], 200);
  float before = w->adjustment().rotation[0][0];
  w->injectCursor(20, 20);
  w->frame(none);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  w->frame(none);
  w->injectCursor(120, 20);
  w->frame(none);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  w->frame(none);
  EXPECT_NE(w->adjustment().rotation[0][0], before);
  w->setMessage("");
  w->frame(none);
  EXPECT_FALSE(w->messageRect().has_value());
}

// Animate menu (§1.2.3): Start recording reaches the model's side, which then saves every frame.
TEST_F(WindowTest, StartRecordingIsInTheAnimateMenu) {
  int recordings = 0;
  MenuActions a;
  a.animating = true;
  a.startRecording = [&] { ++recordings; };
  w->frame(a);
  chooseMenuItem("Start recording", a);
  EXPECT_EQ(recordings, 1);
  EXPECT_FALSE(w->menuOpen());
}

TEST_F(WindowTest, PointerReportsTheMouseInsertionCombinationsOnly) {
  MenuActions none;
  w->frame(none);
  w->injectCursor(kSize / 2.0, kSize / 2.0);
  w->frame(none);
  // A plain left click (rotation) is not a GetMouseStatus click.
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  Window::Pointer p = w->takePointer();
  EXPECT_FALSE(p.pushed);
  // Shift+Ctrl: pushed and down, then released; latched until taken.
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, GLFW_MOD_SHIFT | GLFW_MOD_CONTROL);
  p = w->takePointer();
  EXPECT_TRUE(p.pushed);
  EXPECT_TRUE(p.down);
  EXPECT_FALSE(w->takePointer().pushed);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, GLFW_MOD_SHIFT | GLFW_MOD_CONTROL);
  p = w->takePointer();
  EXPECT_TRUE(p.released);
  EXPECT_FALSE(p.down);
  // The key 2 counts as a combination too.
  w->injectKey(GLFW_KEY_2, GLFW_PRESS, 0);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  EXPECT_TRUE(w->takePointer().pushed);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  w->injectKey(GLFW_KEY_2, GLFW_RELEASE, 0);
  // The window centre looks at the framed box's centre: the middle point lies on that axis,
  // between the front and rear points.
  runtime::Bounds b = scene().framingBounds();
  EXPECT_NEAR(p.middle[0], b.center().x, 0.02);
  EXPECT_NEAR(p.middle[1], b.center().y, 0.02);
  EXPECT_GT(p.front[2], p.middle[2]);
  EXPECT_GT(p.middle[2], p.rear[2]);
}

TEST_F(WindowTest, MultiViewPanesFillTheirWindowsWithABorder) {
  // Two views side by side (window: left 0 0 0.5 1, right 0.5 0 0.5 1), a 4-pixel white border:
  // the left pane shows a red square, the right one a blue one, each framed in its own half.
  auto square = [](int color) {
    Geometry g;
    quad(g, V3f(-1, -1, 0), V3f(1, -1, 0), V3f(1, 1, 0), V3f(-1, 1, 0), color);
    return g;
  };
  std::vector<ViewPane> panes(2);
  panes[0].geometry = square(2);
  panes[0].rect = {0, 0, 0.5f, 1};
  panes[1].geometry = square(4);
  panes[1].rect = {0.5f, 0, 0.5f, 1};
  panes[1].viewId = 1;
  ViewSettings v;
  v.windowBorderSize = 4;
  v.windowBorderColor = {1, 1, 1};
  w->setViews(panes, v, palette(), {});
  Image img = grab();
  Blob red = find(img, kRed), blue = find(img, kBlue), white = find(img, {255, 255, 255});
  ASSERT_GT(red.count, 0);
  ASSERT_GT(blue.count, 0);
  EXPECT_LT(red.x1, kSize / 2);
  EXPECT_GT(blue.x0, kSize / 2);
  // Each square fills 90% of its pane's width (a pane of kSize/2 - 2 pixels), centred in it.
  EXPECT_NEAR(red.width(), (kSize / 2 - 2) * 0.9, 3);
  EXPECT_NEAR(red.cx, (kSize / 2 - 2) / 2.0, 2);
  EXPECT_NEAR(blue.cx, kSize / 2 + 2 + (kSize / 2 - 2) / 2.0, 2);
  // The border: a white column 4 pixels wide down the middle.
  EXPECT_EQ(white.width(), 4);
  EXPECT_EQ(white.height(), kSize);
  // The mouse works on the pane it presses in (lpfg): panning in the right pane moves only the
  // blue square.
  MenuActions none;
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_SHIFT, 300, 200, 0, 40, none);
  Image panned = grab();
  EXPECT_NEAR(find(panned, kRed).cy, red.cy, 0.5);
  EXPECT_NEAR(find(panned, kBlue).cy, blue.cy + 40, 2);
  // …and then in the left one, only the red square; the blue one keeps its pan.
  drag(GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_SHIFT, 100, 200, 0, -30, none);
  Image both = grab();
  EXPECT_NEAR(find(both, kRed).cy, red.cy - 30, 2);
  EXPECT_NEAR(find(both, kBlue).cy, blue.cy + 40, 2);
  // Back to one view.
  w->setScene(scene(), zview(), palette(), {});
  EXPECT_EQ(find(grab(), {255, 255, 255}).count, 0);
}

TEST_F(WindowTest, DraggingAVeryLargeModelDrawsAPreviewAndReleaseTheWholePicture) {
  // 250 000 dots on a grid: more than the preview limit, so while the left button drags the view
  // a decimated copy is drawn (fewer lit pixels); on release the whole picture is back.
  Geometry g;
  const int n = 500;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      V3f p(-1 + 2.f * i / n, -1 + 2.f * j / n, 0);
      g.addSegment({p, p + V3f(0.002f, 0, 0), 1, 2});
    }
  w->setScene(g, ViewSettings(), palette(), {});
  auto lit = [](const Image& img) { return find(img, kRed).count; };
  MenuActions none;
  int full = lit(grab());
  w->injectCursor(100, 100);
  w->frame(none);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  w->frame(none);
  int dragging = lit(grab());
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  w->frame(none);
  int released = lit(grab());
  EXPECT_GT(full, 0);
  EXPECT_LT(dragging, full * 0.8);
  EXPECT_EQ(released, full);
}

TEST_F(WindowTest, AnimationFramesKeepTheFramingUnlessAskedToRefit) {
  // A growing model: the second frame is the scene twice as large. Keep (lpfg's animation
  // default) shows it twice as large; Refit frames it like the first; HCenter keeps the size.
  auto grown = [] {
    Geometry g = scene();
    for (auto& v : g.vertices) v.position = v.position * 2.f;
    for (auto& s : g.segments) s.from = s.from * 2.f, s.to = s.to * 2.f;
    return g;
  };
  w->setScene(scene(), zview(), palette(), {});
  int first = find(grab(), kRed).width();
  w->setScene(grown(), zview(), palette(), {}, Window::Framing::Keep);
  EXPECT_NEAR(find(grab(), kRed).width(), 2 * first, 3);
  w->setScene(scene(), zview(), palette(), {});
  w->setScene(grown(), zview(), palette(), {}, Window::Framing::HCenter);
  EXPECT_NEAR(find(grab(), kRed).width(), 2 * first, 3);
  w->setScene(grown(), zview(), palette(), {}, Window::Framing::Refit);
  EXPECT_NEAR(find(grab(), kRed).width(), first, 2);
}

// The editors' controls (app/window/Editors): a function's point dragged (its ends held at x = 0 and 1),
// a colour picked from a grid and changed by its sliders; each edit reported after the frame.
TEST_F(WindowTest, CurveAndColourControlsReportEdits) {
  std::vector<std::tuple<size_t, size_t, std::array<float, 4>>> edits;
  std::vector<std::pair<size_t, float>> changes;
  MenuActions a;
  Panel f;
  f.title = "Function grow";
  PanelControl curve;
  curve.kind = PanelControl::Kind::Curve;
  curve.label = "grow";
  curve.function = true;
  curve.points = {{0, 0}, {0.3f, 0.2f}, {0.7f, 0.8f}, {1, 1}};
  curve.curve = {{0, 0}, {0.5f, 0.5f}, {1, 1}};
  f.controls = {curve};
  f.edited = [&edits](size_t c, size_t i, std::array<float, 4> v) { edits.emplace_back(c, i, v); };
  Panel colours;
  colours.title = "Colormap";
  PanelControl grid;
  grid.kind = PanelControl::Kind::Swatches;
  grid.label = "colours";
  grid.value = 1;
  for (int i = 0; i < 16; ++i) grid.colors.push_back({i / 15.0f, 0.5f, 0.2f, 1});
  PanelControl one;
  one.kind = PanelControl::Kind::Color;
  one.label = "Colour 1";
  one.colors = {{0.5f, 0.5f, 0.5f, 1}};
  colours.controls = {grid, one};
  colours.changed = [&changes](size_t i, float v) { changes.emplace_back(i, v); };
  colours.edited = f.edited;
  a.panels = {f, colours};
  Image before = grab();
  w->showPanel("Function grow", true);
  w->frame(a);
  w->frame(a);
  // Point 1 dragged 40 pixels up: it rises, and keeps its x.
  auto pt = w->panelItemRect("Function grow", "grow#1");
  ASSERT_TRUE(pt.has_value());
  const double x = ((*pt)[0] + (*pt)[2]) / 2, y = ((*pt)[1] + (*pt)[3]) / 2;
  w->injectCursor(x, y);
  w->frame(a);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  w->frame(a);
  EXPECT_TRUE(edits.empty());  // a press alone moves nothing
  for (int i = 1; i <= 4; ++i) {
    w->injectCursor(x, y - 10 * i);
    w->frame(a);
  }
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  w->frame(a);
  ASSERT_FALSE(edits.empty());
  auto [control, point, v] = edits.back();
  EXPECT_EQ(control, 0u);
  EXPECT_EQ(point, 1u);
  EXPECT_FLOAT_EQ(v[0], 0.3f);  // moved by the pointer's motion: straight up keeps x exactly
  EXPECT_GT(v[1], 0.2f + 0.1f);
  // The first point dragged right and up: its x stays 0.
  edits.clear();
  auto first = w->panelItemRect("Function grow", "grow#0");
  ASSERT_TRUE(first.has_value());
  const double fx = ((*first)[0] + (*first)[2]) / 2, fy = ((*first)[1] + (*first)[3]) / 2;
  w->injectCursor(fx, fy);
  w->frame(a);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  w->frame(a);
  w->injectCursor(fx + 30, fy - 20);
  w->frame(a);
  w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  w->frame(a);
  ASSERT_FALSE(edits.empty());
  EXPECT_EQ(std::get<1>(edits.back()), 0u);
  EXPECT_EQ(std::get<2>(edits.back())[0], 0.0f);
  EXPECT_GT(std::get<2>(edits.back())[1], 0.0f);
  // Ctrl+click between points 1 and 2 adds a point there (funcedit's Add); Shift+Ctrl+click on
  // point 2 removes it, on the last point nothing (a function keeps its ends).
  std::vector<std::tuple<size_t, size_t, std::array<float, 2>>> added;
  std::vector<std::pair<size_t, size_t>> removed;
  a.panels[0].added = [&added](size_t c, size_t at, std::array<float, 2> q) { added.emplace_back(c, at, q); };
  a.panels[0].removed = [&removed](size_t c, size_t i) { removed.emplace_back(c, i); };
  auto p1 = w->panelItemRect("Function grow", "grow#1"), p2 = w->panelItemRect("Function grow", "grow#2");
  auto p3 = w->panelItemRect("Function grow", "grow#3");
  ASSERT_TRUE(p1 && p2 && p3);
  auto clickWith = [&](double cx, double cy, int mods) {
    w->injectCursor(cx, cy);
    w->frame(a);
    w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, mods);
    w->frame(a);
    w->injectMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, mods);
    w->frame(a);
  };
  const double midX = ((*p1)[0] + (*p1)[2] + (*p2)[0] + (*p2)[2]) / 4, midY = ((*p1)[1] + (*p1)[3]) / 2 + 30;
  clickWith(midX, midY, GLFW_MOD_CONTROL);
  ASSERT_EQ(added.size(), 1u);
  EXPECT_EQ(std::get<1>(added[0]), 2u);  // before the old point 2, in x order
  EXPECT_GT(std::get<2>(added[0])[0], 0.3f);
  EXPECT_LT(std::get<2>(added[0])[0], 0.7f);
  clickWith(((*p2)[0] + (*p2)[2]) / 2, ((*p2)[1] + (*p2)[3]) / 2, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT);
  clickWith(((*p3)[0] + (*p3)[2]) / 2, ((*p3)[1] + (*p3)[3]) / 2, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT);
  EXPECT_EQ(removed, (std::vector<std::pair<size_t, size_t>>{{0, 2}}));
  EXPECT_EQ(added.size(), 1u);            // Shift+Ctrl+clicks add nothing
  EXPECT_EQ(w->takePointer().insert, 0);  // nor ask the model for MouseIns (§7.4's Shift+Ctrl)
  // The drags in the panel did not turn the view.
  w->showPanel("Function grow", false);
  w->frame(a);
  EXPECT_EQ(differingPixels(before, grab()), 0);
  // Colours: a click on swatch 3 selects it; a click at the red slider's right end makes red 255.
  w->showPanel("Colormap", true);
  w->frame(a);
  w->frame(a);
  auto swatch = w->panelItemRect("Colormap", "colours#3");
  ASSERT_TRUE(swatch.has_value());
  click(((*swatch)[0] + (*swatch)[2]) / 2, ((*swatch)[1] + (*swatch)[3]) / 2, a);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].first, 0u);
  EXPECT_FLOAT_EQ(changes[0].second, 3.0f);
  edits.clear();
  auto red = w->panelItemRect("Colormap", "Colour 1 R");
  ASSERT_TRUE(red.has_value());
  click((*red)[2] - 2, ((*red)[1] + (*red)[3]) / 2, a);
  ASSERT_FALSE(edits.empty());
  EXPECT_EQ(std::get<0>(edits.back()), 1u);
  EXPECT_FLOAT_EQ(std::get<2>(edits.back())[0], 1.0f);
  EXPECT_FLOAT_EQ(std::get<2>(edits.back())[1], 0.5f);  // green as it was
}
