// The L-system string: a contiguous byte buffer of module records ([u16 id][params][u16 id]),
// plus the table of module descriptors needed to walk it in either direction.
#pragma once
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/include/lcjit/abi.h"

namespace lcjit::runtime {

// Owns a __lc_Buffer (the form model code appends to).
// Grows `b` to hold `extra` more bytes (at least doubling): the one way module strings grow,
// for the engine and for model code's successors (lcjit_buffer_reserve). (Transparent huge
// pages for large strings were tried: branching.l 92 -> 130 ms, 141 -> 198 MB.)
void growBuffer(__lc_Buffer& b, size_t extra);

class ModuleBuffer {
 public:
  ModuleBuffer() = default;
  ModuleBuffer(const ModuleBuffer&) = delete;
  ModuleBuffer& operator=(const ModuleBuffer&) = delete;
  ModuleBuffer(ModuleBuffer&& o) noexcept : b_(o.b_) { o.b_ = {nullptr, 0, 0}; }
  ModuleBuffer& operator=(ModuleBuffer&& o) noexcept {
    std::swap(b_, o.b_);
    return *this;
  }
  ~ModuleBuffer() { std::free(b_.data); }

  __lc_Buffer* raw() { return &b_; }
  char* data() { return b_.data; }
  const char* data() const { return b_.data; }
  size_t size() const { return b_.size; }
  void clear() { b_.size = 0; }
  void resize(size_t n) {
    reserve(n > b_.size ? n - b_.size : 0);
    b_.size = n;
  }
  void reserve(size_t extra);
  void append(const char* p, size_t n) {
    if (n == 0) return;  // data may still be null: memcpy(null, p, 0) is undefined
    if (b_.cap - b_.size < n) reserve(n);
    std::memcpy(b_.data + b_.size, p, n);
    b_.size += n;
  }
  void swap(ModuleBuffer& o) { std::swap(b_, o.b_); }

 private:
  __lc_Buffer b_{nullptr, 0, 0};
};

// Descriptors of every module a model knows: predefined (ids 0-102) and user-declared.
class ModuleTable {
 public:
  ModuleTable();
  void setUserModules(const __lc_ModuleInfo* mods, uint32_t n);

  size_t count() const { return infos_.size(); }
  const __lc_ModuleInfo& info(__lc_ModuleId id) const { return infos_[id]; }
  uint32_t recordSize(__lc_ModuleId id) const { return recordSize_[id]; }
  bool valid(__lc_ModuleId id) const { return id < infos_.size(); }
  int find(const std::string& name) const;

  static __lc_ModuleId idAt(const char* rec) {
    __lc_ModuleId id;
    std::memcpy(&id, rec, 2);
    return id;
  }
  size_t next(const char* s, size_t pos) const { return pos + recordSize_[idAt(s + pos)]; }
  size_t prev(const char* s, size_t pos) const { return pos - recordSize_[idAt(s + pos - 2)]; }

  // Appends `Name` or `Name(p1,p2,...)` (floats %.9g, doubles %.17g).
  void format(const char* rec, std::string& out) const;
  // The names format() gives modules whose language shows them otherwise than by their L+C name
  // (XL: `G` for the model's XL_G, `[` for SB): `shown` maps an L+C name to the language's.
  // Null: the L+C names. Set again after setUserModules().
  using ShownName = std::string_view (*)(std::string_view);
  void showNames(ShownName shown);
  // Appends one parameter the same way; `rec` is the module's record.
  static void formatField(const __lc_Field& f, const char* rec, std::string& out);

 private:
  std::vector<__lc_ModuleInfo> infos_;
  std::vector<uint32_t> recordSize_;
  std::vector<size_t> nameLength_;  // format() appends names without a strlen each
  std::vector<std::string> shown_;  // by id, the language's name where it differs (showNames)
};

}  // namespace lcjit::runtime
