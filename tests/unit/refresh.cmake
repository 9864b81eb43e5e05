# Refresh modes and file monitoring (app/session/FileMonitor): the §1.2.2/§1.3 policy tables and the
# inotify watcher on real files in a temporary directory. No window.
add_executable(lcjit_refresh_test ${CMAKE_CURRENT_LIST_DIR}/refresh_test.cpp)
target_link_libraries(lcjit_refresh_test PRIVATE lcjit_monitor GTest::gtest_main)
add_test(NAME refresh_test COMMAND lcjit_refresh_test)
