// Video files: RGBA pictures of one size, one at a time, into .mp4 (H.264 through libx264, else
// MPEG-4 part 2) or .webm (VP9 through libvpx, else VP8), yuv420p, through FFmpeg's libraries.
// FFmpeg is loaded (dlopen) when the first video is opened, not when lcjit starts.
#pragma once
#include <memory>
#include <string>

#include <llvm/Support/Error.h>

#include "viewer/ImageFiles.h"

namespace lcjit::viewer {

struct VideoOptions {
  int fps = 25;  // frames per second of the file (every picture is one frame)
};

class VideoWriter {
 public:
  // Checks the name's type, loads FFmpeg, finds the encoder and creates the file, so that a
  // video that cannot be written fails before the first frame is made.
  static llvm::Expected<std::unique_ptr<VideoWriter>> create(const std::string& path, const VideoOptions& options = {});
  // Closes the file as finish() would, if that was not done (errors are lost: call finish()).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // One frame. The first sets the video's size; every later one must have it. yuv420p needs
  // even sizes: an odd width or height is padded by one column or row repeating the last.
  llvm::Error add(const runtime::Image& image);
  // Flushes the encoder and writes the container's trailer. A video that got no frame is removed.
  llvm::Error finish();

  const std::string& path() const;
  std::string codecName() const;  // the encoder's name, e.g. "libx264"
  int frames() const;             // added so far

  struct Impl;

 private:
  explicit VideoWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace lcjit::viewer
