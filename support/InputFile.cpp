// readInputFile (see the header): open with O_NONBLOCK, fstat the descriptor, refuse all but a
// regular file, then read as LLVM does.
#include "support/InputFile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <string>

#include <llvm/ADT/SmallString.h>

namespace lcjit::support {

namespace {

// What a refused file is instead of a regular file; 0 is no error.
enum class NotRegular { Fifo = 1, CharacterDevice, BlockDevice, Socket, Other };

class NotRegularCategory : public std::error_category {
 public:
  const char* name() const noexcept override { return "lcjit.input-file"; }
  std::string message(int kind) const override {
    switch (NotRegular(kind)) {
      case NotRegular::Fifo: return "not a regular file (a FIFO)";
      case NotRegular::CharacterDevice: return "not a regular file (a character device)";
      case NotRegular::BlockDevice: return "not a regular file (a block device)";
      case NotRegular::Socket: return "not a regular file (a socket)";
      case NotRegular::Other: break;
    }
    return "not a regular file";
  }
};

const NotRegularCategory& notRegularCategory() {
  static const NotRegularCategory category;
  return category;
}

// Why a file of mode `mode` is not read; none for a regular file.
std::error_code refusal(mode_t mode) {
  NotRegular kind;
  if (S_ISREG(mode)) return {};
  if (S_ISDIR(mode)) return std::make_error_code(std::errc::is_a_directory);  // as reading one says
  if (S_ISFIFO(mode)) kind = NotRegular::Fifo;
  else if (S_ISCHR(mode)) kind = NotRegular::CharacterDevice;
  else if (S_ISBLK(mode)) kind = NotRegular::BlockDevice;
  else if (S_ISSOCK(mode)) kind = NotRegular::Socket;
  else kind = NotRegular::Other;
  return {int(kind), notRegularCategory()};
}

std::error_code lastError() { return {errno, std::generic_category()}; }

}  // namespace

std::error_code inputRefusal(unsigned mode) { return refusal(mode_t(mode)); }

bool isNotRegularFile(std::error_code ec) { return ec.category() == notRegularCategory(); }

llvm::ErrorOr<std::unique_ptr<llvm::MemoryBuffer>> readInputFile(const llvm::Twine& path, bool nullTerminated,
                                                                 llvm::sys::fs::file_status* status) {
  llvm::SmallString<256> storage;
  const char* name = path.toNullTerminatedStringRef(storage).data();
  // A device is not even opened (opening some has effects: a terminal, a tape); what is opened
  // is checked again below, since the path may name something else by then.
  struct stat st {};
  if (::stat(name, &st) != 0) return lastError();
  if (std::error_code ec = refusal(st.st_mode)) return ec;
  // O_NONBLOCK: a FIFO put there meanwhile must not block the open (no writer would ever come).
  int fd;
  do fd = ::open(name, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  while (fd < 0 && errno == EINTR);
  if (fd < 0) return lastError();
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::fstat(fd, &st) != 0) return lastError();
  if (std::error_code ec = refusal(st.st_mode)) return ec;
  // A regular file never blocks; cleared all the same, for the file systems that honour it.
  if (int flags = ::fcntl(fd, F_GETFL); flags < 0 || ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0) return lastError();
  if (status) {
    if (std::error_code ec = llvm::sys::fs::status(fd, *status)) return ec;
  }
  return llvm::MemoryBuffer::getOpenFile(fd, path, uint64_t(st.st_size), nullTerminated);
}

}  // namespace lcjit::support
