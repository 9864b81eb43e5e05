# Session reloads (manual §1.2.2's New … table): which files each reload re-reads.
add_executable(lcjit_session_test ${CMAKE_CURRENT_LIST_DIR}/session_test.cpp)
target_link_libraries(lcjit_session_test PRIVATE lcjit_batch GTest::gtest_main)
add_test(NAME session_test COMMAND lcjit_session_test)

# The sandboxed window run's reply (app/sandbox/SandboxReply.h): a round trip, and damaged replies refused.
add_executable(lcjit_sandbox_reply_test ${CMAKE_CURRENT_LIST_DIR}/sandbox_reply_test.cpp)
target_link_libraries(lcjit_sandbox_reply_test PRIVATE lcjit_sandbox GTest::gtest_main)
add_test(NAME sandbox_reply_test COMMAND lcjit_sandbox_reply_test)

# The window's Parameters panel (app/window/Parameters.h): .vset values and vlab panels' edits.
if(LCJIT_WITH_WINDOW)
  add_executable(lcjit_parameters_test ${CMAKE_CURRENT_LIST_DIR}/parameters_test.cpp)
  target_link_libraries(lcjit_parameters_test PRIVATE lcjit_interactive GTest::gtest_main)
  add_test(NAME parameters_test COMMAND lcjit_parameters_test)
endif()

# A sandboxed run's cgroup (app/sandbox/SandboxCgroup.h): memory outside the address space counted, tasks
# bounded, every process killed. Skipped where no cgroup can be made.
add_executable(lcjit_sandbox_cgroup_test ${CMAKE_CURRENT_LIST_DIR}/sandbox_cgroup_test.cpp)
target_link_libraries(lcjit_sandbox_cgroup_test PRIVATE lcjit_sandbox GTest::gtest_main)
add_test(NAME sandbox_cgroup_test COMMAND lcjit_sandbox_cgroup_test)

# The command line's options (app/cli/Options.h): a sandboxed run's child parses what its parent
# parsed, but for the options that stay with the parent.
add_executable(lcjit_options_test ${CMAKE_CURRENT_LIST_DIR}/options_test.cpp)
target_link_libraries(lcjit_options_test PRIVATE lcjit_cli CLI11::CLI11 GTest::gtest_main)
add_test(NAME options_test COMMAND lcjit_options_test)
