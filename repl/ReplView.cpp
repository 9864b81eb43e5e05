// The REPL's `:view` window (see ReplView.h).
//
// The window sleeps in its event wait while nothing happens; a helper thread watches stdin only
// to wake that wait when a key arrives, so that a typed key is still handled at once. Every GLFW
// call stays on the REPL's thread, where GLFW wants them.
#include "repl/ReplView.h"

#include "runtime/Engine.h"
#include "runtime/turtle/Drawing.h"

#if LCJIT_HAVE_WINDOW
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "app/common/Frame.h"
#include "viewer/Window.h"
#endif

namespace lcjit::repl {

#if LCJIT_HAVE_WINDOW

namespace {

// Wakes the window's event wait (Window::waitEvents) when stdin has input.
class InputWaker {
 public:
  InputWaker() : thread_([this] { loop(); }) {}
  ~InputWaker() {
    {
      std::lock_guard<std::mutex> l(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  // The main thread has read the input there was: watch for more.
  void consumed() {
    {
      std::lock_guard<std::mutex> l(mutex_);
      waiting_ = false;
    }
    cv_.notify_all();
  }

 private:
  void loop() {
    sigset_t all;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, nullptr);  // Ctrl-C is the main thread's
    std::unique_lock<std::mutex> l(mutex_);
    while (!stop_) {
      l.unlock();
      pollfd p{STDIN_FILENO, POLLIN, 0};
      int n = ::poll(&p, 1, 100);
      l.lock();
      if (n <= 0 || stop_) continue;
      waiting_ = true;
      viewer::Window::wake();
      // stdin stays readable until the main thread reads it; an end of input stays readable for
      // good, hence the time limit.
      cv_.wait_for(l, std::chrono::milliseconds(100), [this] { return !waiting_ || stop_; });
    }
  }

  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false, waiting_ = false;
  std::thread thread_;
};

}  // namespace

struct ReplView::Impl {
  std::unique_ptr<viewer::Window> window;
  std::unique_ptr<InputWaker> waker;  // after the window: destroyed first, as it wakes the window
  app::RenderLook look;
};

ReplView::ReplView() = default;
ReplView::~ReplView() = default;

llvm::Error ReplView::open(int width, int height, const std::string& title) {
  viewer::WindowOptions w;
  w.width = width;
  w.height = height;
  w.title = title;
  auto window = viewer::Window::create(w);
  if (!window) return window.takeError();
  impl_ = std::make_unique<Impl>();
  impl_->window = std::move(*window);
  impl_->waker = std::make_unique<InputWaker>();
  changed_ = true;
  return llvm::Error::success();
}

void ReplView::close() { impl_.reset(); }
bool ReplView::isOpen() const { return impl_ != nullptr; }

void ReplView::inputConsumed() {
  if (impl_) impl_->waker->consumed();
}

bool ReplView::pump(const Pump& p) {
  if (!impl_) return true;
  if (changed_) {
    runtime::Geometry geometry;
    p.report(p.engine.interpret(geometry));  // what was drawn before the fault still shows
    const app::RenderLook& look = impl_->look.of(p.drawing);
    impl_->window->setScene(geometry, p.drawing.view, look.palette, look.textures, viewer::Window::Framing::Refit);
    changed_ = false;
  }
  viewer::MenuActions actions;
  bool close = false;
  actions.exit = [&] { close = true; };
  actions.saveName = p.saveName;
  actions.saveAs = p.saveAs;
  if (!impl_->window->frame(actions) || close) {
    impl_.reset();
    return false;
  }
  impl_->window->waitEvents(0.1);
  return true;
}

#else  // a build without the window

struct ReplView::Impl {};
ReplView::ReplView() = default;
ReplView::~ReplView() = default;
llvm::Error ReplView::open(int, int, const std::string&) {
  return llvm::createStringError("this lcjit was built without the window (LCJIT_WITH_WINDOW=OFF)");
}
void ReplView::close() {}
bool ReplView::isOpen() const { return false; }
void ReplView::inputConsumed() {}
bool ReplView::pump(const Pump&) { return true; }

#endif

}  // namespace lcjit::repl
