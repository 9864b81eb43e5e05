# Faults in model code (docs/faults.md): each kind survived 100 times in one process, memory flat.
add_executable(lcjit_faults_test ${CMAKE_CURRENT_LIST_DIR}/faults_test.cpp)
target_link_libraries(lcjit_faults_test PRIVATE lcjit_session GTest::gtest_main)
add_test(NAME faults_test COMMAND lcjit_faults_test)
set_tests_properties(faults_test PROPERTIES TIMEOUT 120)
