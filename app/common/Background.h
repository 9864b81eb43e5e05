// A job on another thread whose result the caller picks up when it is ready, by polling: the
// model compiles (hot swap, the better tier) while the running one goes on. Starting a new job
// abandons the current one without waiting for it (a std::async future would block in its
// destructor): abandoned jobs finish on their own and are reaped by later polls; the
// destructor waits for all of them, so nothing they use may go away before this object.
#pragma once
#include <chrono>
#include <functional>
#include <future>
#include <optional>
#include <vector>

namespace lcjit::app {

template <class T>
class Background {
 public:
  Background() = default;
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  ~Background() {
    if (current_.valid()) current_.wait();
    for (auto& f : abandoned_) f.wait();
  }

  void start(std::function<T()> job) {
    if (current_.valid()) abandoned_.push_back(std::move(current_));
    current_ = std::async(std::launch::async, std::move(job));
  }
  bool running() const { return current_.valid(); }
  // The result of the current job once it has finished (then nothing is running).
  std::optional<T> take() {
    reap();
    if (!isReady(current_)) return std::nullopt;
    return current_.get();
  }

 private:
  static bool isReady(const std::future<T>& f) {
    return f.valid() && f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  }
  void reap() {
    std::erase_if(abandoned_, [](std::future<T>& f) {
      if (!isReady(f)) return false;
      f.get();  // T's destructor must cope with an unchecked result (e.g. consume an llvm::Error)
      return true;
    });
  }

  std::future<T> current_;
  std::vector<std::future<T>> abandoned_;
};

}  // namespace lcjit::app
