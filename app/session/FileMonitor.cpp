// Refresh policy (manual §1.2.2, §1.3) and the inotify file watcher. See FileMonitor.h.
#include "app/session/FileMonitor.h"

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace lcjit::app {

namespace fs = std::filesystem;

// ---- policy -----------------------------------------------------------------------------------

std::optional<RefreshMode> parseRefreshMode(std::string_view s) {
  if (s == "expl" || s == "explicit") return RefreshMode::Explicit;
  if (s == "cont" || s == "continuous") return RefreshMode::Continuous;
  if (s == "trig" || s == "triggered") return RefreshMode::Triggered;
  return std::nullopt;
}

const char* toString(Action a) {
  switch (a) {
    case Action::None: return "none";
    case Action::NewModel: return "New model";
    case Action::NewLsystem: return "New L-system";
    case Action::NewRun: return "New run";
    case Action::NewView: return "New view";
    case Action::NewRendering: return "New rendering";
    case Action::NewAnimate: return "New animate";
  }
  return "?";
}

Action actionForChange(FileKind k, RefreshMode mode) {
  if (mode == RefreshMode::Explicit) return Action::None;
  // §1.3 (Continuous and Triggered alike — lpfg has one "Triggered/Continuous" watcher).
  switch (k) {
    case FileKind::Model: return Action::NewLsystem;
    case FileKind::View: return Action::NewView;
    case FileKind::Animation: return Action::NewAnimate;  // "Rereads file only"
    case FileKind::Colormap:
    case FileKind::Material:
    case FileKind::Surface:
    case FileKind::Texture: return Action::NewRendering;
    case FileKind::Function:
    case FileKind::Contour:
    case FileKind::Timeline:
    case FileKind::Parameters: return Action::NewRun;
    // Not in lpfg's table (it restarts the program on New L-system only): a saved .e file
    // restarts the environmental program with the settings it now has.
    case FileKind::Environment: return Action::NewLsystem;
    case FileKind::Other: return Action::None;
  }
  return Action::None;
}

std::set<FileKind> filesReadBy(Action a) {
  const std::set<FileKind> rendering = {FileKind::Colormap, FileKind::Material, FileKind::Surface,
                                        FileKind::Texture};
  const std::set<FileKind> data = {FileKind::Function, FileKind::Contour, FileKind::Timeline,
                                   FileKind::Parameters};
  std::set<FileKind> out;
  switch (a) {
    case Action::None: break;
    case Action::NewModel:
      out = {FileKind::Model, FileKind::View, FileKind::Animation, FileKind::Environment};
      out.insert(rendering.begin(), rendering.end());
      out.insert(data.begin(), data.end());
      break;
    case Action::NewLsystem:
      out = {FileKind::Model, FileKind::Environment};
      out.insert(rendering.begin(), rendering.end());
      out.insert(data.begin(), data.end());
      break;
    case Action::NewRun:
      out = rendering;
      out.insert(data.begin(), data.end());
      break;
    case Action::NewView:
    case Action::NewRendering:
      out = rendering;
      out.insert(FileKind::View);
      break;
    case Action::NewAnimate: out = {FileKind::Animation}; break;
  }
  return out;
}

bool resetsView(Action a) { return a == Action::NewModel || a == Action::NewView; }
bool resetsRendering(Action a) {
  return a == Action::NewModel || a == Action::NewView || a == Action::NewRendering;
}
bool rerunsSimulation(Action a) {
  return a == Action::NewModel || a == Action::NewLsystem || a == Action::NewRun;
}

std::optional<ReloadParts> reloadPartsFor(Action a) {
  switch (a) {
    case Action::NewModel: return ReloadParts::all();
    case Action::NewLsystem: return ReloadParts::newLsystem();
    case Action::NewRun: return ReloadParts::newRun();
    case Action::NewView:
    case Action::NewRendering: return ReloadParts::newView();
    default: return std::nullopt;
  }
}

std::vector<Action> actionsForChanges(const std::vector<std::string>& paths, RefreshMode mode) {
  std::set<Action> acts;
  for (const auto& p : paths) {
    Action a = actionForChange(fileKindOf(p), mode);
    if (a != Action::None) acts.insert(a);
  }
  auto has = [&](Action a) { return acts.count(a) != 0; };
  if (has(Action::NewModel)) return {Action::NewModel};
  std::vector<Action> out;
  // The animation file first: its settings apply when the simulation re-runs.
  if (has(Action::NewAnimate)) out.push_back(Action::NewAnimate);
  // New L-system re-reads everything New run does (and re-runs).
  if (has(Action::NewLsystem)) out.push_back(Action::NewLsystem);
  else if (has(Action::NewRun)) out.push_back(Action::NewRun);
  // Neither re-reads the view file. New view re-reads everything New rendering does; New
  // L-system / New run re-read the colours, surfaces and textures New rendering is for.
  if (has(Action::NewView)) out.push_back(Action::NewView);
  else if (has(Action::NewRendering) && !has(Action::NewLsystem) && !has(Action::NewRun))
    out.push_back(Action::NewRendering);
  return out;
}

// ---- watcher ----------------------------------------------------------------------------------

namespace {
constexpr uint32_t kMask = IN_CLOSE_WRITE | IN_MODIFY | IN_MOVED_TO | IN_CREATE | IN_ATTRIB;
}

FileMonitor::FileMonitor(std::chrono::milliseconds quiet, std::chrono::milliseconds maxDelay)
    : quiet_(quiet), maxDelay_(std::max(maxDelay, quiet)) {}

FileMonitor::~FileMonitor() {
  if (fd_ >= 0) ::close(fd_);
}

bool FileMonitor::watch(const std::vector<std::string>& paths) {
  // The same inotify instance goes on (adding a directory it watches already gives the same
  // watch), and changes not yet reported stay pending for the files still watched: a save made
  // while the set is replaced (after a reload) is not lost.
  drain();
  std::map<std::string, Pending> stillPending;
  for (const auto& [index, p] : pending_) stillPending.emplace(paths_[index], p);
  paths_ = paths;
  byWatch_.clear();
  pending_.clear();
  error_.clear();
  if (paths.empty()) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    return true;
  }
  if (fd_ < 0) fd_ = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) {
    error_ = std::string("inotify_init1: ") + std::strerror(errno);
    return false;
  }
  for (size_t i = 0; i < paths.size(); ++i)
    if (auto it = stillPending.find(paths[i]); it != stillPending.end()) pending_.emplace(i, it->second);
  bool ok = true;
  auto add = [&](const fs::path& file, size_t index) {
    fs::path dir = file.parent_path();
    if (dir.empty()) dir = ".";
    std::string name = file.filename().string();
    if (name.empty() || name == "." || name == "..") {
      error_ += (error_.empty() ? "" : "; ") + file.string() + ": not a file name";
      ok = false;
      return;
    }
    int wd = ::inotify_add_watch(fd_, dir.c_str(), kMask | IN_ONLYDIR);
    if (wd < 0) {
      error_ += (error_.empty() ? "" : "; ") + dir.string() + ": " + std::strerror(errno);
      ok = false;
      return;
    }
    auto& idx = byWatch_[wd][name];
    if (std::find(idx.begin(), idx.end(), index) == idx.end()) idx.push_back(index);
  };
  for (size_t i = 0; i < paths.size(); ++i) {
    fs::path p(paths[i]);
    add(p, i);
    // A symbolic link: also watch the file it points to (an edit there changes the link's content).
    std::error_code ec;
    if (fs::is_symlink(p, ec)) {
      fs::path target = fs::canonical(p, ec);
      if (!ec) add(target, i);
    }
  }
  return ok;
}

