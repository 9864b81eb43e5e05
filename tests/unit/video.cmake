# Video files (viewer/VideoFile): written, then read back with FFmpeg's decoders, which the test
# links (lcjit itself opens FFmpeg only when it writes a video).
if(TARGET lcjit_video)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(LCJIT_FFMPEG_TEST REQUIRED IMPORTED_TARGET libavformat libavcodec libswscale libavutil)
  add_executable(video_test ${CMAKE_CURRENT_LIST_DIR}/video_test.cpp)
  target_link_libraries(video_test PRIVATE lcjit_video lcjit_support PkgConfig::LCJIT_FFMPEG_TEST GTest::gtest_main)
  add_test(NAME video_test COMMAND video_test)
endif()
