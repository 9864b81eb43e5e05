// The four function-file targets (.func, .fset, .tset, .vset): the input read as a file of that
// kind, then every entry evaluated at a few points, as model code would ask for them.
#pragma once
#include "runtime/Functions.h"
#include "tests/fuzz/FuzzSupport.h"

namespace lcjit::fuzz {

inline int functionFile(const uint8_t* data, size_t size, const char* extension,
                        llvm::Error (runtime::FunctionStore::*load)(const std::string&)) {
  const std::string& path = inputFile(data, size, extension);
  runtime::FunctionStore store;
  checkError((store.*load)(path), path);
  for (int id = 1; id <= store.size(); ++id)
    for (float x : {-1.0f, 0.0f, 0.37f, 1.0f, 2.0f}) {
      (void)store.func(id, x);
      (void)store.pfunc(id, x, -3, 3);
      (void)store.tfunc(id, x);
      (void)store.funcTangent(id, x);
      (void)store.val(id);
    }
  return 0;
}

}  // namespace lcjit::fuzz
