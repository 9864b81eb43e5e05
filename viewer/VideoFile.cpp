// Video files through FFmpeg (see VideoFile.h).
#include "viewer/VideoFile.h"

#include "support/ReplacingFile.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <vector>

#include <llvm/Support/Path.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace lcjit::viewer {
namespace {

// lcjit does not link FFmpeg: its libraries bring some 130 shared libraries (codecs, VA-API,
// OpenCL …) that cost every start-up about 25 ms to map and relocate (a program that only
// links them, against one that does not: hyperfine, 26.6 ms against 0.6 ms), far more than a
// cached lcjit run takes. They are opened with dlopen when the first video is, by the sonames of
// the headers compiled against; the functions used are looked up by name into this table.
enum Library { avutil, avcodec, avformat, swscale, kLibraries };
#define LCJIT_STRING2(x) #x
#define LCJIT_STRING(x) LCJIT_STRING2(x)
const char* const kSonames[kLibraries] = {
    "libavutil.so." LCJIT_STRING(LIBAVUTIL_VERSION_MAJOR), "libavcodec.so." LCJIT_STRING(LIBAVCODEC_VERSION_MAJOR),
    "libavformat.so." LCJIT_STRING(LIBAVFORMAT_VERSION_MAJOR), "libswscale.so." LCJIT_STRING(LIBSWSCALE_VERSION_MAJOR)};

#define LCJIT_FFMPEG_FUNCTIONS(X)                                                                                  \
  X(avutil, av_strerror) X(avutil, av_frame_alloc) X(avutil, av_frame_free) X(avutil, av_frame_get_buffer)         \
  X(avutil, av_frame_make_writable) X(avutil, av_opt_set) X(avutil, av_log_set_level)                              \
  X(avcodec, avcodec_find_encoder_by_name) X(avcodec, avcodec_find_encoder) X(avcodec, avcodec_alloc_context3)     \
  X(avcodec, avcodec_open2) X(avcodec, avcodec_free_context) X(avcodec, avcodec_parameters_from_context)           \
  X(avcodec, avcodec_send_frame) X(avcodec, avcodec_receive_packet) X(avcodec, av_packet_alloc)                    \
  X(avcodec, av_packet_free) X(avcodec, av_packet_rescale_ts)                                                      \
  X(avformat, avformat_alloc_output_context2) X(avformat, avformat_new_stream) X(avformat, avformat_write_header)   \
  X(avformat, av_interleaved_write_frame) X(avformat, av_write_trailer) X(avformat, avio_open)                     \
  X(avformat, avio_closep) X(avformat, avformat_free_context)                                                      \
  X(swscale, sws_getContext) X(swscale, sws_scale) X(swscale, sws_freeContext)

struct FFmpeg {
#define LCJIT_POINTER(lib, name) decltype(&::name) name = nullptr;
  LCJIT_FFMPEG_FUNCTIONS(LCJIT_POINTER)
#undef LCJIT_POINTER
};

// Loaded once per process; the libraries stay (FFmpeg keeps global state).
llvm::Expected<const FFmpeg*> loadFFmpeg() {
  static std::once_flag once;
  static FFmpeg ff;
  static std::string error;
  std::call_once(once, [] {
    void* handles[kLibraries] = {};
    for (int i = 0; i < kLibraries; ++i)
      if (!(handles[i] = ::dlopen(kSonames[i], RTLD_NOW | RTLD_LOCAL))) {
        error = std::string("cannot load FFmpeg: ") + ::dlerror() +
                " (install libavcodec59, libavformat59, libavutil57 and libswscale6; ./setup.sh does)";
        return;
      }
#define LCJIT_LOAD(lib, name)                                                                              \
  if (!(ff.name = reinterpret_cast<decltype(ff.name)>(::dlsym(handles[lib], #name)))) {                    \
    error = std::string("cannot load FFmpeg: ") + kSonames[lib] + " has no " #name;                        \
    return;                                                                                                \
  }
    LCJIT_FFMPEG_FUNCTIONS(LCJIT_LOAD)
#undef LCJIT_LOAD
    // FFmpeg's own notes (x264's statistics, …) would mix with lcjit's messages; errors come
    // back as return codes and are said in lcjit's words.
    ff.av_log_set_level(AV_LOG_QUIET);
  });
  if (!error.empty()) return llvm::createStringError(error);
  return &ff;
}

std::string lowerExtension(const std::string& path) { return llvm::sys::path::extension(path).drop_front().lower(); }

}  // namespace

struct VideoWriter::Impl {
  const FFmpeg& ff;
  std::string path;
  VideoOptions options;
  const AVCodec* codec = nullptr;
  AVFormatContext* format = nullptr;
  AVCodecContext* context = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scale = nullptr;
  int width = 0, height = 0;  // the pictures'; the video's are rounded up to even
  int frames = 0;
  bool headerWritten = false, broken = false, finished = false;
  std::vector<uint8_t> padded;
  support::ReplacingFile target;  // put in place by finish(): a player never opens half a video

  Impl(const FFmpeg& f, std::string p, const VideoOptions& o) : ff(f), path(std::move(p)), options(o), target(path) {}
  ~Impl() {
    if (scale) ff.sws_freeContext(scale);
    if (packet) ff.av_packet_free(&packet);
    if (frame) ff.av_frame_free(&frame);
    if (context) ff.avcodec_free_context(&context);
    if (format) {
      if (format->pb) ff.avio_closep(&format->pb);
      ff.avformat_free_context(format);
    }
  }

  llvm::Error fail(const std::string& what) const { return llvm::createStringError("cannot write " + path + ": " + what); }
  llvm::Error fail(const std::string& what, int code) const {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    if (ff.av_strerror(code, text, sizeof text) < 0) std::snprintf(text, sizeof text, "FFmpeg error %d", code);
    return fail(what + ": " + text);
  }

  // The encoder, its stream and the container's header, at the first picture's size.
  llvm::Error open(int w, int h) {
    width = w;
    height = h;
    if (!(context = ff.avcodec_alloc_context3(codec))) return fail("out of memory");
    context->width = w + (w & 1);
    context->height = h + (h & 1);
    context->pix_fmt = AV_PIX_FMT_YUV420P;
    context->time_base = AVRational{1, options.fps};
    context->framerate = AVRational{options.fps, 1};
    context->gop_size = 2 * options.fps;  // a key frame every two seconds, to seek to
    // swscale converts with BT.601's matrix into limited range: say so, so that players agree.
    context->colorspace = AVCOL_SPC_SMPTE170M;
    context->color_primaries = AVCOL_PRI_SMPTE170M;
    context->color_trc = AVCOL_TRC_SMPTE170M;
    context->color_range = AVCOL_RANGE_MPEG;
    if (format->oformat->flags & AVFMT_GLOBALHEADER) context->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    // Quality over size: pictures of plants have thin lines that coarse quantisers smear.
    const std::string name = codec->name;
    auto set = [&](const char* key, const char* value) { ff.av_opt_set(context->priv_data, key, value, 0); };
    if (name == "libx264") {
      set("preset", "medium");
      set("crf", "20");
    } else if (name == "libvpx-vp9") {
      context->bit_rate = 0;  // constant quality
      set("crf", "32");
      set("deadline", "good");
      set("cpu-used", "4");  // faster than the default (1): a recording should keep up with its frames
      set("row-mt", "1");
    } else if (name == "libvpx") {
      context->bit_rate = 8'000'000;  // VP8's crf is bounded by a bit rate
      set("crf", "10");
      set("deadline", "good");
      set("cpu-used", "4");
    } else {
      context->flags |= AV_CODEC_FLAG_QSCALE;
      context->global_quality = FF_QP2LAMBDA * 3;
    }
    if (int r = ff.avcodec_open2(context, codec, nullptr); r < 0) return fail("cannot open the " + name + " encoder", r);
    if (!(stream = ff.avformat_new_stream(format, nullptr))) return fail("out of memory");
    stream->time_base = context->time_base;
    if (int r = ff.avcodec_parameters_from_context(stream->codecpar, context); r < 0) return fail("encoder parameters", r);
    if (int r = ff.avformat_write_header(format, nullptr); r < 0) return fail("cannot write the header", r);
    headerWritten = true;
    if (!(frame = ff.av_frame_alloc()) || !(packet = ff.av_packet_alloc())) return fail("out of memory");
    frame->format = context->pix_fmt;
    frame->width = context->width;
    frame->height = context->height;
    if (int r = ff.av_frame_get_buffer(frame, 0); r < 0) return fail("out of memory", r);
    scale = ff.sws_getContext(context->width, context->height, AV_PIX_FMT_RGBA, context->width, context->height,
                              AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr);
    if (!scale) return fail("no conversion from RGBA to yuv420p");
    return llvm::Error::success();
  }

  // Sends `f` (nullptr: the end) and writes every packet the encoder has ready.
  llvm::Error encode(AVFrame* f) {
    if (int r = ff.avcodec_send_frame(context, f); r < 0) return fail("encoding failed", r);
    for (;;) {
      int r = ff.avcodec_receive_packet(context, packet);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) break;
      if (r < 0) return fail("encoding failed", r);
      // Every frame lasts one tick; without it mp4's edit list ends before the last frame.
      if (packet->duration == 0) packet->duration = 1;
      ff.av_packet_rescale_ts(packet, context->time_base, stream->time_base);
      packet->stream_index = stream->index;
      if (int w = ff.av_interleaved_write_frame(format, packet); w < 0) return fail("write failed", w);
    }
    if (format->pb->error < 0) return fail("write failed", format->pb->error);
    return llvm::Error::success();
  }

  llvm::Error add(const runtime::Image& image) {
    if (finished) return fail("the video is finished");
    if (broken) return fail("an earlier frame failed");
    if (image.width <= 0 || image.height <= 0 || image.rgba.size() < size_t(image.width) * image.height * 4)
      return fail("empty picture");
    if (!context) {
      if (auto e = open(image.width, image.height)) {
        broken = true;
        return e;
      }
    } else if (image.width != width || image.height != height) {
      return fail("frame " + std::to_string(frames + 1) + " is " + std::to_string(image.width) + "×" +
                  std::to_string(image.height) + " pixels; the video's frames are " + std::to_string(width) + "×" +
                  std::to_string(height));
    }
    // Copied into rows of a vector-aligned size (swscale reads whole vectors, past a row's end),
    // padded to the video's even size by repeating the last column and row.
    const int W = context->width, H = context->height, stride = (W * 4 + 63) / 64 * 64;
    padded.resize(size_t(stride) * H + 64);
    for (int y = 0; y < H; ++y) {
      const uint8_t* from = &image.rgba[size_t(std::min(y, height - 1)) * width * 4];
      uint8_t* to = &padded[size_t(y) * stride];
      std::memcpy(to, from, size_t(width) * 4);
      if (W != width) std::memcpy(to + size_t(width) * 4, from + size_t(width - 1) * 4, 4);
    }
    if (int r = ff.av_frame_make_writable(frame); r < 0) return fail("out of memory", r);
    const uint8_t* rows = padded.data();
    ff.sws_scale(scale, &rows, &stride, 0, H, frame->data, frame->linesize);
    frame->pts = frames;
    if (auto e = encode(frame)) {
      broken = true;
      return e;
    }
    ++frames;
    return llvm::Error::success();
  }

  llvm::Error finish() {
    if (std::exchange(finished, true)) return llvm::Error::success();
    if (!headerWritten) {
      // No frame (or no encoder for the first): no video, rather than a file no player opens.
      ff.avio_closep(&format->pb);
      target.abandon();
      return llvm::Error::success();
    }
    // After a failed frame, what was written is closed properly all the same.
    llvm::Error e = broken ? llvm::Error::success() : encode(nullptr);
    if (!e)
      if (int r = ff.av_write_trailer(format); r < 0) e = fail("cannot write the trailer", r);
    if (!e && format->pb->error < 0) e = fail("write failed", format->pb->error);
    if (int r = ff.avio_closep(&format->pb); r < 0 && !e) e = fail("write failed", r);
    if (e) return e;
    return target.commit();
  }
};

VideoWriter::VideoWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

VideoWriter::~VideoWriter() {
  if (impl_) llvm::consumeError(impl_->finish());
}

llvm::Expected<std::unique_ptr<VideoWriter>> VideoWriter::create(const std::string& path, const VideoOptions& options) {
  auto fail = [&](const std::string& what) { return llvm::createStringError("cannot write " + path + ": " + what); };
  const std::string ext = lowerExtension(path);
  if (ext != "mp4" && ext != "webm") return fail(std::string("unknown video type (use ") + kVideoFileTypes + ")");
  if (options.fps < 1 || options.fps > 1000) return fail("the frame rate must be 1 to 1000 frames per second");
  auto ff = loadFFmpeg();
  if (!ff) return fail(llvm::toString(ff.takeError()));
  auto impl = std::make_unique<Impl>(**ff, path, options);
  const bool mp4 = ext == "mp4";
  static const char* const kMp4[] = {"libx264", nullptr}, *const kWebm[] = {"libvpx-vp9", "libvpx", nullptr};
  for (const char* const* name = mp4 ? kMp4 : kWebm; *name && !impl->codec; ++name)
    impl->codec = impl->ff.avcodec_find_encoder_by_name(*name);
  if (!impl->codec && mp4) impl->codec = impl->ff.avcodec_find_encoder(AV_CODEC_ID_MPEG4);
  if (!impl->codec)
    return fail(std::string("this FFmpeg has no encoder for .") + ext +
                (mp4 ? " (libx264 or MPEG-4 part 2)" : " (libvpx: VP9 or VP8)"));
  if (int r = impl->ff.avformat_alloc_output_context2(&impl->format, nullptr, mp4 ? "mp4" : "webm", path.c_str()); r < 0)
    return impl->fail("no ." + ext + " muxer", r);
  // "file:": a name with a colon in it is a file, not an FFmpeg protocol.
  if (int r = impl->ff.avio_open(&impl->format->pb, ("file:" + impl->target.writePath()).c_str(), AVIO_FLAG_WRITE); r < 0)
    return impl->fail("cannot create the file", r);
  return std::unique_ptr<VideoWriter>(new VideoWriter(std::move(impl)));
}

llvm::Error VideoWriter::add(const runtime::Image& image) { return impl_->add(image); }
llvm::Error VideoWriter::finish() { return impl_->finish(); }
const std::string& VideoWriter::path() const { return impl_->path; }
std::string VideoWriter::codecName() const { return impl_->codec->name; }
int VideoWriter::frames() const { return impl_->frames; }

}  // namespace lcjit::viewer
