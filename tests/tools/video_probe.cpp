// video_probe VIDEO [PREFIX]
// What the end-to-end tests know of a video lcjit wrote, read with FFmpeg's demuxer and decoder:
// one line `codec WIDTH HEIGHT FPS FRAMES` (e.g. `h264 800 800 25 4`; FPS from the first and last
// frames' timestamps, since a .webm stores none; 0 for one frame); with PREFIX, every frame also to
// PREFIX0000.png, PREFIX0001.png … (for tests/tools/image_diff).
// Exit status: 0, or 2 when the file cannot be read as a video.
#include <cstdio>
#include <string>
#include <vector>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: video_probe VIDEO [PREFIX]\n");
    return 2;
  }
  const std::string prefix = argc > 2 ? argv[2] : "";
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, argv[1], nullptr, nullptr) < 0 || avformat_find_stream_info(format, nullptr) < 0) {
    std::fprintf(stderr, "video_probe: cannot read %s\n", argv[1]);
    return 2;
  }
  int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (index < 0) {
    std::fprintf(stderr, "video_probe: %s has no video stream\n", argv[1]);
    return 2;
  }
  AVStream* stream = format->streams[index];
  const AVCodec* decoder = avcodec_find_decoder(stream->codecpar->codec_id);
  AVCodecContext* context = avcodec_alloc_context3(decoder);
  avcodec_parameters_to_context(context, stream->codecpar);
  if (!decoder || avcodec_open2(context, decoder, nullptr) < 0) {
    std::fprintf(stderr, "video_probe: no decoder for %s\n", argv[1]);
    return 2;
  }
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* scale = nullptr;
  int frames = 0;
  int64_t first = 0, last = 0;
  auto receive = [&] {
    while (avcodec_receive_frame(context, frame) >= 0) {
      (frames == 0 ? first : last) = frame->best_effort_timestamp;
      if (!prefix.empty()) {
        scale = sws_getCachedContext(scale, frame->width, frame->height, AVPixelFormat(frame->format), frame->width,
                                     frame->height, AV_PIX_FMT_RGB24, SWS_BILINEAR, nullptr, nullptr, nullptr);
        // swscale writes whole vectors: rows of an aligned size.
        const int stride = (frame->width * 3 + 63) / 64 * 64;
        std::vector<uint8_t> rgb(size_t(stride) * frame->height + 64);
        uint8_t* dst[1] = {rgb.data()};
        int strides[1] = {stride};
        sws_scale(scale, frame->data, frame->linesize, 0, frame->height, dst, strides);
        char name[32];
        std::snprintf(name, sizeof name, "%04d.png", frames);
        if (!stbi_write_png((prefix + name).c_str(), frame->width, frame->height, 3, rgb.data(), stride)) {
          std::fprintf(stderr, "video_probe: cannot write %s%s\n", prefix.c_str(), name);
          std::exit(2);
        }
      }
      ++frames;
    }
  };
  while (av_read_frame(format, packet) >= 0) {
    if (packet->stream_index == index && avcodec_send_packet(context, packet) >= 0) receive();
    av_packet_unref(packet);
  }
  avcodec_send_packet(context, nullptr);
  receive();
  const double seconds = double(last - first) * av_q2d(stream->time_base);
  std::printf("%s %d %d %.0f %d\n", avcodec_get_name(stream->codecpar->codec_id), stream->codecpar->width,
              stream->codecpar->height, frames > 1 && seconds > 0 ? (frames - 1) / seconds : 0.0, frames);
  sws_freeContext(scale);
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&context);
  avformat_close_input(&format);
  return 0;
}
