# Unit tests of the input-file readers (runtime/files) and of how lcjit opens what they read
# (support/InputFile: only regular files).
add_executable(lcjit_files_test
  ${CMAKE_CURRENT_LIST_DIR}/view_file_test.cpp ${CMAKE_CURRENT_LIST_DIR}/palette_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/contours_test.cpp ${CMAKE_CURRENT_LIST_DIR}/surfaces_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_files_test.cpp ${CMAKE_CURRENT_LIST_DIR}/images_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/bspline_surfaces_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/terrain_patches_test.cpp ${CMAKE_CURRENT_LIST_DIR}/panel_file_test.cpp
  ${CMAKE_CURRENT_LIST_DIR}/input_file_test.cpp)
target_link_libraries(lcjit_files_test PRIVATE lcjit_files PNG::PNG GTest::gtest_main)  # libpng: test PNGs
target_include_directories(lcjit_files_test SYSTEM PRIVATE /usr/include/stb)  # stb_image_write: test images
target_compile_definitions(lcjit_files_test PRIVATE LCJIT_TEST_DATA="${CMAKE_CURRENT_LIST_DIR}/data")
add_test(NAME files_test COMMAND lcjit_files_test)

# The editors' function and contour files (runtime/files/CurveFiles): byte-for-byte round trips,
# and moved points read back by the model's own readers (runtime/Functions, Contours).
add_executable(curve_files_test ${CMAKE_CURRENT_LIST_DIR}/curve_files_test.cpp)
target_link_libraries(curve_files_test PRIVATE lcjit_files lcjit_functions GTest::gtest_main)
add_test(NAME curve_files_test COMMAND curve_files_test)
