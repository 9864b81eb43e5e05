// What C++ typed at lcjit's REPL compiles against (see docs/repl.md): an expression's value is
// turned into text here, in the model's own types, and handed to the host, which prints it.
#pragma once
#include <cstdio>
#include <string>
#include <type_traits>

#include "vectors.h"

extern "C" void lcjit_repl_output(const char* text);

namespace __lc_repl {

template <class T>
std::string typeName() {  // from the compiler's own spelling of T
  std::string f = __PRETTY_FUNCTION__;
  size_t at = f.find("T = ");
  return at == std::string::npos ? "value" : f.substr(at + 4, f.find_first_of(";]", at) - at - 4);
}

inline std::string number(const char* format, auto v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

inline std::string quoted(const char* s) { return s ? "\"" + std::string(s) + "\"" : "(null)"; }

template <class T>
std::string show(const T& v) {
  using U = std::remove_cvref_t<T>;
  if constexpr (std::is_same_v<U, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<U, char>) return "'" + std::string(1, v) + "'";
  else if constexpr (std::is_floating_point_v<U>) return number("%.9g", (double)v);
  else if constexpr (std::is_integral_v<U> && std::is_signed_v<U>) return number("%lld", (long long)v);
  else if constexpr (std::is_integral_v<U>) return number("%llu", (unsigned long long)v);
  else if constexpr (std::is_enum_v<U>) return show((std::underlying_type_t<U>)v);
  else if constexpr (std::is_same_v<U, std::string>) return quoted(v.c_str());
  else if constexpr (std::is_convertible_v<U, const char*>) return quoted(v);
  else if constexpr (std::is_pointer_v<U>) return number("%p", (const void*)v);
  else if constexpr (std::is_same_v<U, __lc_V3<float>> || std::is_same_v<U, __lc_V3<double>>)
    return "(" + show(v.x) + ", " + show(v.y) + ", " + show(v.z) + ")";
  else if constexpr (std::is_same_v<U, __lc_V2<float>> || std::is_same_v<U, __lc_V2<double>>)
    return "(" + show(v.x) + ", " + show(v.y) + ")";
  else return "(" + typeName<U>() + ")";
}

// `expr` is the typed expression wrapped in a lambda: a void one is only run.
template <class F>
void print(F expr) {
  if constexpr (std::is_void_v<decltype(expr())>) expr();
  else lcjit_repl_output(show(expr()).c_str());
}

}  // namespace __lc_repl
