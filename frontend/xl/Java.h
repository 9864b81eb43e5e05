// The Java of XL models as C++ (frontend/xl/Translate.cpp): Java's types, its Math, and the
// functions of XL's library that models call. Internal to frontend/xl.
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

// Java's Math, as C++ has it (the functions take and give doubles, in radians, as Java's do).
inline std::string javaMath(std::string_view name) {
  static const std::set<std::string_view> kSame = {"sqrt", "sin",  "cos",   "tan",  "asin", "acos", "atan", "atan2",
                                                   "exp",  "log",  "log10", "pow",  "floor", "ceil", "abs",  "cbrt",
                                                   "sinh", "cosh", "tanh",  "hypot"};
  if (kSame.count(name)) return "std::" + std::string(name);
  if (name == "min") return "std::fmin";
  if (name == "max") return "std::fmax";
  if (name == "PI") return "M_PI";
  if (name == "E") return "M_E";
  if (name == "toRadians") return "(M_PI / 180) *";
  if (name == "toDegrees") return "(180 / M_PI) *";
  if (name == "round") return "(long long)std::floor(0.5 +";  // Java's: the nearest, halves up
  return "";
}

// GroIMP's shaders by name (imp3d.shading.RGBAShader: its STANDARD table, the EGA's 16 as EGA_0 …
// EGA_15, then java.awt.Color's BLACK … WHITE) as the number of their colour: lcjit's colour
// index is it + 2 (Palette::ega(), runtime/files/Palette.h), as for F's colours.
inline constexpr std::string_view kShaders[] = {
    "EGA_0", "EGA_1",  "EGA_2",  "EGA_3",  "EGA_4",  "EGA_5",      "EGA_6",   "EGA_7", "EGA_8", "EGA_9",
    "EGA_10", "EGA_11", "EGA_12", "EGA_13", "EGA_14", "EGA_15",    "BLACK",   "BLUE",  "CYAN",  "DARK_GRAY",
    "GRAY",   "GREEN",  "LIGHT_GRAY", "MAGENTA", "ORANGE", "PINK", "RED",     "YELLOW", "WHITE"};

// XL's library functions (de.grogra.rgg.Library) that models call most, as C++ on lpfg's random
// numbers (ran(x): uniform in [0, x)): random(a, b) uniform in [a, b), irandom(a, b) a whole
// number from a to b, probability(p) true with probability p, normal(mu, sigma) normally
// distributed (Box and Muller's transform of two uniform numbers); R2D and DEG, degrees per
// radian and radians per degree; println and print of a number, a truth value or a string.
inline constexpr std::string_view kLibrary =
    "inline float random(float a, float b) { return a + ran(b - a); } "
    "inline int irandom(int a, int b) { return a + (int)ran((float)(b - a + 1)); } "
    "inline bool probability(float p) { return ran(1) < p; } "
    "const double R2D = 180 / M_PI, DEG = M_PI / 180; "
    "inline double normal(double mu, double sigma) { double u = 1 - ran(1), v = ran(1); "
    "return mu + sigma * std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * v); } "
    "inline void print(double x) { std::printf(\"%g\", x); } inline void print(const char* s) { std::printf(\"%s\", s); } "
    "inline void print(bool b) { std::printf(\"%s\", b ? \"true\" : \"false\"); } "
    "inline void println(double x) { std::printf(\"%g\\n\", x); } "
    "inline void println(const char* s) { std::printf(\"%s\\n\", s); } "
    "inline void println(bool b) { std::printf(\"%s\\n\", b ? \"true\" : \"false\"); } inline void println() { std::printf(\"\\n\"); } "
    "inline void print(long long x) { std::printf(\"%lld\", x); } inline void print(int x) { print((long long)x); } "
    "inline void println(long long x) { std::printf(\"%lld\\n\", x); } inline void println(int x) { println((long long)x); }";

}  // namespace lcjit::frontend::xl
