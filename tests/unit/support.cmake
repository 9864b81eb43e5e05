# Unit tests of support/ (lcjit_support), linked with nothing else of lcjit's: how files are
# written whole or not at all (ReplacingFile), the engines' memory in huge pages (HugePages). How
# inputs are opened (InputFile) is tested with the readers that use it (files.cmake).
add_executable(lcjit_support_test ${CMAKE_CURRENT_LIST_DIR}/replacing_file_test.cpp
                                  ${CMAKE_CURRENT_LIST_DIR}/huge_pages_test.cpp)
target_link_libraries(lcjit_support_test PRIVATE lcjit_support GTest::gtest_main)
add_test(NAME support_test COMMAND lcjit_support_test)
