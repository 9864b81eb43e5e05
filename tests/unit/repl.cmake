# The REPL (repl/Repl, `lcjit repl`): its text handling alone (completion, complete C++), and end
# to end with scripted input (tests/repl/, see tests/run_repl.sh): every NAME.in and NAME.drive
# there is the test repl.NAME.
add_executable(lcjit_repl_text_test ${CMAKE_CURRENT_LIST_DIR}/repl_text_test.cpp)
target_link_libraries(lcjit_repl_text_test PRIVATE lcjit_repl_text GTest::gtest_main)
add_test(NAME repl_text_test COMMAND lcjit_repl_text_test)

set(LCJIT_REPL_DIR ${CMAKE_CURRENT_LIST_DIR}/../repl)
file(GLOB LCJIT_REPL_SCRIPTS CONFIGURE_DEPENDS ${LCJIT_REPL_DIR}/*.in ${LCJIT_REPL_DIR}/*.drive)
foreach(script ${LCJIT_REPL_SCRIPTS})
  get_filename_component(name ${script} NAME_WE)
  # :view and --lab open the window; :save writes pictures.
  if((name STREQUAL "view" OR name STREQUAL "lab") AND NOT LCJIT_WITH_WINDOW)
    continue()
  endif()
  if(name STREQUAL "save" AND NOT LCJIT_WITH_RENDERING)
    continue()
  endif()
  set(command ${CMAKE_CURRENT_LIST_DIR}/../run_repl.sh $<TARGET_FILE:lcjit> ${LCJIT_REPL_DIR} ${name})
  if(name STREQUAL "view" OR name STREQUAL "lab")
    # The window needs an X server.
    set(command xvfb-run -a -s "-screen 0 1024x768x24" ${command})
  endif()
  add_test(NAME repl.${name} COMMAND ${command})
  set_tests_properties(repl.${name} PROPERTIES TIMEOUT 60)
endforeach()