void FileMonitor::drain() {
  if (fd_ < 0) return;
  alignas(struct inotify_event) char buf[16384];
  for (;;) {
    ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      return;  // EAGAIN: nothing more
    }
    auto now = Clock::now();
    // A write that closed the file, or a file renamed into place, is a finished save: it need
    // not wait out the quiet period (that would delay every reload by it). A later write to the
    // same file starts waiting again; a chmod after the save (IN_ATTRIB) changes nothing.
    auto mark = [&](size_t index, uint32_t mask) {
      auto [it, fresh] = pending_.try_emplace(index, Pending{now, now});
      it->second.last = now;
      if (mask & (IN_CLOSE_WRITE | IN_MOVED_TO)) it->second.saved = true;
      else if (mask & (IN_MODIFY | IN_CREATE)) it->second.saved = false;
    };
    for (ssize_t off = 0; off < n;) {
      const auto* ev = reinterpret_cast<const struct inotify_event*>(buf + off);
      off += ssize_t(sizeof(struct inotify_event) + ev->len);
      if (ev->mask & IN_Q_OVERFLOW) {  // events lost: assume everything changed
        for (size_t i = 0; i < paths_.size(); ++i) mark(i, 0);
        continue;
      }
      if (ev->mask & IN_IGNORED) {  // the directory went away
        byWatch_.erase(ev->wd);
        continue;
      }
      if (ev->len == 0 || (ev->mask & IN_ISDIR)) continue;
      auto w = byWatch_.find(ev->wd);
      if (w == byWatch_.end()) continue;
      auto f = w->second.find(ev->name);  // ev->name is NUL-terminated (padded)
      if (f == w->second.end()) continue;
      for (size_t index : f->second) mark(index, ev->mask);
    }
  }
}

