// The Java of XL models as C++ (frontend/xl/Translate.cpp): Java's types, its Math, GroIMP's
// shaders' names (XL's library itself is runtime/include/lcjit/xl.h). Internal to frontend/xl.
#pragma once
#include <set>
#include <string>
#include <string_view>

namespace lcjit::frontend::xl {

// Java's number and boolean types as C++'s; empty for any other.
inline std::string javaType(std::string_view type) {
  if (type == "boolean") return "bool";
  if (type == "int" || type == "float" || type == "double" || type == "long" || type == "short" || type == "char") {
    return std::string(type);
  }
  if (type == "byte") return "signed char";
  return "";
}

// Java's Math: lcjit/xl.h's __xl_Math, which has Java's (the functions of doubles in radians,
// abs, min and max of the type given, round to the nearest, random in [0, 1)); empty for a name
// it does not have.
inline std::string javaMath(std::string_view name) {
  static const std::set<std::string_view> kMath = {
      "sqrt", "cbrt", "pow",  "exp",  "log",   "log10", "sin",  "cos",       "tan",       "asin",   "acos", "atan",
      "atan2", "sinh", "cosh", "tanh", "hypot", "floor", "ceil", "toRadians", "toDegrees", "signum", "abs",  "min",
      "max",  "round", "random", "PI", "E"};
  return kMath.count(name) ? "__xl_Math::" + std::string(name) : "";
}

// GroIMP's shaders by name (imp3d.shading.RGBAShader: its STANDARD table, the EGA's 16 as EGA_0 …
// EGA_15, then java.awt.Color's BLACK … WHITE) as the number of their colour: lcjit's colour
// index is it + 2 (Palette::ega(), runtime/files/Palette.h), as for F's colours.
inline constexpr std::string_view kShaders[] = {
    "EGA_0", "EGA_1",  "EGA_2",  "EGA_3",  "EGA_4",  "EGA_5",      "EGA_6",   "EGA_7", "EGA_8", "EGA_9",
    "EGA_10", "EGA_11", "EGA_12", "EGA_13", "EGA_14", "EGA_15",    "BLACK",   "BLUE",  "CYAN",  "DARK_GRAY",
    "GRAY",   "GREEN",  "LIGHT_GRAY", "MAGENTA", "ORANGE", "PINK", "RED",     "YELLOW", "WHITE"};

}  // namespace lcjit::frontend::xl
