// The program's read-only segments released from this process (ProgramPages.h).
#include "app/batch/ProgramPages.h"

#include <elf.h>
#include <link.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>

namespace lcjit::app {

size_t releaseProgramPages() {
  size_t released = 0;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) -> int {
        const uintptr_t page = uintptr_t(::sysconf(_SC_PAGESIZE));
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          if (ph.p_type != PT_LOAD || (ph.p_flags & PF_W))
            continue;  // writable: relocated or written data, which the file does not hold
          uintptr_t begin = (info->dlpi_addr + ph.p_vaddr + page - 1) & ~(page - 1);
          uintptr_t end = (info->dlpi_addr + ph.p_vaddr + ph.p_filesz) & ~(page - 1);
          if (end > begin && ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED) == 0)
            *static_cast<size_t*>(out) += end - begin;
        }
        return 1;  // the first object is the program itself
      },
      &released);
  return released;
}

void releaseProgramPagesOnceAt(size_t stringBytes) {
  static std::atomic<bool> done{false};
  if (stringBytes >= kReleaseProgramPagesAt && !done.exchange(true))
    releaseProgramPages();
}

}  // namespace lcjit::app
