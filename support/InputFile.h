// Every file lcjit reads as input (the model and the headers it includes, the view file and the
// files its lines name, colormaps, materials, contours, functions, surfaces, meshes, textures,
// terrains, a string loaded with LoadString, the cache's own files) is read here, and only if it
// is a regular file: a link to /dev/zero or /dev/urandom would be read without end (all of the
// machine's memory), and a FIFO would block its open() for ever. The file is opened without
// blocking and checked through its descriptor, so that what is read is what was checked.
#pragma once
#include <memory>
#include <system_error>

#include <llvm/ADT/Twine.h>
#include <llvm/Support/ErrorOr.h>
#include <llvm/Support/FileSystem.h>
#include <llvm/Support/MemoryBuffer.h>

namespace lcjit::support {

// The whole of the regular file `path`, as llvm::MemoryBuffer::getFile gives it (mapped when it
// is large, so no copy is made), named `path`; its status in `*status` if asked for. Errors: the
// system's (no such file, permission denied), is_a_directory for a folder, or, for anything else
// that is not a regular file, a code whose message is "not a regular file (a FIFO)" ("(a
// character device)", "(a block device)", "(a socket)").
llvm::ErrorOr<std::unique_ptr<llvm::MemoryBuffer>> readInputFile(const llvm::Twine& path, bool nullTerminated = true,
                                                                 llvm::sys::fs::file_status* status = nullptr);

// Why a file of mode `mode` (stat's st_mode) is not read as input, in readInputFile's words; none
// for a regular file. For who must judge a file without reading it (the sandbox's parent).
std::error_code inputRefusal(unsigned mode);

// Whether `ec` is readInputFile's refusal of something that is not a regular file.
bool isNotRegularFile(std::error_code ec);

}  // namespace lcjit::support
