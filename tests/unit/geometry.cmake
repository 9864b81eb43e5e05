# Turtle geometry (manual §5): small models run through the whole pipeline (Session: preprocess,
# rewrite, JIT, derive), their interpreted Geometry checked against hand-computed values.
add_executable(lcjit_geometry_test ${CMAKE_CURRENT_LIST_DIR}/geometry_test.cpp)
target_link_libraries(lcjit_geometry_test PRIVATE lcjit_session GTest::gtest_main)
target_compile_definitions(lcjit_geometry_test PRIVATE LCJIT_TEST_DATA="${CMAKE_CURRENT_LIST_DIR}/data")
add_test(NAME geometry_test COMMAND lcjit_geometry_test)
set_tests_properties(geometry_test PROPERTIES TIMEOUT 600)
