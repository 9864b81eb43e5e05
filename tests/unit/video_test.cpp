// viewer/VideoFile: videos written frame by frame and read back with FFmpeg's demuxers and
// decoders (linked here, opened by lcjit only when a video is made): frame count, size, codec,
// frame rate and the colours of known solid frames; and the errors, each naming the file.
#include "viewer/VideoFile.h"
#include "support/ReplacingFile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

namespace fs = std::filesystem;
using lcjit::runtime::Image;
using lcjit::viewer::VideoOptions;
using lcjit::viewer::VideoWriter;

namespace {

using Rgb = std::array<int, 3>;
// Far apart in every channel pair, so that a swapped channel or a wrong frame shows.
const std::vector<Rgb> kColours = {{220, 30, 30}, {30, 200, 40}, {40, 40, 210}, {240, 240, 240}, {20, 20, 20}, {230, 220, 40}};

Image solid(int w, int h, Rgb c) {
  Image im;
  im.width = w;
  im.height = h;
  im.rgba.resize(size_t(w) * h * 4);
  for (size_t i = 0; i < im.rgba.size(); i += 4) {
    im.rgba[i] = uint8_t(c[0]);
    im.rgba[i + 1] = uint8_t(c[1]);
    im.rgba[i + 2] = uint8_t(c[2]);
    im.rgba[i + 3] = 255;
  }
  return im;
}

struct Decoded {
  std::string error;
  AVCodecID codec = AV_CODEC_ID_NONE;
  AVRational frameRate{0, 1};
  int width = 0, height = 0;
  std::vector<Image> frames;  // RGBA
};

// Every frame of the file's video stream, converted back to RGBA.
Decoded decode(const std::string& path) {
  Decoded d;
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, path.c_str(), nullptr, nullptr) < 0) return d.error = "cannot open " + path, d;
  avformat_find_stream_info(format, nullptr);
  int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (index < 0) {
    avformat_close_input(&format);
    return d.error = "no video stream", d;
  }
  AVStream* stream = format->streams[index];
  d.codec = stream->codecpar->codec_id;
  d.frameRate = stream->avg_frame_rate;
  d.width = stream->codecpar->width;
  d.height = stream->codecpar->height;
  const AVCodec* decoder = avcodec_find_decoder(d.codec);
  AVCodecContext* context = avcodec_alloc_context3(decoder);
  avcodec_parameters_to_context(context, stream->codecpar);
  if (avcodec_open2(context, decoder, nullptr) < 0) d.error = "cannot open the decoder";
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* scale = nullptr;
  auto receive = [&] {
    while (avcodec_receive_frame(context, frame) >= 0) {
      scale = sws_getCachedContext(scale, frame->width, frame->height, AVPixelFormat(frame->format), frame->width,
                                   frame->height, AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
      Image im;
      im.width = frame->width;
      im.height = frame->height;
      // swscale writes whole vectors: rows of an aligned size, copied into the Image after.
      const int row = im.width * 4, aligned = (row + 63) / 64 * 64;
      std::vector<uint8_t> rows(size_t(aligned) * im.height + 64);
      uint8_t* dst[1] = {rows.data()};
      int stride[1] = {aligned};
      sws_scale(scale, frame->data, frame->linesize, 0, frame->height, dst, stride);
      im.rgba.resize(size_t(row) * im.height);
      for (int y = 0; y < im.height; ++y) std::memcpy(&im.rgba[size_t(y) * row], &rows[size_t(y) * aligned], row);
      d.frames.push_back(std::move(im));
    }
  };
  while (d.error.empty() && av_read_frame(format, packet) >= 0) {
    if (packet->stream_index == index && avcodec_send_packet(context, packet) >= 0) receive();
    av_packet_unref(packet);
  }
  avcodec_send_packet(context, nullptr);
  receive();
  sws_freeContext(scale);
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&context);
  avformat_close_input(&format);
  return d;
}

AVCodecID codecOfEncoder(const std::string& name) {
  if (name == "libx264") return AV_CODEC_ID_H264;
  if (name == "mpeg4") return AV_CODEC_ID_MPEG4;
  if (name == "libvpx-vp9") return AV_CODEC_ID_VP9;
  if (name == "libvpx") return AV_CODEC_ID_VP8;
  return AV_CODEC_ID_NONE;
}

class VideoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("lcjit_video_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string file(const std::string& name) const { return (dir / name).string(); }
  fs::path dir;
};

// Writes the solid colours at w×h, reads them back and checks them against what was written.
void roundTrip(const std::string& path, int w, int h, const std::vector<std::string>& encoders) {
  VideoOptions options;
  options.fps = 10;
  auto video = VideoWriter::create(path, options);
  ASSERT_TRUE(bool(video)) << llvm::toString(video.takeError());
  const std::string encoder = (*video)->codecName();
  EXPECT_NE(std::find(encoders.begin(), encoders.end(), encoder), encoders.end()) << encoder;
  for (const Rgb& c : kColours) ASSERT_FALSE(bool((*video)->add(solid(w, h, c))));
  EXPECT_EQ((*video)->frames(), int(kColours.size()));
  ASSERT_FALSE(bool((*video)->finish()));

  Decoded d = decode(path);
  ASSERT_EQ(d.error, "");
  EXPECT_EQ(d.codec, codecOfEncoder(encoder));
  EXPECT_EQ(d.frameRate.num, 10 * d.frameRate.den) << d.frameRate.num << "/" << d.frameRate.den;
  // yuv420p: an odd size is padded to the next even one.
  EXPECT_EQ(d.width, w + w % 2);
  EXPECT_EQ(d.height, h + h % 2);
  ASSERT_EQ(d.frames.size(), kColours.size());
  for (size_t i = 0; i < kColours.size(); ++i) {
    const Image& f = d.frames[i];
    ASSERT_EQ(f.width, w + w % 2);
    // The centre and the padded corner (a copy of the last column and row): the frame's colour,
    // within what 4:2:0 and a lossy codec change.
    for (auto [x, y] : {std::pair{f.width / 2, f.height / 2}, std::pair{f.width - 1, f.height - 1}}) {
      auto p = f.pixel(x, y);
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(p[ch], kColours[i][ch], 16) << path << " frame " << i << " pixel " << x << "," << y << " channel " << ch;
    }
  }
}

