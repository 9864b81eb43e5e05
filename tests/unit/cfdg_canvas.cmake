# The CFDG canvas (runtime/cfdg/AggCanvas.cpp) against Context Free's cfdg, run by the test as
# the oracle (skipped without /usr/bin/cfdg).
add_executable(lcjit_cfdg_canvas_test ${CMAKE_CURRENT_LIST_DIR}/cfdg_canvas_test.cpp)
target_link_libraries(lcjit_cfdg_canvas_test PRIVATE lcjit_cfdg_canvas lcjit_files PNG::PNG GTest::gtest_main)
add_test(NAME cfdg_canvas_test COMMAND lcjit_cfdg_canvas_test)
