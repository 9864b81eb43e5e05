# Unit tests of the exporters (runtime/export): every format written and read back.
if(NOT TARGET TinyGLTF::TinyGLTF)
  find_package(TinyGLTF CONFIG REQUIRED)
endif()
add_executable(lcjit_export_test ${CMAKE_CURRENT_LIST_DIR}/export_test.cpp)
target_link_libraries(lcjit_export_test PRIVATE lcjit_export TinyGLTF::TinyGLTF fmt::fmt GTest::gtest_main)
add_test(NAME export_test COMMAND lcjit_export_test)
