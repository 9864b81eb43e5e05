# Turtle geometry (manual §5): small models run through the whole pipeline (Session: preprocess,
# rewrite, JIT, derive), their interpreted Geometry checked against hand-computed values.
add_executable(lcjit_geometry_test ${CMAKE_CURRENT_LIST_DIR}/geometry_test.cpp)
target_link_libraries(lcjit_geometry_test PRIVATE lcjit_session GTest::gtest_main)
target_compile_definitions(lcjit_geometry_test PRIVATE LCJIT_TEST_DATA="${CMAKE_CURRENT_LIST_DIR}/data")
add_test(NAME geometry_test COMMAND lcjit_geometry_test)
set_tests_properties(geometry_test PROPERTIES TIMEOUT 600)

# printf's %.9g/%.17g without printf (runtime/NumberText), against printf itself.
add_executable(lcjit_number_text_test ${CMAKE_CURRENT_LIST_DIR}/number_text_test.cpp)
target_link_libraries(lcjit_number_text_test PRIVATE lcjit_runtime GTest::gtest_main)
add_test(NAME number_text_test COMMAND lcjit_number_text_test)
