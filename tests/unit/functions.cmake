# Unit tests for runtime/Functions (lpfg function files).
add_executable(functions_test ${CMAKE_SOURCE_DIR}/tests/unit/functions_test.cpp)
target_link_libraries(functions_test PRIVATE lcjit_functions GTest::gtest_main)
target_compile_definitions(functions_test PRIVATE
  LCJIT_FUNCTIONS_DATA="${CMAKE_SOURCE_DIR}/tests/unit/data/functions")
add_test(NAME functions_test COMMAND functions_test)
