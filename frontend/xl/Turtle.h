// GroIMP's turtle commands (de.grogra.turtle) as lcjit's turtle draws them. GroIMP's turtle frame
// is left = local x, up = local y, head = local z, starting as the world's axes in a z-up world;
// lcjit's (lpfg's) is H = +y, L = −x, U = +z. Shown with GroIMP's z as lcjit's y (GroIMP's front
// view: x to the right, z up), GroIMP's frame is lcjit's turned half round its head: the same H,
// L and U reversed. So a rotation about GroIMP's up or left is lcjit's about U or L the other way
// round, and one about the head is the same: RU(a) = Right(a) (`-`), RL(a) = Up(a) (`^`),
// RH(a) = RollR(a) (`/`), with lcjit's default `corrected rotation: on`. docs/xl.md gives the
// GroIMP sources of each fact (the rotation matrices of URotation, RL and RH, F's and M's
// constructors, TurtleState's defaults).
#pragma once
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

namespace lcjit::frontend::xl {

struct TurtleCommand {
  std::string_view name;  // GroIMP's class, as XL writes it
  int arity;              // the arguments of this form
  // The module that stands for it in lcjit's string: lcjit's own F, or one the translation
  // declares (`declared` types); GroIMP's F(l, d) is lcjit's F_d, lcjit's F having one parameter.
  std::string_view module;
  std::string_view declared;  // "float, float"; empty: lcjit's own module, or one without parameters
  bool own;                   // lcjit's predefined module: nothing to declare, nothing to interpret
  // What lcjit's turtle does for it (lpfg's modules; $1, $2 its arguments); empty: nothing.
  std::string_view drawn;
  // Instead of `produce drawn;`, the statements of its interpretation rule ($1, $2… likewise).
  std::string_view body = {};
  // How far it moves the turtle along its head ($1 …); empty: not at all. A module extending it
  // with a shader of its own draws it in a branch, then moves this far.
  std::string_view advance = {};
  // A solid drawn of polygons: statements (nproduce) that draw it where the turtle is and leave
  // the turtle as it was; after them the turtle moves `advance` (in place of drawn and body).
  std::string_view solid = {};
};

// GroIMP's Box(l, w, h) (Box.draw: drawBox(w/2, h/2, l)): x from −w/2 to w/2 along its left, y
// from −h/2 to h/2 along its up, z from 0 to l along its head; its six faces lpfg's polygons,
// each in a branch, its corners reached by moves in the world's axes (lcjit/xl.h's
// __xl_local_move: GroIMP's x, y, z are lcjit's −L, −U, H). Corner k has x's sign from bit 0,
// y's from bit 1, z = l for bit 2.
inline constexpr std::string_view kBoxFaces =
    "static const int __xl_faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}}; "
    "float __xl_c[8][3]; "
    "for (int k = 0; k < 8; ++k) __xl_local_move((k & 1 ? 0.5f : -0.5f) * ($2), (k & 2 ? 0.5f : -0.5f) * ($3), "
    "(k & 4) ? ($1) : 0.0f, __xl_c[k]); "
    "for (int f = 0; f < 6; ++f) { nproduce SB SP; float __xl_at[3] = {0, 0, 0}; "
    "for (int j = 0; j < 4; ++j) { const float* c = __xl_c[__xl_faces[f][j]]; "
    "nproduce MoveRel3f(V3f(c[0] - __xl_at[0], c[1] - __xl_at[1], c[2] - __xl_at[2])) PP; "
    "for (int i = 0; i < 3; ++i) __xl_at[i] = c[i]; } nproduce EP EB; } ";

// GroIMP's F(l, d, c): a cylinder l long of diameter d and colour c for itself alone, −1 standing
// for the turtle state's (F's fields `diameter` and `color`); colour c is lcjit's index c + 2
// (runtime/files/Palette.h, Palette::ega()).
inline constexpr std::string_view kOwnCylinder =
    "if ($2 < 0 && $3 < 0) produce F($1); nproduce SB; if ($2 >= 0) nproduce SetWidth($2); "
    "if ($3 >= 0) nproduce SetColor((int)($3) + 2); produce F($1) EB f($1);";

// GroIMP's turtle state length and its local form (TurtleState's `length`, `localLength`), which
// lcjit's turtle keeps for XL (lcjit_turtle_field, lcjit/abi.h): a shoot (F0, FMul, FAdd) takes
// the local one, and the local one is the length again after it.
#define XL_STATE_LENGTH "lcjit_turtle_field(__lc_TurtleStepLength)"
#define XL_SHOOT                                                                                   \
  "float __xl_l = lcjit_turtle_field(__lc_TurtleLocalStepLength); "                              \
  "lcjit_set_turtle_field(__lc_TurtleLocalStepLength, " XL_STATE_LENGTH "); "
#define XL_SET_LENGTH(value)                                                                        \
  "float __xl_v = " value "; lcjit_set_turtle_field(__lc_TurtleStepLength, __xl_v); "           \
  "lcjit_set_turtle_field(__lc_TurtleLocalStepLength, __xl_v); produce ;"
#define XL_SET_LOCAL_LENGTH(value) "lcjit_set_turtle_field(__lc_TurtleLocalStepLength, " value "); produce ;"

inline constexpr TurtleCommand kTurtleCommands[] = {
    // F(l): a cylinder of length l along the head, then the turtle at its end (Shoot, TurtleStep).
    {"F", 1, "F", "", true, "", {}, "$1"},
    // F(l, d): of diameter d for itself alone (F's field `diameter`; −1 is the state's).
    {"F", 2, "F_d", "float, float", false, "", "if ($2 < 0) produce F($1); else produce SB SetWidth($2) F($1) EB f($1);", "$1"},
    // F(l, d, c): and of colour c (kOwnCylinder).
    {"F", 3, "F_dc", "float, float, int", false, "", kOwnCylinder, "$1"},
    // F0: a cylinder of the turtle state's local length (TurtleState: 100 while nothing sets it),
    // FMul(x) and FAdd(x) of that times or plus x; after a shoot the local values are the
    // state's again (Shoot.execute). XL_STATE_LENGTH and XL_SHOOT.
    {"F0", 0, "F0", "", false, "", XL_SHOOT "produce F(__xl_l);"},
    {"FMul", 1, "FMul", "float", false, "", XL_SHOOT "produce F(__xl_l * $1);"},
    {"FAdd", 1, "FAdd", "float", false, "", XL_SHOOT "produce F(__xl_l + $1);"},
    // M(l): moves l along the head without drawing; M0 by the state's length (not the local one),
    // MMul(x) by that times x, MAdd(x) plus x, MRel(x) by it times x − 1: from the end of the
    // shoot before, to x of its length from its base (the quick reference's `L(10) [MRel(0.7) …]`).
    {"M", 1, "M", "float", false, "f($1)"},
    {"M0", 0, "M0", "", false, "f(" XL_STATE_LENGTH ")"},
    {"MMul", 1, "MMul", "float", false, "f(" XL_STATE_LENGTH " * $1)"},
    {"MAdd", 1, "MAdd", "float", false, "f(" XL_STATE_LENGTH " + $1)"},
    {"MRel", 1, "MRel", "float", false, "f(" XL_STATE_LENGTH " * ($1 - 1))"},
    // L(x): the state's length and its local form become x, LAdd(x) the length plus x, LMul(x)
    // times x; Ll, LlAdd and LlMul set the local form alone; L0 puts back the first, 100.
    {"L", 1, "L", "float", false, "", XL_SET_LENGTH("$1")},
    {"LAdd", 1, "LAdd", "float", false, "", XL_SET_LENGTH(XL_STATE_LENGTH " + $1")},
    {"LMul", 1, "LMul", "float", false, "", XL_SET_LENGTH(XL_STATE_LENGTH " * $1")},
    {"L0", 0, "L0", "", false, "", XL_SET_LENGTH("100")},
    {"Ll", 1, "Ll", "float", false, "", XL_SET_LOCAL_LENGTH("$1")},
    {"LlAdd", 1, "LlAdd", "float", false, "", XL_SET_LOCAL_LENGTH(XL_STATE_LENGTH " + $1")},
    {"LlMul", 1, "LlMul", "float", false, "", XL_SET_LOCAL_LENGTH(XL_STATE_LENGTH " * $1")},
    // D(x): the state's diameter, lcjit's line width (SetWidth); DAdd and DMul from the width.
    {"D", 1, "D", "float", false, "SetWidth($1)"},
    {"DAdd", 1, "DAdd", "float", false, "SetWidth(lcjit_turtle_field(__lc_TurtleWidth) + $1)"},
    {"DMul", 1, "DMul", "float", false, "SetWidth(lcjit_turtle_field(__lc_TurtleWidth) * $1)"},
    // P(c): the state's colour, one of GroIMP's 16 (lcjit's c + 2, as F's).
    {"P", 1, "P", "int", false, "", "if ($1 >= 0 && $1 <= 15) produce SetColor($1 + 2); else produce ;"},
    {"RU", 1, "RU", "float", false, "Right($1)"},
    {"RL", 1, "RL", "float", false, "Up($1)"},
    {"RH", 1, "RH", "float", false, "RollR($1)"},
    // RV(g): gravitropism, the head turned towards the world's down by g (lcjit/xl.h's
    // __xl_gravitropism, GRotation's rotation).
    {"RV", 1, "RV", "float", false, "",
     "float __xl_hu[6]; if (__xl_gravitropism($1, __xl_hu)) produce SetHead(__xl_hu[0], __xl_hu[1], __xl_hu[2], "
     "__xl_hu[3], __xl_hu[4], __xl_hu[5]); else produce ;"},
    // AdjustLU: turned about the head so that the up is as near the world's up as it can be, the
    // left horizontal (AdjustLU.java). lpfg's RollToVert turns lpfg's U up, which is GroIMP's
    // up reversed: then half a turn about the head.
    {"AdjustLU", 0, "AdjustLU", "", false, "RollToVert RollR(180)"},
    // Translate(x, y, z): moves by (x, y, z) in the world's axes without drawing (the quick
    // reference: "im globalen Koordinatensystem … relativ zur bisherigen Position"); GroIMP's
    // (x, y, z) is lcjit's (x, z, −y).
    {"Translate", 3, "Translate", "float, float, float", false, "MoveRel3f(V3f($1, $3, -$2))"},
    // Sphere(r): a sphere of radius r where the turtle is, which it does not move: lcjit's own.
    {"Sphere", 1, "Sphere", "", true, "Sphere($1)"},
    // GroIMP's solids on an axis (imp3d.objects.Axis): each stands on the turtle's position along
    // its head, and what follows it starts at its top (Axis.postTransform: the length along the
    // local z), as after an F. lcjit draws Box as the cuboid it is (kBoxFaces); the round ones as
    // a line of their diameter (its width): Cylinder(l, r) and Cone(l, r) 2r wide, Frustum(l,
    // r1, r2) r1 + r2; in the turtle's colour.
    {"Cylinder", 2, "Cylinder", "float, float", false, "SB SetWidth(2 * $2) F($1) EB f($1)", {}, "$1"},
    {"Cone", 2, "Cone", "float, float", false, "SB SetWidth(2 * $2) F($1) EB f($1)", {}, "$1"},
    {"Frustum", 3, "Frustum", "float, float, float", false, "SB SetWidth($2 + $3) F($1) EB f($1)", {}, "$1"},
    {"Box", 3, "Box", "float, float, float", false, "", {}, "$1", kBoxFaces},
    // Parallelogram(l, w): a flat rectangle l long along the head and w wide along GroIMP's left
    // (lcjit's L), centred on the head (Parallelogram's axis (w/2, 0, 0), from −axis to +axis, its
    // area 2 |axis| l): lpfg's polygon of its four corners, drawn round from the corner at +L.
    {"Parallelogram", 2, "Parallelogram", "float, float", false,
     "SB Left(90) f(($2) / 2) SP PP Right(90) f($1) Right(90) f($2) Right(90) f($1) EP EB f($1)", {}, "$1"},
    // Null: a node that does nothing to the turtle; Null(x, y, z) translated by (x, y, z) in its
    // parent's frame (Null's transform), which moves the turtle there (lcjit/xl.h's
    // __xl_local_move), as a module extending Null does after setTransform(x, y, z).
    {"Null", 0, "Null", "", false, ""},
    {"Null", 3, "Null_t", "float, float, float", false, "",
     "if ($1 == 0 && $2 == 0 && $3 == 0) produce ; float __xl_d[3]; __xl_local_move($1, $2, $3, __xl_d); "
     "produce MoveRel3f(V3f(__xl_d[0], __xl_d[1], __xl_d[2]));"},
};
#undef XL_STATE_LENGTH
#undef XL_SHOOT
#undef XL_SET_LENGTH
#undef XL_SET_LOCAL_LENGTH

// GroIMP's command `name` with `arity` arguments; null when lcjit has none.
inline const TurtleCommand* turtleNamed(std::string_view name, int arity) {
  for (const TurtleCommand& c : kTurtleCommands)
    if (c.name == name && c.arity == arity) return &c;
  return nullptr;
}
inline bool isTurtleCommand(std::string_view name) {
  for (const TurtleCommand& c : kTurtleCommands)
    if (c.name == name) return true;
  return false;
}

// The names of GroIMP's turtle commands lcjit has, for messages: "F, F0, …, Sphere and Null".
inline std::string turtleNames() {
  std::string names;
  constexpr size_t n = std::size(kTurtleCommands);
  for (size_t i = 0; i < n; ++i) {
    bool again = false;
    for (size_t j = 0; j < i; ++j) again = again || kTurtleCommands[j].name == kTurtleCommands[i].name;
    if (again) continue;
    if (!names.empty()) names += i + 1 == n ? " and " : ", ";
    names += kTurtleCommands[i].name;
  }
  return names;
}

// The fields of GroIMP's turtle commands, which a module extending one inherits, in the order
// of the command's constructor's arguments, with their values when it has none: F() and M() are
// 1 long, F's diameter and colour −1 (the turtle state's), RU(), RL() and RH() turn by 0 (F.java,
// M.java, the rotations' constructors); Sphere() has radius 1 (Sphere.java), Cylinder() and Cone()
// length and radius 1 (`this (1, 1)`), Frustum() radii 1 and 0.5 (`this (1, 1, 0.5f)`), a Box and
// a Parallelogram are 1 each way (Axis's `length = 1`, Box's `width = 1`, `height = 1`); the
// solids' `shader` is −1, the turtle's colour (ShadedNull's shader, as lcjit keeps it: a colour).
struct Field {
  std::string_view command, name, type, fallback;
};
inline constexpr Field kFields[] = {
    {"F", "length", "float", "1"}, {"F", "diameter", "float", "-1"}, {"F", "color", "int", "-1"},
    {"M", "length", "float", "1"},
    {"RU", "angle", "float", "0"}, {"RL", "angle", "float", "0"}, {"RH", "angle", "float", "0"},
    {"Sphere", "radius", "float", "1"}, {"Sphere", "shader", "int", "-1"},
    {"Cylinder", "length", "float", "1"}, {"Cylinder", "radius", "float", "1"}, {"Cylinder", "shader", "int", "-1"},
    {"Cone", "length", "float", "1"}, {"Cone", "radius", "float", "1"}, {"Cone", "shader", "int", "-1"},
    {"Frustum", "length", "float", "1"}, {"Frustum", "baseRadius", "float", "1"},
    {"Frustum", "topRadius", "float", "0.5"}, {"Frustum", "shader", "int", "-1"},
    {"Box", "length", "float", "1"}, {"Box", "width", "float", "1"}, {"Box", "height", "float", "1"},
    {"Box", "shader", "int", "-1"},
    {"Parallelogram", "length", "float", "1"}, {"Parallelogram", "width", "float", "1"},
    {"Parallelogram", "shader", "int", "-1"},
    // Null's translation (Null(x, y, z), setTransform(x, y, z)): 0 each, named so that no
    // field of the user's is hidden (XL names them only through those two).
    {"Null", "__xl_tx", "float", "0"}, {"Null", "__xl_ty", "float", "0"}, {"Null", "__xl_tz", "float", "0"}};

// The fields of turtle command `command`, in kFields' order (its constructor's arguments').
inline std::vector<const Field*> fieldsOf(std::string_view command) {
  std::vector<const Field*> fields;
  for (const Field& f : kFields)
    if (f.command == command) fields.push_back(&f);
  return fields;
}

// What `new X()` is for a command with fields: its shortest form with arguments, each field at
// its value when it has none (F() is F(1), Cylinder() Cylinder(1, 1)); empty: X has none.
inline std::vector<std::string> defaultArguments(std::string_view name) {
  for (const TurtleCommand& c : kTurtleCommands)
    if (c.name == name && c.arity == 0) return {};  // `Null` is Null's own form without arguments
  int shortest = 0;
  for (const TurtleCommand& c : kTurtleCommands)
    if (c.name == name && c.arity > 0 && (shortest == 0 || c.arity < shortest)) shortest = c.arity;
  const std::vector<const Field*> fields = fieldsOf(name);
  std::vector<std::string> arguments;
  if (shortest > 0 && fields.size() >= size_t(shortest))
    for (int k = 0; k < shortest; ++k) arguments.emplace_back(fields[k]->fallback);
  return arguments;
}

}  // namespace lcjit::frontend::xl
