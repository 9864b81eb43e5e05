// The lcjit program's own code pages in this process: given back once a run's string dwarfs them.
#pragma once

#include <cstddef>

namespace lcjit::app {

// Unmaps the pages of the program's read-only segments (code, constants, unwind tables: ~110 MB
// of file, 25-35 MB of it touched by a run, most by the compiler and start-up) from this process,
// with madvise(MADV_DONTNEED). They stay in the page cache, shared with every other lcjit process;
// what the run still executes faults back in, a few hundred pages. Writable segments, relocated
// data among them, are left alone. Returns the bytes released from the mapping.
size_t releaseProgramPages();

// Once per process, when a string reaches kReleaseProgramPagesAt bytes: then the program's pages
// are a small share of the run's memory and faulting some back costs nothing measurable. A run
// of a small model pays nothing.
constexpr size_t kReleaseProgramPagesAt = 8u << 20;
void releaseProgramPagesOnceAt(size_t stringBytes);

}  // namespace lcjit::app
