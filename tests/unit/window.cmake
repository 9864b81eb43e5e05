# The interactive window (viewer/Window.h) under X: the test starts its own Xvfb when DISPLAY is
# unset (skips if it cannot), injects mouse/keyboard input and checks pixels and menu calls.
if(TARGET lcjit_window)
  add_executable(window_test ${CMAKE_CURRENT_LIST_DIR}/window_test.cpp)
  target_link_libraries(window_test PRIVATE lcjit_window GTest::gtest_main)
  add_test(NAME window_test COMMAND window_test)
  set_tests_properties(window_test PROPERTIES TIMEOUT 300)
endif()
# The window's file editors (app/window/Editors) with a Session: edits re-run or redraw, Save writes.
if(LCJIT_WITH_WINDOW)
  add_executable(editors_test ${CMAKE_CURRENT_LIST_DIR}/editors_test.cpp)
  target_link_libraries(editors_test PRIVATE lcjit_interactive GTest::gtest_main)
  add_test(NAME editors_test COMMAND editors_test)
endif()
