// What a compiled model's object puts in memory besides its code (StaticData in Compiler.h): read
// from the object file's sections and symbols before it is linked, so that a model whose static
// data would pass a memory limit is refused before any of it is allocated, and so that loading
// knows which variables start zero-filled (their bytes need not be copied for resetState()).
#pragma once

#include "jit/Compiler.h"
#include "jit/ObjectCache.h"

#include <set>
#include <string>

namespace lcjit::jit {

struct ObjectData {
  StaticData data;
  std::set<std::string> zeroFilled;  // the symbols the object defines in zero-filled sections (.bss)
};

ObjectData dataOf(const CachedObject& object);

}  // namespace lcjit::jit
