// The C++ every front end writes and the JIT compiles: the one thing about it both sides must
// agree on before either runs.
#pragma once

namespace lcjit::frontend {

// The C++ model code is compiled as (-std=). lpfg compiles models as gnu++11: gnu++14 adds
// nothing that breaks them, and C++17/20 would (std::byte, std::lerp ... clash with models' own
// names under `using namespace std`). A model's lpfg.mak may ask for a newer one.
inline constexpr const char* kDefaultLanguageStandard = "gnu++14";

}  // namespace lcjit::frontend
