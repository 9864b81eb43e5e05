// The shapes waiting to be expanded, each in a numbered slot (the expander's queue orders the
// slots by area). A design can hold millions at once (sierpinski at 2000 pixels: 1.6 million), and
// each is read once, in an order unrelated to the order it was made in: what is kept per shape is
// what differs from shape to shape, in as few cache lines as possible. The transform and colour
// are the shape's own; the rest of its state (z, time, colour target, blend) is mostly the same
// for every shape of a run, so it is kept once and shared by the shapes that have it. Internal
// to runtime/cfdg (Expander.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#include "runtime/include/lcjit/cfdg.h"
#include "support/HugePages.h"

namespace lcjit::runtime::cfdg {

class UnfinishedShapes {
 public:
  struct Shape {
    uint64_t seed = 0;
    int shape = 0;
    uint32_t rest = 0;  // the rest of its state: a record of rests_
    double own[10];     // sx, shy, shx, sy, tx, ty, then the colour's four values
    std::unique_ptr<double[]> params;  // the shape's parameter block (null for none)
  };

  // A new slot for `shape`; its number.
  uint32_t add(int shape, uint64_t seed, const __cf_State& s, std::unique_ptr<double[]> params) {
    uint32_t slot;
    if (!free_.empty()) {
      slot = free_.back();
      free_.pop_back();
    } else {
      slot = count_++;
      if ((slot & kChunkMask) == 0) chunks_.push_back(newChunk());
    }
    Shape& u = (*this)[slot];
    u.seed = seed;
    u.shape = shape;
    u.rest = shareRest(s);
    std::memcpy(u.own, &s.sx, sizeof(double) * 6);
    std::memcpy(u.own + 6, s.colour, sizeof(double) * 4);
    u.params = std::move(params);
    return slot;
  }
  Shape& operator[](uint32_t slot) { return chunks_[slot >> kChunkBits][slot & kChunkMask]; }
  ~UnfinishedShapes() {
    for (uint32_t slot = 0; slot < count_; ++slot) (*this)[slot].~Shape();
  }
  // The slot's state as it was given to add().
  void state(uint32_t slot, __cf_State& out) {
    const Shape& u = (*this)[slot];
    std::memcpy(&out.sx, u.own, sizeof(double) * 6);
    std::memcpy(out.colour, u.own + 6, sizeof(double) * 4);
    rests_[u.rest].to(out);
  }
  // The slot is free again (its shape was expanded).
  void release(uint32_t slot) {
    Shape& u = (*this)[slot];
    u.params.reset();
    Rest& r = rests_[u.rest];
    if (--r.users == 0) {
      freeRests_.push_back(u.rest);
      if (u.rest == lastRest_) lastRest_ = kNone;
    }
    free_.push_back(slot);
  }
  // Asks for the slot's memory ahead of reading it.
  void prefetch(uint32_t slot) {
    const char* p = reinterpret_cast<const char*>(&(*this)[slot]);
    __builtin_prefetch(p);
    __builtin_prefetch(p + sizeof(Shape) - 1);
  }
  uint32_t slotsMade() const { return count_; }
  // Where the chunks' memory comes from (HugePageArena::feedFrom).
  void feedFrom(support::HugePageReserve* reserve) { arena_.feedFrom(reserve); }

 private:
  // The state's values between the transform and the colour (z, time), and after the colour
  // (target, assign, blend), as bytes: shared only when equal to the bit.
  static constexpr size_t kFirst = offsetof(__cf_State, zsz), kFirstBytes = offsetof(__cf_State, colour) - kFirst;
  static constexpr size_t kSecond = offsetof(__cf_State, target), kSecondBytes = sizeof(__cf_State) - kSecond;
  struct Rest {
    unsigned char bytes[kFirstBytes + kSecondBytes];
    uint32_t users = 0;
    void from(const __cf_State& s) {
      std::memcpy(bytes, reinterpret_cast<const char*>(&s) + kFirst, kFirstBytes);
      std::memcpy(bytes + kFirstBytes, reinterpret_cast<const char*>(&s) + kSecond, kSecondBytes);
    }
    bool same(const __cf_State& s) const {
      return std::memcmp(bytes, reinterpret_cast<const char*>(&s) + kFirst, kFirstBytes) == 0 &&
             std::memcmp(bytes + kFirstBytes, reinterpret_cast<const char*>(&s) + kSecond, kSecondBytes) == 0;
    }
    void to(__cf_State& s) const {
      std::memcpy(reinterpret_cast<char*>(&s) + kFirst, bytes, kFirstBytes);
      std::memcpy(reinterpret_cast<char*>(&s) + kSecond, bytes + kFirstBytes, kSecondBytes);
    }
  };
  // The record of the last rest shared, when it has the same values; else a new one. A design
  // whose shapes all differ in z gets a record per waiting shape, no more than the slots it saves.
  uint32_t shareRest(const __cf_State& s) {
    if (lastRest_ != kNone && rests_[lastRest_].same(s)) {
      ++rests_[lastRest_].users;
      return lastRest_;
    }
    uint32_t r;
    if (!freeRests_.empty()) {
      r = freeRests_.back();
      freeRests_.pop_back();
    } else {
      r = uint32_t(rests_.size());
      rests_.emplace_back();
    }
    rests_[r].from(s);
    rests_[r].users = 1;
    lastRest_ = r;
    return r;
  }

  // Slots live in chunks that never move (a rule body adding shapes keeps its own in place), in
  // huge pages: a large design writes hundreds of megabytes of them.
  static constexpr uint32_t kChunkBits = 12, kChunk = 1u << kChunkBits, kChunkMask = kChunk - 1;
  static constexpr uint32_t kNone = UINT32_MAX;
  Shape* newChunk() {
    Shape* chunk = static_cast<Shape*>(arena_.take(sizeof(Shape) * kChunk, alignof(Shape)));
    for (uint32_t k = 0; k < kChunk; ++k) new (chunk + k) Shape;
    return chunk;
  }
  support::HugePageArena arena_;
  std::vector<Shape*> chunks_;
  uint32_t count_ = 0;
  std::vector<uint32_t> free_;
  std::vector<Rest> rests_;
  std::vector<uint32_t> freeRests_;
  uint32_t lastRest_ = kNone;
};

}  // namespace lcjit::runtime::cfdg
