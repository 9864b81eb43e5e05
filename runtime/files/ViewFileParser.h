// The view-file reader's shared parts (ViewFile.cpp: the lines, the command table and the
// small commands; ViewFileCommands.cpp: lights, tropisms, surfaces, terrain, meshes, the shadow
// map, fonts; ViewFileViews.cpp: views, boxes and windows): the number and word readers as lpfg's
// sscanf and ReadFloats read, the commands, and the Parser's state. Internal to the reader.
#pragma once
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/files/ViewFile.h"

namespace lcjit::runtime::viewfile {

// The number and word readers (ViewFile.cpp).
bool isBlank(char c);
bool isAlpha(char c);
const char* skipBlanks(const char* p);
const char* skipNonBlanks(const char* p);
// sscanf("%f")-style: blanks, then the longest number prefix.
bool scanFloat(const char*& p, float& v);
// sscanf("%d")-style; base 0 is %i's (0x and 0 prefixes).
bool scanInt(const char*& p, int& v, int base = 10);
int scanFloats(const char*& p, float* out, int n);
// lpfg's Utils::ReadFloats: `n` blank-separated tokens, each read as a number prefix (the rest of
// a token such as "1,2" is skipped, so commas do not separate); leaves `p` on the next token.
bool tokenFloats(const char*& p, float* out, int n);
// After an item letter of light:/tropism:/mesh: (lpfg skips two characters: the letter and ':').
const char* afterItemLetter(const char* p);
// The next item label of view:/shadow map: lines: two letters in a row (so exponents such as
// 1.2e-009 are passed over), as lpfg looks for it.
const char* nextLabel(const char* p);
std::string trimmed(std::string_view s);

enum class Cmd {
  Preproc, LineStyle, ZBuffer, RenderMode, Light, Surface, Texture, FrontDist, BackDist, Tropism,
  Torque, Projection, Scale, ScaleFactor, MinZoom, MaxZoom, Rotation, Font, WinFont, STropism,
  Window, WindowBorder, ContourSides, GenerateOnViewChange, View, BSurface, Box,
  CorrectedRotation, BackfaceCulling, Terrain, ConcavePolygons, Gradient, Function, Gallery,
  ShadowMap, PSLinecap, StationaryLights, AutoNormals, TaperedCylinders, Antialiasing, Mesh,
  AnimatedMesh, CappedCylinders, WireframeLineWidth
};

class Parser {
 public:
  Parser(ViewSettings& vs, std::vector<ViewFileWarning>& warnings, std::string file)
      : vs_(vs), warnings_(warnings), file_(std::move(file)) {}

  void run(std::string_view text);

 private:
  ViewSettings& vs_;
  std::vector<ViewFileWarning>& warnings_;
  std::string file_;
  int line_ = 0;
  std::string text_;  // the current line without leading and trailing blanks
  size_t indent_ = 0;  // how many leading blanks were removed (for columns)
  int lpfgWindows_ = 0;  // lpfg's window list length, for its view id check (see checkViewId)
  int lastViewId_ = -1;  // the view: on the previous command line, for item continuation lines
  int commands_ = 0, unrecognized_ = 0;  // lines read as commands, and lines that are not
  size_t firstUnrecognized_ = 0;          // the first one's warning
  std::set<std::string> surfaceLines_, meshLines_;

  // ---- lines (ViewFile.cpp)
  void warn(const char* at, const std::string& message);
  void lineMarker(const char* p);
  void handleLine(std::string_view raw);

  // ---- small value readers and the commands of one line (ViewFile.cpp)
  bool onOff(const char* arg, bool& flag, const char* what);
  bool oneFloat(const char* arg, float& v, const char* what);
  bool oneInt(const char* arg, int& v, const char* what);
  void dispatch(Cmd cmd, const char* arg);

  // ---- lights, tropisms, external files, shadow map, fonts (ViewFileCommands.cpp)
  void readLight(const char* arg);
  void readTropism(const char* arg, bool torque);
  // `file scale sdiv tdiv texture` as lpfg's sscanf("%s %f %d %d %d") reads a surface: how many
  // values read (1 to 5; 3 is an error: divisions come in pairs) and those values. `what` names
  // the command in warnings; false after a warning.
  struct SurfaceArgs {
    std::string file;
    int count = 0;
    float scale = 1;
    int sdiv = 0, tdiv = 0, texture = -1;
  };
  bool readSurfaceArgs(const char* at, const char* what, SurfaceArgs& a);
  void readSurface(const char* arg);
  void readBSurface(const char* arg);
  void readTerrain(const char* arg);
  void readMesh(const char* arg);
  void readShadowMap(const char* arg);
  void readXFont(const char* arg);
  void readWinFont(const char* arg);

  // ---- views, boxes, windows (ViewFileViews.cpp)
  bool checkViewId(long id, const char* at);
  ViewDefinition& viewFor(int id);
  void readView(const char* arg);
  static int viewItem(const char* p);
  void applyViewItems(ViewDefinition& view, const char* p);
  static constexpr const char* kViewItems[] = {"dir:", "pan:", "up:", "fov:", "shift:", "scale:"};
  void readBox(const char* arg);
  void readWindow(const char* arg);
};

}  // namespace lcjit::runtime::viewfile
