// The window input model code reads (see WindowInput.h).
#include "runtime/WindowInput.h"

#include <algorithm>

namespace lcjit::runtime {

void UserMenu::add(const std::string& label, int code) {
  std::lock_guard<std::mutex> lock(mutex_);
  items_.emplace_back(label, code);
}

void UserMenu::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  items_.clear();
}

std::vector<std::pair<std::string, int>> UserMenu::items() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return items_;
}

void UserMenu::choose(int code) {
  std::lock_guard<std::mutex> lock(mutex_);
  choice_ = code;
}

int UserMenu::choice() {
  std::lock_guard<std::mutex> lock(mutex_);
  int c = choice_;
  choice_ = -1;
  return c;
}

void AnimationControl::set(bool AnimationRequests::*flag) {
  std::lock_guard<std::mutex> lock(mutex_);
  requests_.*flag = true;
}

AnimationRequests AnimationControl::take() {
  std::lock_guard<std::mutex> lock(mutex_);
  AnimationRequests r = requests_;
  requests_ = AnimationRequests();
  return r;
}

void Views::setBox(int id, V3f min, V3f max) {
  std::lock_guard<std::mutex> lock(mutex_);
  views_[id].min = min;
  views_[id].max = max;
}

void Views::setCamera(int id, const CameraPosition& camera) {
  std::lock_guard<std::mutex> lock(mutex_);
  views_[id].camera = camera;
  views_[id].hasCamera = true;
}

float Views::box(int id, int axis, bool max) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = views_.find(id);
  if (it == views_.end()) return 0;
  const V3f& v = max ? it->second.max : it->second.min;
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

float Views::scale(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = views_.find(id);
  return it != views_.end() && it->second.hasCamera ? it->second.camera.scale : 1;
}

CameraPosition Views::camera(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = views_.find(id);
  return it != views_.end() ? it->second.camera : CameraPosition{};
}

CameraPosition cameraPosition(V3f eye, V3f lookAt, V3f head, V3f up, float scale) {
  CameraPosition c{};
  c.position = eye;
  c.lookat = lookAt;
  c.head = head;
  c.up = up;
  c.left = head % up;
  c.scale = scale;
  return c;
}

CameraPosition initialWindowCamera(float viewScale) {
  return cameraPosition(V3f(0, 0, 1), V3f(0, 0, 0), V3f(0, 0, -1), V3f(0, 1, 0), viewScale);
}

void Mouse::update(const MouseStatus& s) {
  std::lock_guard<std::mutex> lock(mutex_);
  bool pushed = status_.lbPushed || s.lbPushed, released = status_.lbReleased || s.lbReleased;
  status_ = s;
  fed_ = true;
  status_.lbPushed = pushed;
  status_.lbReleased = released;
}

MouseStatus Mouse::take() {
  std::lock_guard<std::mutex> lock(mutex_);
  MouseStatus s = status_;
  status_.lbPushed = status_.lbReleased = false;
  read_ = true;
  return s;
}

bool Mouse::wasRead() {
  std::lock_guard<std::mutex> lock(mutex_);
  return read_;
}

TabletStatus Mouse::tablet() {
  std::lock_guard<std::mutex> lock(mutex_);
  TabletStatus t;
  read_ = true;
  if (!fed_) return t;
  t.connected = true;
  t.viewX = status_.viewX;
  t.viewY = status_.viewY;
  t.pressure = status_.lbDown ? 1 : 0;
  t.buttonState = status_.lbDown ? 1 : 0;
  t.atFront = status_.atFront;
  t.atRear = status_.atRear;
  return t;
}

float Tunables::codeValue(float value, float min, float max) {
  if (min > max) std::swap(min, max);
  return std::clamp(value, min, max);
}

float Tunables::get(const char* name, float value, float min, float max) {
  if (!name) return value;
  if (min > max) std::swap(min, max);
  std::lock_guard<std::mutex> lock(mutex_);
  for (Entry& e : entries_)
    if (e.name == name) {
      e.value = value, e.min = min, e.max = max;  // the code may have changed since
      return e.moved ? e.movedTo : codeValue(value, min, max);
    }
  entries_.push_back({name, value, min, max, false, 0});
  return codeValue(value, min, max);
}

std::vector<Tunables::Entry> Tunables::entries() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_;
}

void Tunables::move(const std::string& name, float to) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Entry& e : entries_)
    if (e.name == name) e.moved = true, e.movedTo = to;
}

void Tunables::reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Entry& e : entries_) e.moved = false;
}

}  // namespace lcjit::runtime
