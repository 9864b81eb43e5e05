# lpfg function files (.func/.fset/.tset/.vset) and func/pfunc/tfunc/val; meant
# to be include()d from the top-level CMakeLists after find_package(LLVM).
add_library(lcjit_functions STATIC ${CMAKE_SOURCE_DIR}/runtime/Functions.cpp)
target_include_directories(lcjit_functions PUBLIC ${CMAKE_SOURCE_DIR}/runtime)
target_include_directories(lcjit_functions SYSTEM PUBLIC ${LLVM_INCLUDE_DIRS})
target_compile_features(lcjit_functions PUBLIC cxx_std_20)
target_link_libraries(lcjit_functions PUBLIC LLVM)
