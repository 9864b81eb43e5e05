// Outputs written one frame at a time (see FrameSequence.h).
#include "app/common/FrameSequence.h"

#include <cstdio>
#include <filesystem>
#include <regex>

#if LCJIT_HAVE_RENDERING
#include "viewer/VideoFile.h"
#endif

namespace lcjit::app {

std::optional<std::string> numberedName(const std::string& pattern, int number) {
  static const std::regex conversion("%0?[0-9]{0,2}d");
  const std::string name = std::filesystem::path(pattern).filename().string();
  std::smatch m;
  if (!std::regex_search(name, m, conversion) || name.find('%', m.position(0) + m.length(0)) != std::string::npos ||
      name.find('%') != size_t(m.position(0)))
    return std::nullopt;
  char text[32];
  std::snprintf(text, sizeof text, m.str(0).c_str(), number);
  return (std::filesystem::path(pattern).parent_path() / (m.prefix().str() + text + m.suffix().str())).string();
}

// A video takes every frame into its one file, also when its name has a printf number in it.
bool isFrameSequence(const std::string& out) { return viewer::isVideoFileName(out) || numberedName(out, 0).has_value(); }

llvm::Expected<std::unique_ptr<FrameSequence>> FrameSequence::open(const std::string& out, int fps) {
  std::unique_ptr<FrameSequence> s(new FrameSequence(out));
  if (!viewer::isVideoFileName(out)) {
    if (!numberedName(out, 0))
      return llvm::createStringError("cannot write " + out + ": frames go to a video (" + viewer::kVideoFileTypes +
                                     ") or to numbered files (a name with one printf number, frame%04d.png)");
    return s;
  }
#if LCJIT_HAVE_RENDERING
  viewer::VideoOptions options;
  options.fps = fps;
  auto video = viewer::VideoWriter::create(out, options);
  if (!video) return video.takeError();
  s->video_ = std::move(*video);
  return s;
#else
  (void)fps;
  return llvm::createStringError("cannot write " + out + ": this lcjit was built without pictures "
                                 "(LCJIT_WITH_RENDERING=OFF), which a video is made of; strings, -dtf and the "
                                 "exports (.obj, .gltf, .svg …) work");
#endif
}

FrameSequence::FrameSequence(std::string out) : out_(std::move(out)) {}
FrameSequence::~FrameSequence() = default;

llvm::Error FrameSequence::add(int number, const FrameSource& source) {
#if LCJIT_HAVE_RENDERING
  if (video_) {
    auto picture = source.picture();
    if (!picture) return picture.takeError();
    return video_->add(*picture);
  }
#endif
  return source.writeFile(*numberedName(out_, number));
}

llvm::Error FrameSequence::finish() {
#if LCJIT_HAVE_RENDERING
  if (video_) return video_->finish();
#endif
  return llvm::Error::success();
}

}  // namespace lcjit::app
