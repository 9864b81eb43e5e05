# Unit tests for jit/ (lcjit_jit) and frontend/lc/Preprocess (lcjit_preprocess); include()d from
# tests/CMakeLists.txt. One ctest entry per binary: the jit tests share one freshly built PCH.
add_executable(lcjit_jit_test "${CMAKE_CURRENT_LIST_DIR}/jit_test.cpp")
target_link_libraries(lcjit_jit_test PRIVATE lcjit_jit lcjit_support GTest::gtest_main)
target_compile_definitions(lcjit_jit_test PRIVATE
  LCJIT_TEST_DATA_DIR="${CMAKE_CURRENT_LIST_DIR}/data")
add_test(NAME jit_test COMMAND lcjit_jit_test)
set_tests_properties(jit_test PROPERTIES TIMEOUT 600)

add_executable(lcjit_preprocess_test "${CMAKE_CURRENT_LIST_DIR}/preprocess_test.cpp")
target_link_libraries(lcjit_preprocess_test PRIVATE lcjit_preprocess GTest::gtest_main)
target_compile_definitions(lcjit_preprocess_test PRIVATE LCJIT_RUNTIME_INCLUDE_DIR="${CMAKE_SOURCE_DIR}/runtime/include")
add_test(NAME preprocess_test COMMAND lcjit_preprocess_test)
