# Renderer, framing and headless (EGL, software) rendering tests: synthetic geometry rendered to
# images whose pixels are checked. Needs no display and no GPU (Mesa llvmpipe).
if(TARGET lcjit_headless)
  add_executable(render_test ${CMAKE_CURRENT_LIST_DIR}/render_test.cpp)
  target_link_libraries(render_test PRIVATE lcjit_headless lcjit_text GTest::gtest_main)
  target_include_directories(render_test SYSTEM PRIVATE /usr/include/stb)
  add_test(NAME render_test COMMAND render_test)
endif()
