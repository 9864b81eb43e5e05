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

template <class V> std::string number(const char* format, V v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

inline std::string quoted(const char* s) { return s ? "\"" + std::string(s) + "\"" : "(null)"; }

template <class T>
std::string show(const T& v) {
  typedef typename std::remove_cv<typename std::remove_reference<T>::type>::type U;
  if constexpr (std::is_same<U, bool>::value) return v ? "true" : "false";
  else if constexpr (std::is_same<U, char>::value) return "'" + std::string(1, v) + "'";
  else if constexpr (std::is_floating_point<U>::value) return number("%.9g", (double)v);
  else if constexpr (std::is_integral<U>::value && std::is_signed<U>::value) return number("%lld", (long long)v);
  else if constexpr (std::is_integral<U>::value) return number("%llu", (unsigned long long)v);
  else if constexpr (std::is_enum<U>::value) return show((typename std::underlying_type<U>::type)v);
  else if constexpr (std::is_same<U, std::string>::value) return quoted(v.c_str());
  else if constexpr (std::is_convertible<U, const char*>::value) return quoted(v);
  else if constexpr (std::is_pointer<U>::value) return number("%p", (const void*)v);
  else if constexpr (std::is_base_of<V3t<float>, U>::value || std::is_base_of<V3t<double>, U>::value)
    return "(" + show(v.x) + ", " + show(v.y) + ", " + show(v.z) + ")";
  else if constexpr (std::is_base_of<V2t<float>, U>::value || std::is_base_of<V2t<double>, U>::value)
    return "(" + show(v.x) + ", " + show(v.y) + ")";
  else return "(" + typeName<U>() + ")";
}

// `expr` is the typed expression wrapped in a lambda: a void one is only run.
template <class F>
void print(F expr) {
  if constexpr (std::is_void<decltype(expr())>::value) expr();
  else lcjit_repl_output(show(expr()).c_str());
}

}  // namespace __lc_repl
