# Environmental programs (manual §5.10): the test program (our own, the program side of vlab's
# protocol) and the tests that run models with it.
add_executable(lcjit_envfixture ${CMAKE_CURRENT_LIST_DIR}/../environment/envfixture.cpp)
add_executable(lcjit_environment_test ${CMAKE_CURRENT_LIST_DIR}/environment_test.cpp)
target_link_libraries(lcjit_environment_test PRIVATE lcjit_session GTest::gtest_main)
target_compile_definitions(lcjit_environment_test PRIVATE LCJIT_ENV_FIXTURE="$<TARGET_FILE:lcjit_envfixture>")
add_dependencies(lcjit_environment_test lcjit_envfixture)
add_test(NAME environment_test COMMAND lcjit_environment_test)

# lcjit ended by a signal while the program computes: nothing left behind.
foreach(case "files;TERM" "memory;HUP" "pipes;TERM" "files;INT;INT" "memory;INT")
  string(REPLACE ";" "_" label "${case}")
  add_test(NAME environment.terminated_${label}
           COMMAND ${CMAKE_CURRENT_LIST_DIR}/../run_env_termination.sh $<TARGET_FILE:lcjit> $<TARGET_FILE:lcjit_envfixture> ${case})
endforeach()
add_test(NAME environment.watch_crash_then_fix
         COMMAND ${CMAKE_CURRENT_LIST_DIR}/../run_watch_env.sh $<TARGET_FILE:lcjit> $<TARGET_FILE:lcjit_envfixture>)
