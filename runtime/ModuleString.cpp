// Module buffers, descriptors and the text form of modules (see ModuleString.h).
#include "runtime/ModuleString.h"

#include "runtime/NumberText.h"

#include <charconv>
#include <algorithm>
#include <new>

namespace lcjit::runtime {

void growBuffer(__lc_Buffer& b, size_t extra) {
  if (b.cap - b.size >= extra) return;
  size_t cap = std::max<size_t>({b.cap * 2, b.size + extra, size_t(4096)});
  char* d = static_cast<char*>(std::realloc(b.data, cap));
  if (!d) throw std::bad_alloc();
  b.data = d;
  b.cap = cap;
}

void ModuleBuffer::reserve(size_t extra) { growBuffer(b_, extra); }

ModuleTable::ModuleTable() { setUserModules(nullptr, 0); }

void ModuleTable::setUserModules(const __lc_ModuleInfo* mods, uint32_t n) {
  infos_.assign(__lc_stdmods, __lc_stdmods + __lc_FirstUserModule);
  infos_.insert(infos_.end(), mods, mods + n);
  recordSize_.clear();
  nameLength_.clear();
  for (auto& m : infos_) {
    recordSize_.push_back(m.recordSize);
    nameLength_.push_back(std::strlen(m.name));
  }
}

int ModuleTable::find(const std::string& name) const {
  for (size_t i = 0; i < infos_.size(); ++i)
    if (name == infos_[i].name) return (int)i;
  return -1;
}

namespace {

template <class T> void number(std::string& out, T v, int precision = 0) {
  char buf[64];
  if constexpr (std::is_floating_point_v<T>)
    out.append(buf, printfG(buf, v, precision));
  else
    out.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

template <class T> T get(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <class V> void vec(std::string& out, const char* p, int n, int precision) {
  using T = decltype(V().x);
  out += '(';
  for (int i = 0; i < n; ++i) {
    if (i) out += ',';
    number(out, get<T>(p + i * sizeof(T)), precision);
  }
  out += ')';
}

void field(std::string& out, const __lc_Field& f, const char* p) {
  switch (f.kind) {
    case __lc_FK_Bool: out += get<bool>(p) ? '1' : '0'; break;
    case __lc_FK_Char: number(out, (int)get<char>(p)); break;
    case __lc_FK_Signed:
      if (f.size == 1) number(out, (int)get<int8_t>(p));
      else if (f.size == 2) number(out, get<int16_t>(p));
      else if (f.size == 4) number(out, get<int32_t>(p));
      else number(out, get<int64_t>(p));
      break;
    case __lc_FK_Unsigned:
      if (f.size == 1) number(out, (unsigned)get<uint8_t>(p));
      else if (f.size == 2) number(out, get<uint16_t>(p));
      else if (f.size == 4) number(out, get<uint32_t>(p));
      else number(out, get<uint64_t>(p));
      break;
    case __lc_FK_Float: number(out, get<float>(p), 9); break;
    case __lc_FK_Double: number(out, get<double>(p), 17); break;
    case __lc_FK_V2f: vec<V2f>(out, p, 2, 9); break;
    case __lc_FK_V2d: vec<V2d>(out, p, 2, 17); break;
    case __lc_FK_V3f: vec<V3f>(out, p, 3, 9); break;
    case __lc_FK_V3d: vec<V3d>(out, p, 3, 17); break;
    case __lc_FK_Text: {
      const char* s = get<const char*>(p);
      out += '"';
      if (s) out += s;
      out += '"';
      break;
    }
    default:
      out += '<';
      out += f.typeName;
      out += '>';
  }
}

}  // namespace

void ModuleTable::formatField(const __lc_Field& f, const char* rec, std::string& out) { field(out, f, rec + f.offset); }

void ModuleTable::showNames(ShownName shown) {
  shown_.assign(infos_.size(), std::string());
  if (!shown) return;
  for (size_t id = 0; id < infos_.size(); ++id) {
    std::string_view name(infos_[id].name, nameLength_[id]);
    if (std::string_view s = shown(name); s != name) shown_[id] = s;
  }
}

void ModuleTable::format(const char* rec, std::string& out) const {
  const __lc_ModuleId id = idAt(rec);
  const __lc_ModuleInfo& m = infos_[id];
  if (id < shown_.size() && !shown_[id].empty()) out += shown_[id];
  else out.append(m.name, nameLength_[id]);
  if (m.nFields == 0) return;
  out += '(';
  for (uint32_t i = 0; i < m.nFields; ++i) {
    if (i) out += ',';
    field(out, m.fields[i], rec + m.fields[i].offset);
  }
  out += ')';
}

}  // namespace lcjit::runtime
