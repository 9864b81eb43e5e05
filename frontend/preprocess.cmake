# lcjit_preprocess: in-process `-E` of .l files (Clang as a library). include()d from
# frontend/CMakeLists.txt; needs LLVM and Clang found (top-level CMakeLists.txt does that).
add_library(lcjit_preprocess
  "${CMAKE_CURRENT_LIST_DIR}/Preprocess.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/Preprocess.h"
  "${CMAKE_CURRENT_LIST_DIR}/CacheFiles.cpp"
  "${CMAKE_CURRENT_LIST_DIR}/CacheFiles.h")
separate_arguments(_lcjit_pp_llvm_defs NATIVE_COMMAND "${LLVM_DEFINITIONS}")
target_compile_options(lcjit_preprocess PRIVATE ${_lcjit_pp_llvm_defs})
target_compile_definitions(lcjit_preprocess PRIVATE
  LCJIT_CLANG_EXECUTABLE="${LCJIT_CLANG_EXECUTABLE}"
  LCJIT_CLANG_RESOURCE_DIR="${LCJIT_CLANG_RESOURCE_DIR}")
target_include_directories(lcjit_preprocess SYSTEM PUBLIC ${LLVM_INCLUDE_DIRS} ${CLANG_INCLUDE_DIRS})
target_include_directories(lcjit_preprocess PUBLIC "${CMAKE_CURRENT_LIST_DIR}/..")
# Shared libclang-cpp / libLLVM keep link times low.
target_link_libraries(lcjit_preprocess PUBLIC clang-cpp LLVM)
target_compile_features(lcjit_preprocess PUBLIC cxx_std_20)