TEST_F(VideoTest, Mp4FramesReadBack) { roundTrip(file("colours.mp4"), 64, 48, {"libx264", "mpeg4"}); }
TEST_F(VideoTest, WebmFramesReadBack) { roundTrip(file("colours.webm"), 64, 48, {"libvpx-vp9", "libvpx"}); }
TEST_F(VideoTest, OddSizeIsPadded) { roundTrip(file("odd.MP4"), 33, 21, {"libx264", "mpeg4"}); }

// The padding repeats the last column and row, not another part of the picture: a picture
// whose last column and row have their own colour keeps it in the added ones.
TEST_F(VideoTest, PaddingRepeatsTheLastColumnAndRow) {
  const int w = 33, h = 21;
  Image im = solid(w, h, kColours[0]);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (x >= w - 8 || y >= h - 8)  // a border wide enough to survive the codec's blocks
        for (int ch = 0; ch < 3; ++ch) im.rgba[(size_t(y) * w + x) * 4 + ch] = uint8_t(kColours[2][ch]);
  auto video = VideoWriter::create(file("border.mp4"));
  ASSERT_TRUE(bool(video)) << llvm::toString(video.takeError());
  ASSERT_FALSE(bool((*video)->add(im)));
  ASSERT_FALSE(bool((*video)->finish()));
  Decoded d = decode(file("border.mp4"));
  ASSERT_EQ(d.frames.size(), 1u) << d.error;
  const Image& f = d.frames[0];
  ASSERT_EQ(f.width, w + 1);
  ASSERT_EQ(f.height, h + 1);
  for (auto [x, y] : {std::pair{w, h / 2}, std::pair{w / 2, h}, std::pair{w, h}}) {
    auto p = f.pixel(x, y);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(p[ch], kColours[2][ch], 16) << "pixel " << x << "," << y << " channel " << ch;
  }
  auto inside = f.pixel(4, 4);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(inside[ch], kColours[0][ch], 16) << "channel " << ch;
}

TEST_F(VideoTest, FrameOfAnotherSizeIsAnErrorNamingTheFile) {
  auto video = VideoWriter::create(file("sizes.mp4"));
  ASSERT_TRUE(bool(video)) << llvm::toString(video.takeError());
  ASSERT_FALSE(bool((*video)->add(solid(32, 32, kColours[0]))));
  std::string e = llvm::toString((*video)->add(solid(40, 32, kColours[1])));
  EXPECT_NE(e.find("sizes.mp4"), std::string::npos) << e;
  EXPECT_NE(e.find("frame 2 is 40×32 pixels; the video's frames are 32×32"), std::string::npos) << e;
  // What was written before stays a video of its frames.
  ASSERT_FALSE(bool((*video)->finish()));
  Decoded d = decode(file("sizes.mp4"));
  EXPECT_EQ(d.frames.size(), 1u) << d.error;
}

TEST_F(VideoTest, UnknownTypeIsAnError) {
  auto video = VideoWriter::create(file("clip.avi"));
  ASSERT_FALSE(bool(video));
  std::string e = llvm::toString(video.takeError());
  EXPECT_NE(e.find("clip.avi: unknown video type (use .mp4 or .webm)"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(file("clip.avi")));
}

TEST_F(VideoTest, UnwritablePlaceIsAnErrorAtCreation) {
  auto video = VideoWriter::create(file("no/such/folder/clip.webm"));
  ASSERT_FALSE(bool(video));
  std::string e = llvm::toString(video.takeError());
  EXPECT_NE(e.find("no/such/folder/clip.webm: cannot create the file: No such file or directory"), std::string::npos) << e;
}

TEST_F(VideoTest, NoFramesNoFile) {
  auto video = VideoWriter::create(file("empty.mp4"));
  ASSERT_TRUE(bool(video)) << llvm::toString(video.takeError());
  // Created at once (an unwritable place fails early) beside its name, which it takes when
  // finished: a player never opens half a video.
  auto unfinished = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
      n += lcjit::support::ReplacingFile::isUnfinished(e.path().filename().string());
    return n;
  };
  EXPECT_FALSE(fs::exists(file("empty.mp4")));
  EXPECT_EQ(unfinished(), 1);
  ASSERT_FALSE(bool((*video)->finish()));
  EXPECT_FALSE(fs::exists(file("empty.mp4")));
  EXPECT_EQ(unfinished(), 0);
}

TEST_F(VideoTest, DestructorFinishesTheFile) {
  {
    auto video = VideoWriter::create(file("dropped.webm"));
    ASSERT_TRUE(bool(video)) << llvm::toString(video.takeError());
    for (int i = 0; i < 3; ++i) ASSERT_FALSE(bool((*video)->add(solid(16, 16, kColours[i]))));
  }
  Decoded d = decode(file("dropped.webm"));
  EXPECT_EQ(d.error, "");
  EXPECT_EQ(d.frames.size(), 3u);
}

}  // namespace