FileMonitor::Clock::time_point FileMonitor::settlesAt(const Pending& p) const {
  if (p.saved) return p.last + kSavedQuiet;
  return std::min(p.last + quiet_, p.first + maxDelay_);
}

std::optional<FileMonitor::Clock::time_point> FileMonitor::readyAt() const {
  std::optional<Clock::time_point> best;
  for (const auto& [index, p] : pending_) {
    auto t = settlesAt(p);
    if (!best || t < *best) best = t;
  }
  return best;
}

std::vector<std::string> FileMonitor::takeReady(Clock::time_point now) {
  std::vector<std::string> out;
  for (auto it = pending_.begin(); it != pending_.end();) {
    const Pending& p = it->second;
    if (now >= settlesAt(p)) {
      out.push_back(paths_[it->first]);  // pending_ is ordered by index = watch() order
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  return out;
}

std::vector<std::string> FileMonitor::poll(int timeoutMs) {
  const auto start = Clock::now();
  const std::optional<Clock::time_point> deadline =
      timeoutMs < 0 ? std::nullopt : std::optional(start + std::chrono::milliseconds(timeoutMs));
  for (;;) {
    drain();
    auto now = Clock::now();
    auto ready = takeReady(now);
    if (!ready.empty()) return ready;
    if (deadline && now >= *deadline) return {};
    if (fd_ < 0 && pending_.empty() && !deadline) return {};  // nothing to wait for
    // Sleep until an event, the next pending change settles, or the deadline.
    std::optional<Clock::time_point> wake = readyAt();
    if (deadline && (!wake || *deadline < *wake)) wake = deadline;
    int waitMs = -1;
    if (wake) {
      auto d = std::chrono::duration_cast<std::chrono::milliseconds>(*wake - now).count() + 1;
      waitMs = int(std::clamp<long long>(d, 0, 1 << 30));
    }
    if (fd_ >= 0) {
      struct pollfd pfd{fd_, POLLIN, 0};
      int r = ::poll(&pfd, 1, waitMs);
      if (r < 0 && errno != EINTR) return {};
    } else if (waitMs > 0) {
      struct timespec ts{waitMs / 1000, (waitMs % 1000) * 1000000L};
      ::nanosleep(&ts, nullptr);
    }
  }
}

}  // namespace lcjit::app
