// Outputs written one frame at a time: numbered files (`-out frame%04d.png`, any -out type with a
// printf number in its name, as Context Free numbers frames) or a video (`movie.mp4`,
// `movie.webm`: viewer/VideoFile.h). A batch run's -out (every step) and the window's Start
// recording (every frame shown, `--record`) both write through it.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <llvm/Support/Error.h>

#include "viewer/ImageFiles.h"

namespace lcjit::viewer {
class VideoWriter;
}

namespace lcjit::app {

// `pattern` with `number` in place of its one printf integer conversion (%d, %4d, %04d) in the
// file name; nullopt for a name without exactly one.
std::optional<std::string> numberedName(const std::string& pattern, int number);

// Whether `out` is written frame by frame: a numbered name or a video.
bool isFrameSequence(const std::string& out);

// What makes one frame: a whole file of the sequence's kind under a given name (numbered files),
// or the picture (a video's frame).
struct FrameSource {
  std::function<llvm::Error(const std::string& path)> writeFile;
  std::function<llvm::Expected<runtime::Image>()> picture;
};

class FrameSequence {
 public:
  // A video's file is created here: one that cannot be written fails before any frame is made.
  static llvm::Expected<std::unique_ptr<FrameSequence>> open(const std::string& out, int fps);
  ~FrameSequence();  // finishes a video that finish() did not (its errors are lost)

  // Frame `number` (numbered files are named by it; a video takes its frames in order).
  llvm::Error add(int number, const FrameSource& source);
  // Finishes a video (encoder flushed, trailer written); nothing for numbered files.
  llvm::Error finish();
  const std::string& out() const { return out_; }

 private:
  explicit FrameSequence(std::string out);
  std::string out_;
#if LCJIT_HAVE_RENDERING
  std::unique_ptr<viewer::VideoWriter> video_;
#endif
};

}  // namespace lcjit::app
