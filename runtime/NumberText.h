// printf's "%.*g" for floats and doubles, without printf: the string's text writes every float
// parameter as %.9g and every double as %.17g (lpfg's own text forms), and at ~40 ns a number
// std::to_chars' precision path was most of `-out x.str`'s time. The P significant digits are
// worked out exactly in 128-bit integers where the value's scale allows (all but the extremes of
// the exponent range); elsewhere std::to_chars does it. Either way the text is printf's, byte for
// byte (tests/unit/number_text_test.cpp compares them over millions of values).
#pragma once

namespace lcjit::runtime {

// Writes %.{precision}g of `v` at `out` (room for 32 chars) and returns its end. precision 1..17.
char* printfG(char* out, double v, int precision);
char* printfG(char* out, float v, int precision);

}  // namespace lcjit::runtime
