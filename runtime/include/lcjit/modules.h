// Module records and descriptors shared by model code and the host runtime.
// A module in a string is a record {id, parameters..., id}; see __lc_R below.
#pragma once
#include <cstdint>
#include <type_traits>
#include "types.h"

typedef uint16_t __lc_ModuleId;
enum { __lc_FirstUserModule = 103 };

// Parameter kinds the runtime knows how to print and convert.
enum __lc_FieldKind : uint8_t {
  __lc_FK_Other = 0, __lc_FK_Bool, __lc_FK_Signed, __lc_FK_Unsigned, __lc_FK_Float, __lc_FK_Double,
  __lc_FK_V2f, __lc_FK_V2d, __lc_FK_V3f, __lc_FK_V3d, __lc_FK_Text, __lc_FK_Char
};

// (Model code is C++14, as lpfg's models are C++11: no `if constexpr` or `_v` traits here.)
template <class T> struct __lc_Kind {
  static constexpr uint8_t value = std::is_enum<T>::value ? __lc_FK_Signed
                                   : !std::is_integral<T>::value ? __lc_FK_Other
                                   : std::is_signed<T>::value    ? __lc_FK_Signed
                                                                 : __lc_FK_Unsigned;
};
#define __LC_KIND(T, K) \
  template <> struct __lc_Kind<T> { static constexpr uint8_t value = K; };
__LC_KIND(bool, __lc_FK_Bool)
__LC_KIND(char, __lc_FK_Char)
__LC_KIND(float, __lc_FK_Float)
__LC_KIND(double, __lc_FK_Double)
__LC_KIND(V2tf, __lc_FK_V2f)
__LC_KIND(V2f, __lc_FK_V2f)
__LC_KIND(V2td, __lc_FK_V2d)
__LC_KIND(V2d, __lc_FK_V2d)
__LC_KIND(V3tf, __lc_FK_V3f)
__LC_KIND(V3f, __lc_FK_V3f)
__LC_KIND(V3td, __lc_FK_V3d)
__LC_KIND(V3d, __lc_FK_V3d)
__LC_KIND(const char*, __lc_FK_Text)
__LC_KIND(char*, __lc_FK_Text)
#undef __LC_KIND
template <class T> constexpr uint8_t __lc_kind_of() { return __lc_Kind<T>::value; }

struct __lc_Field {
  uint32_t offset;
  uint32_t size;
  uint8_t kind;
  const char* typeName;
};

struct __lc_ModuleInfo {
  const char* name;
  uint32_t recordSize;  // sizeof the record struct: 4 for a module without parameters
  uint32_t nFields;
  const __lc_Field* fields;  // offsets are from the start of the record
};

// Module records as lpfg lays them out (and writes them to .strb files): a struct of the leading
// id, the parameters with their natural C++ alignment, and a trailing id field; the id is also
// stored in the record's last two bytes so that strings can be walked backwards.
template <class... T> struct __lc_R;
template <> struct __lc_R<> { __lc_ModuleId id, id2; };
template <class T0> struct __lc_R<T0> { __lc_ModuleId id; T0 p0; __lc_ModuleId id2; };
template <class T0, class T1> struct __lc_R<T0, T1> { __lc_ModuleId id; T0 p0; T1 p1; __lc_ModuleId id2; };
template <class T0, class T1, class T2> struct __lc_R<T0, T1, T2> { __lc_ModuleId id; T0 p0; T1 p1; T2 p2; __lc_ModuleId id2; };
template <class T0, class T1, class T2, class T3>
struct __lc_R<T0, T1, T2, T3> { __lc_ModuleId id; T0 p0; T1 p1; T2 p2; T3 p3; __lc_ModuleId id2; };
template <class T0, class T1, class T2, class T3, class T4, class T5>
struct __lc_R<T0, T1, T2, T3, T4, T5> { __lc_ModuleId id; T0 p0; T1 p1; T2 p2; T3 p3; T4 p4; T5 p5; __lc_ModuleId id2; };

#define __LC_FIELD(R, i, T) {(uint32_t)__builtin_offsetof(R, p##i), (uint32_t)sizeof(T), __lc_kind_of<T>(), #T}
#define __LC_FIELDS_0(R)
#define __LC_FIELDS_1(R, a) __LC_FIELD(R, 0, a)
#define __LC_FIELDS_2(R, a, b) __LC_FIELD(R, 0, a), __LC_FIELD(R, 1, b)
#define __LC_FIELDS_3(R, a, b, c) __LC_FIELDS_2(R, a, b), __LC_FIELD(R, 2, c)
#define __LC_FIELDS_4(R, a, b, c, d) __LC_FIELDS_3(R, a, b, c), __LC_FIELD(R, 3, d)
#define __LC_FIELDS_6(R, a, b, c, d, e, f) __LC_FIELDS_4(R, a, b, c, d), __LC_FIELD(R, 4, e), __LC_FIELD(R, 5, f)

// Record structs, ids and field tables of the predefined modules.
#define LCJIT_MODULE(N, I, A, ...)                                                  \
  using __lc_R_##N = __lc_R<__VA_ARGS__>;                                          \
  enum : __lc_ModuleId { __lc_id_##N = I };                                        \
  static constexpr __lc_Field __lc_fields_##N[A > 0 ? A : 1] = {__LC_FIELDS_##A(__lc_R_##N __VA_OPT__(, ) __VA_ARGS__)};
#include "stdmods.def"
#undef LCJIT_MODULE

static constexpr __lc_ModuleInfo __lc_stdmods[__lc_FirstUserModule] = {
#define LCJIT_MODULE(N, I, A, ...) {#N, (uint32_t)sizeof(__lc_R_##N), A, __lc_fields_##N},
#include "stdmods.def"
#undef LCJIT_MODULE
};

