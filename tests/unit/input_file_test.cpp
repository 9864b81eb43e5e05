// support/InputFile: only a regular file is read. A FIFO, a device (/dev/zero, /dev/urandom)
// or a socket is refused at once, by what it is, instead of blocking in open() or being read
// without end; a regular file is read whole, as before.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "runtime/files/AnimationFile.h"
#include "support/InputFile.h"

namespace fs = std::filesystem;
using lcjit::support::isNotRegularFile;
using lcjit::support::readInputFile;

namespace {

class InputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/lcjit-input-file-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir = tmpl;
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }

  // What `run` says, run in a child process with its memory and time bounded, so that a reader
  // that does not refuse shows as a failed test rather than a hang or all of the machine's
  // memory; or how the child ended. The time bound is one only a broken machine reaches.
  static std::string inChild(const std::function<std::string()>& run) {
    int out[2];
    if (pipe(out) != 0) return "no pipe";
    pid_t child = fork();
    if (child == 0) {
      close(out[0]);
      struct rlimit as = {size_t(1) << 30, size_t(1) << 30};
      setrlimit(RLIMIT_AS, &as);
      alarm(120);
      std::string said = run();
      (void)!write(out[1], said.data(), said.size());
      _exit(0);
    }
    close(out[1]);
    std::string said;
    char b[256];
    for (ssize_t n; (n = read(out[0], b, sizeof b)) > 0;) said.append(b, size_t(n));
    close(out[0]);
    int status = 0;
    waitpid(child, &status, 0);
    if (WIFSIGNALED(status)) return "killed by " + std::string(strsignal(WTERMSIG(status)));
    return said;
  }
  // What readInputFile says of `p`: "refused: WHY", "failed: WHY" or "read N bytes".
  static std::string outcome(const std::string& p) {
    return inChild([&] {
      auto buf = readInputFile(p);
      if (buf) return "read " + std::to_string((*buf)->getBufferSize()) + " bytes";
      return (isNotRegularFile(buf.getError()) ? "refused: " : "failed: ") + buf.getError().message();
    });
  }
  fs::path dir;
};

TEST_F(InputFileTest, ARegularFileIsReadWhole) {
  std::ofstream(path("a.s"), std::ios::binary) << "first\nsecond\n";
  llvm::sys::fs::file_status st;
  auto buf = readInputFile(path("a.s"), /*nullTerminated=*/true, &st);
  ASSERT_TRUE(buf) << buf.getError().message();
  EXPECT_EQ((*buf)->getBuffer(), "first\nsecond\n");
  EXPECT_EQ((*buf)->getBufferIdentifier(), path("a.s"));
  EXPECT_EQ(st.getSize(), 13u);
  EXPECT_EQ(st.type(), llvm::sys::fs::file_type::regular_file);
  // Through a symbolic link to a regular file: what it names is read.
  fs::create_symlink(path("a.s"), path("link.s"));
  EXPECT_EQ(outcome(path("link.s")), "read 13 bytes");
  std::ofstream(path("empty.s"));
  EXPECT_EQ(outcome(path("empty.s")), "read 0 bytes");
}

TEST_F(InputFileTest, AMissingFileOrAFolderFailsAsReadingItDid) {
  auto missing = readInputFile(path("absent.s"));
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.getError(), std::errc::no_such_file_or_directory);
  EXPECT_FALSE(isNotRegularFile(missing.getError()));
  auto folder = readInputFile(dir.string());
  ASSERT_FALSE(folder);
  EXPECT_EQ(folder.getError(), std::errc::is_a_directory);
}

TEST_F(InputFileTest, AFifoIsRefusedWithoutWaitingForAWriter) {
  ASSERT_EQ(mkfifo(path("leaf.s").c_str(), 0600), 0);
  EXPECT_EQ(outcome(path("leaf.s")), "refused: not a regular file (a FIFO)");
}

TEST_F(InputFileTest, DevicesAreRefusedNotReadWithoutEnd) {
  EXPECT_EQ(outcome("/dev/zero"), "refused: not a regular file (a character device)");
  fs::create_symlink("/dev/zero", path("leaf.s"));
  EXPECT_EQ(outcome(path("leaf.s")), "refused: not a regular file (a character device)");
  fs::create_symlink("/dev/urandom", path("petal.s"));
  EXPECT_EQ(outcome(path("petal.s")), "refused: not a regular file (a character device)");
}

TEST_F(InputFileTest, ASocketIsRefused) {
  int s = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  const std::string p = path("leaf.s");
  ASSERT_LT(p.size(), sizeof a.sun_path);
  std::strcpy(a.sun_path, p.c_str());
  ASSERT_EQ(bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << std::strerror(errno);
  EXPECT_EQ(outcome(p), "refused: not a regular file (a socket)");
  close(s);
}

// The animation file is read only by the window (not by -b): its refusal is one warning, and
// lpfg's defaults apply.
TEST_F(InputFileTest, AnAnimationFileThatIsAFifoIsAWarning) {
  ASSERT_EQ(mkfifo(path("plant.a").c_str(), 0600), 0);
  // The warnings, one a line, and the step the settings have (lpfg's default: 1).
  auto load = [&](const std::string& p) {
    return inChild([&] {
      std::vector<std::string> warnings;
      std::string said = "step " + std::to_string(lcjit::runtime::loadAnimationFile(p, warnings).step) + "\n";
      for (const std::string& w : warnings) said += w + "\n";
      return said;
    });
  };
  EXPECT_EQ(load(path("plant.a")),
            "step 1\n" + path("plant.a") +
                ": warning: cannot open file: not a regular file (a FIFO); lpfg's animation defaults are used\n");
  std::ofstream(path("good.a")) << "step: 3\n";
  EXPECT_EQ(load(path("good.a")), "step 3\n");
}

}  // namespace
