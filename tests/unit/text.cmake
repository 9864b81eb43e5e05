# Label text (runtime/text): UTF-8, fontconfig's faces and fallbacks, HarfBuzz's shaping,
# FreeType's outlines and bitmaps. In every build (the exports use it).
add_executable(lcjit_text_test ${CMAKE_CURRENT_LIST_DIR}/text_test.cpp)
target_link_libraries(lcjit_text_test PRIVATE lcjit_text GTest::gtest_main)
add_test(NAME text_test COMMAND lcjit_text_test)
