// The turtle (manual §5): executes predefined modules, moving a position and H/L/U frame, and —
// when given a Geometry — draws them as data with lpfg's rules (line styles, polygons, circles,
// spheres, generalized cylinders, surfaces, meshes, tropisms). Query modules (GetPos & co.)
// receive the state. Without a Geometry it only moves, which is what the query pass needs.
#pragma once
#include <array>
#include <map>
#include <string>
#include <vector>

#include "runtime/turtle/Geometry.h"
#include "runtime/ModuleString.h"
#include "runtime/files/Contours.h"
#include "runtime/files/ViewFile.h"
#include "runtime/include/lcjit/types.h"
#include "runtime/include/lcjit/vectors.h"

namespace lcjit::runtime {

struct ShapeLibrary;
struct PatchGrid;
class BSplineNet;
struct Image;
class Terrain;

// What the turtle draws with: the view file's settings and the shapes it names.
struct TurtleSetup {
  const ViewSettings* view = nullptr;     // null: lpfg's defaults
  V3f viewDirection{0, 0, -1};            // for screen-facing shapes (polygon lines, CircleFront)
  const ContourStore* contours = nullptr;  // .con/.cset files, ids from 1
  const ShapeLibrary* shapes = nullptr;    // surfaces, meshes of the view file
  Terrain* terrain = nullptr;                    // the view file's `terrain:` (§10.3), if loaded
  const std::vector<Image>* textures = nullptr;  // the view file's textures (the terrain grid's colours)
};

// A generalized-cylinder ring: where the last cylinder point was recorded (manual §5.7).
struct CylinderPoint {
  V3f position, heading, left, up;
  float scaleP = 1, scaleQ = 1;
  int contour = 0, contour2 = 0;
  float blend = 0;
};

constexpr int kMaxTropisms = 8;

struct TurtleState {
  V3f position{0, 0, 0};
  V3f heading{0, 1, 0};
  V3f left{-1, 0, 0};
  V3f up{0, 0, 1};
  int color = 1;
  float width = 1, widthUp = 1;  // ScaleContour(p, q) sets both; SetWidth(w) sets both to w
  // SetCoordinateSystem: point (x,y,z) maps to origin + scale·(−x·xAxis + y·yAxis + z·zAxis).
  V3f csOrigin{0, 0, 0}, csX{-1, 0, 0}, csY{0, 1, 0}, csZ{0, 0, 1};
  float csScale = 1;

  int contour = 0, contour2 = 0;  // 0: the default circle
  float blend = 0;
  int contourSides = 0;  // ContourSides module; 0: the view file's `contour sides`
  int texture = -1;
  // CurrentTexture was given (lpfg's "texture on"): surfaces then take `texture` (none if -1)
  // instead of the view file's.
  bool textureSet = false;
  float textureV = 0, textureVCoeff = 1;
  int uPrecision = 0, vPrecision = 0;  // 0: the surface's own

  bool cylinderOn = false, cylinderInherited = false;
  CylinderPoint cylinder;

  std::array<float, kMaxTropisms> elasticity{};
  V3f simpleTropism{0, 1, 0};
  float simpleElasticity = 0;

  // GroIMP's turtle state length (XL's L, LAdd, LMul; F0 draws it, M0 and MRel move by it) and
  // its local form, which the next shoot alone takes (Ll …): TurtleState.java's `length` and
  // `localLength`, 100 at first. lpfg has no such state; interpretation rules reach it through
  // lcjit_turtle_field (lcjit/abi.h).
  float stepLength = 100, localStepLength = 100;
};

// lpfg's tropism array (tropismarr.cpp): global, beside the branch stack (each TurtleState keeps
// its own copy of the elasticities, which EB puts back here). Query passes share one across a
// run (see Turtle::reset), as lpfg's global outlives its query turtles.
struct TropismField {
  bool initialised = false;
  std::array<float, kMaxTropisms> elasticity{};
  V3f direction{0, 0, 0};  // Σ T·I·cos A·E, kept up to date by adding changes
  V3f twist{0, 0, 0};      // Σ T·I·E of the torques, as the view file gives them
  float twistLength = 0;
};

// Appends lpfg's `-dtf` line(s) for one executed module (TurtleText.cpp), given where the turtle
// was and its width before the module, and where it is after.
void describeTurtleCommand(std::string& out, const char* rec, const V3f& positionBefore, float widthBefore,
                           const V3f& positionAfter);

class Turtle {
 public:
  // Starts a fresh interpretation. `out` may be null (query pass: move only). `tropisms`, if
  // given, is the tropism field to work on and keep: it is set from the view file only if not
  // yet initialised, so elasticities a pass leaves changed at the top level carry over to the
  // next pass sharing it (lpfg's global tropisms between its query passes). Without it the
  // field starts from the view file.
  void reset(const TurtleSetup& setup = {}, Geometry* out = nullptr, TropismField* tropisms = nullptr);
  // Executes one module record; query modules (GetPos...) get the state written into `rec`.
  void execute(char* rec);
  // `-dtf`: every executed command is also written to `text` in lpfg's turtle-text format.
  void setTranscript(std::string* text) { transcript_ = text; }
  // Ends the interpretation: open polygons are dropped, as in lpfg.
  void finish();
  const TurtleState& state() const { return state_; }
  TurtleState& state() { return state_; }

