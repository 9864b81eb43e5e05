# The animation file reader and frame schedule (runtime/files/AnimationFile): no window.
add_executable(lcjit_animation_test ${CMAKE_CURRENT_LIST_DIR}/animation_test.cpp)
target_link_libraries(lcjit_animation_test PRIVATE lcjit_files GTest::gtest_main)
add_test(NAME animation_test COMMAND lcjit_animation_test)
