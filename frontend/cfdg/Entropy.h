// How Context Free turns a design's text into the constant random seed of each replacement, loop
// and definition: each node of an expression or adjustment contributes bytes (its text as
// written, or a fixed 6-byte constant for an operator, function or adjustment word), and the
// bytes are mixed into a 64-bit state one at a time. A seed depends on the text, so renaming a
// shape or writing 0.50 for 0.5 changes the picture, in lcjit as in Context Free.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace lcjit::frontend::cfdg {

// The fixed bytes of an operator ("+", "N" for unary minus, "P" unary plus, "!", "cons", "paren",
// "select", "rand2" for +/-), a function (by its name in the design: "sin", "rand", …) or an
// adjustment word ("x", "xyz", "s", "sizexyz", "zsize", "r", "trans" …). Empty when it has none.
std::string hotbits(std::string_view what);

// Whether `name` is one of Context Free's built-in functions (cos, rand, rand::normal …).
bool builtinFunction(std::string_view name);

// Mixes `bytes` into `state`, continuing at byte position `position` (0…7), which it advances.
// Bytes are taken as a C string: a zero byte ends them.
uint64_t mixBytes(uint64_t state, std::string_view bytes, int& position);

// A seed of a whole byte string from `start`.
inline uint64_t seedOf(uint64_t start, std::string_view bytes) {
  int position = 0;
  return mixBytes(start, bytes, position);
}

}  // namespace lcjit::frontend::cfdg
