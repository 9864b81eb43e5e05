// support/ReplacingFile: files written whole or not at all, beside the target and renamed
// over it; devices and symbolic links written in place.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/ReplacingFile.h"

namespace fs = std::filesystem;
using lcjit::support::ReplacingFile;
using lcjit::support::writeWholeFile;

namespace {

class ReplacingFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/lcjit-replacing-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir = tmpl;
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(dir)) n.push_back(e.path().filename().string());
    std::sort(n.begin(), n.end());
    return n;
  }
  fs::path dir;
};

TEST_F(ReplacingFileTest, TheTargetKeepsItsOldBytesUntilCommit) {
  ASSERT_FALSE(writeWholeFile(path("out.str"), "old\n"));
  ReplacingFile f(path("out.str"));
  EXPECT_NE(f.writePath(), path("out.str"));
  EXPECT_EQ(fs::path(f.writePath()).parent_path(), dir);  // beside it: the rename stays on one disk
  EXPECT_EQ(fs::path(f.writePath()).filename().string()[0], '.');  // hidden: frame*.png never matches it
  EXPECT_TRUE(ReplacingFile::isUnfinished(fs::path(f.writePath()).filename().string()));
  EXPECT_FALSE(ReplacingFile::isUnfinished("out.str"));
  std::ofstream(f.writePath()) << "new, half wri";
  EXPECT_EQ(read(path("out.str")), "old\n");  // a reader now still gets the whole old file
  std::ofstream(f.writePath()) << "new\n";
  ASSERT_FALSE(f.commit());
  EXPECT_EQ(read(path("out.str")), "new\n");
  EXPECT_EQ(names(), std::vector<std::string>{"out.str"});
}

TEST_F(ReplacingFileTest, AWriteNotCommittedLeavesTheOldFileAndNoOther) {
  ASSERT_FALSE(writeWholeFile(path("plant.png"), "last good picture"));
  {
    ReplacingFile f(path("plant.png"));
    std::ofstream(f.writePath()) << "a write that failed halfway";
  }
  EXPECT_EQ(read(path("plant.png")), "last good picture");
  EXPECT_EQ(names(), std::vector<std::string>{"plant.png"});
  {
    ReplacingFile f(path("new.png"));  // no old file: none afterwards either
  }
  EXPECT_EQ(names(), std::vector<std::string>{"plant.png"});
}

// A streamed write whose writer fails halfway (the turtle text's error, an encoder's): its error,
// the last good file, nothing beside it.
TEST_F(ReplacingFileTest, AStreamedWriteThatFailsKeepsTheLastGoodFile) {
  ASSERT_FALSE(writeWholeFile(path("plant.str"), "A(1)\n"));
  llvm::Error e = writeWholeFile(path("plant.str"), [](std::ostream& out) {
    out << "A(2)\nB(";
    return llvm::createStringError("plant.l:3: error: the writer stopped");
  });
  ASSERT_TRUE(bool(e));
  EXPECT_EQ(llvm::toString(std::move(e)), "plant.l:3: error: the writer stopped");
  EXPECT_EQ(read(path("plant.str")), "A(1)\n");
  EXPECT_EQ(names(), std::vector<std::string>{"plant.str"});
  ASSERT_FALSE(writeWholeFile(path("plant.str"), [](std::ostream& out) {
    out << "A(2)\n";
    return llvm::Error::success();
  }));
  EXPECT_EQ(read(path("plant.str")), "A(2)\n");
}

// What a writer killed before commit() leaves: removed by name, the target and others kept.
TEST_F(ReplacingFileTest, UnfinishedFilesOfATargetAreRemoved) {
  ASSERT_FALSE(writeWholeFile(path("tree.str"), "good"));
  ASSERT_FALSE(writeWholeFile(path("other.str"), "other"));
  std::string left, otherLeft;
  {
    ReplacingFile killed(path("tree.str")), other(path("other.str"));
    left = killed.writePath(), otherLeft = other.writePath();
    fs::copy_file(left, path("copy"));
    fs::copy_file(otherLeft, path("otherCopy"));
  }
  fs::rename(path("copy"), left);  // as if its writer had died
  fs::rename(path("otherCopy"), otherLeft);
  ReplacingFile::removeUnfinished(path("tree.str"));
  EXPECT_FALSE(fs::exists(left));
  EXPECT_TRUE(fs::exists(otherLeft));
  EXPECT_EQ(read(path("tree.str")), "good");
}

TEST_F(ReplacingFileTest, PermissionsOfTheOldFileStay) {
  ASSERT_FALSE(writeWholeFile(path("tree.vset"), "1\n"));
  fs::permissions(path("tree.vset"), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_FALSE(writeWholeFile(path("tree.vset"), "2\n"));
  EXPECT_EQ(read(path("tree.vset")), "2\n");
  EXPECT_EQ(fs::status(path("tree.vset")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

// A rename would replace the link itself, or (as root) the device node: both are written in place.
TEST_F(ReplacingFileTest, LinksAndDevicesAreWrittenInPlace) {
  ASSERT_FALSE(writeWholeFile(path("real.str"), "old"));
  fs::create_symlink(path("real.str"), path("link.str"));
  ASSERT_FALSE(writeWholeFile(path("link.str"), "through the link"));
  EXPECT_TRUE(fs::is_symlink(path("link.str")));
  EXPECT_EQ(read(path("real.str")), "through the link");
  ReplacingFile null("/dev/null");
  EXPECT_EQ(null.writePath(), "/dev/null");
  EXPECT_FALSE(null.commit());
  EXPECT_TRUE(fs::exists("/dev/null"));
  EXPECT_FALSE(fs::is_regular_file("/dev/null"));
}

TEST_F(ReplacingFileTest, AMissingFolderIsAClearError) {
  llvm::Error e = writeWholeFile(path("no/such/folder/out.str"), "x");
  ASSERT_TRUE(bool(e));
  EXPECT_EQ(llvm::toString(std::move(e)), path("no/such/folder/out.str") + ": error: cannot write file: No such file or directory");
}

}  // namespace