 private:
  // ---- motion (Turtle.cpp)
  void executeModule(char* rec);
  void rotate(V3f& a, V3f& b, float degrees);  // a' = cos·a + sin·b, b' = cos·b − sin·a
  void rotateAbout(V3f axis, float degrees);
  V3f transform(V3f p, V3f origin) const;
  V3f mapPoint(V3f p) const;
  V3f mapDirection(V3f d) const;
  void forward(float d, bool draw, bool polygonVertex);
  void lineAlong(V3f delta);
  void lineTo(V3f target);
  void line(V3f from, V3f to);
  static V3f scaled(const Tropism& tr);  // T·I
  void setElasticity(int i, float e);
  void restoreTropismField();
  void applyTropisms();
  void applySimpleTropism();
  void pushBranch();
  void popBranch();

  // ---- drawing (TurtleDrawing.cpp)
  void drawSegment(const TurtleState& before, float length);
  void ringVertices(const CylinderPoint& c, float v, std::vector<MeshVertex>& out);
  void drawFrustum(const CylinderPoint& a, const CylinderPoint& b, float length, bool inCylinder);
  void drawCap(const CylinderPoint& c);
  void drawCircle(float r, bool front, float inner);
  void drawSphere(float r);
  void drawRhombus(float a, float b);
  void drawTriangle(float a, float b);
  void endPolygon();
  void drawPatch(const V3tf (&points)[16], bool turtleFrame);
  // Adds a tessellated grid; positions/normals map through the turtle frame scaled by `scale`
  // (x along −L, y along H, z along U) unless `world` is set.
  void addGrid(const PatchGrid& grid, bool world, V3f scale, int texture);
  V3f inFrame(V3f p, V3f scale) const;  // P + x·(−L) + y·H + z·U, each coordinate scaled
  void drawSurface(int id, V3f scale);
  void drawMesh(int id, V3f scale);
  void drawBSurface(int id, float scale);
  void extendByNet(const BSplineNet& net, float scale);
  // DBSurfaceS/M: `points` are the record's rows of `maxColumns` V3tf, rows × columns used.
  void drawDynamicBSurface(const float* points, int maxRows, int maxColumns, int rows, int columns);
  void startCylinder();
  void endCylinder();
  CylinderPoint cylinderHere() const;
  const ContourSamples& ring(int contour, int divisions);
  int circleSides() const;
  int cylinderDivisions(int contour) const;
  void extend(V3f p) {
    if (out_) out_->extent.add(p);
  }
  // The bounding box lpfg's view-volume turtle (vvturtle.cpp) gives an F: both ends widened by
  // the line, a cylinder's by its half-widths times the extent of the last contour selected.
  void extendAlongF(const TurtleState& before);
  void selectContourExtent(int id1, int id2, float blend);
  // What that turtle keeps outside its branch stack (its `]` restores only the base turtle), so
  // it follows string order across branches: the contour's extent (±L, ±U factors of the
  // half-widths), whether a generalized cylinder is open, and the width of its last point.
  struct VolumeState {
    float leftPos = 1, leftNeg = 1, upPos = 1, upNeg = 1;
    bool inCylinder = false;
    float width = 1, widthUp = 1;
  };
  VolumeState volume_;
  MeshVertex vertex(V3f p, V3f n, float u = 0, float v = 0) const;

  // ---- the Terrain module (TurtleTerrain.cpp). lpfg draws the terrain by multiplying the GL
  // matrix by the turtle's frame and never restores it: whatever is drawn after it is drawn in
  // that frame too. A mark records where that starts; finish() moves what follows into it.
  struct FrameMark {
    size_t vertices, segments, discs, labels;
    V3f origin, x, y, z;
  };
  void drawTerrain(const CameraPosition& camera);
  void placeInFrames();
  std::vector<FrameMark> frames_;

  TurtleSetup setup_;
  ViewSettings defaults_;
  const ViewSettings* view_ = &defaults_;
  Geometry* out_ = nullptr;
  std::string* transcript_ = nullptr;
  TurtleState state_;
  std::vector<TurtleState> stack_;
  TropismField ownField_;
  TropismField* field_ = &ownField_;
  // Each view-file tropism's T·I, sin A and cos A (cos 0 for a torque), worked out by reset()
  // rather than at every F, with the same float operations.
  struct TropismTerms {
    V3f scaled{0, 0, 0};
    float sinA = 0, cosA = 1;
  };
  std::array<TropismTerms, kMaxTropisms> tropismTerms_{};

  struct PolygonVertex {
    V3f position, normal;
    int color;
  };
  bool polygonOn_ = false;
  std::vector<PolygonVertex> polygon_;
  V3tf userPatch_[16] = {};  // InitSurface/SurfacePoint/DrawSurface

  std::map<std::pair<int, int>, ContourSamples> rings_;  // by (contour, divisions)
  std::vector<MeshVertex> ringA_, ringB_;                // drawFrustum's scratch, reused
};

}  // namespace lcjit::runtime
