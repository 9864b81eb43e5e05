// Compile errors in plain language, for a classroom (--lab): one sentence per error in the
// student's own files, saying what is wrong in the words a modeller uses, before the compiler's
// own text (which follows unchanged).
#pragma once
#include <string>

namespace lcjit::app {

// `diagnostics`: `FILE:LINE:COL: error: MESSAGE` lines (and any others). Returns the plain
// sentences, then "(what the compiler said:)" and `diagnostics`; `diagnostics` alone when no
// line is an error in a user file.
std::string inPlainLanguage(const std::string& diagnostics);

}  // namespace lcjit::app
