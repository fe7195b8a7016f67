// Files in and out: reading refuses what is not a regular file before opening it (a FIFO would
// block forever), writing is atomic and leaves no temporary, output directories are checked
// before any work.

#include "acro/base/file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"
#include "input_errors.h"
#include "refdata.h"

namespace acro {
namespace {

namespace fs = std::filesystem;

TEST(FileIo, AFifoIsRefusedWithoutBlocking) {
  const fs::path dir = acro::testing::ScratchDir("file_io");
  const fs::path fifo = dir / "trial.trc";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string e = acro::testing::InputErrorOf([&] { ReadFileBytes(fifo, 1 << 20); });
  EXPECT_NE(e.find("trial.trc: is not a regular file"), std::string::npos) << e;
  EXPECT_NE(
      acro::testing::InputErrorOf([&] { ReadFileBytes(dir, 1 << 20); }).find("is a directory"),
      std::string::npos);
  EXPECT_NE(acro::testing::InputErrorOf([&] {
              ReadFileBytes(dir / "missing.trc", 1 << 20);
            }).find("cannot open"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(FileIo, AtomicWritesLeaveOnlyTheFile) {
  const fs::path dir = acro::testing::ScratchDir("file_io");
  WriteFileAtomically(dir / "a.txt", "hello");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "a.txt");
  }
  EXPECT_EQ(files, 1);
  const std::vector<std::uint8_t> back = ReadFileBytes(dir / "a.txt", 100);
  EXPECT_EQ(std::string(back.begin(), back.end()), "hello");
  fs::remove_all(dir);
}

TEST(FileIo, OutputDirectoriesAreCheckedWithoutBeingMade) {
  const fs::path dir = acro::testing::ScratchDir("file_io");
  CheckOutputDirectory(dir / "new" / "deeper");  // creatable: fine, and nothing made
  EXPECT_FALSE(fs::exists(dir / "new"));
  std::ofstream(dir / "file") << "x";
  EXPECT_NE(acro::testing::InputErrorOf([&] {
              CheckOutputDirectory(dir / "file");
            }).find("is a file, not a directory"),
            std::string::npos);
  EXPECT_NE(acro::testing::InputErrorOf([&] {
              CheckOutputDirectory(dir / "file" / "sub");
            }).find("is a file: the output"),
            std::string::npos);
  // No probe file is left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.path().filename() != "file";
  EXPECT_EQ(files, 0);
  CreateOutputDirectory(dir / "new" / "deeper");
  EXPECT_TRUE(fs::is_directory(dir / "new" / "deeper"));
  fs::remove_all(dir);
}

TEST(FileIo, RegisteredTemporariesAreRemovedOnRequest) {
  const fs::path dir = acro::testing::ScratchDir("file_io");
  std::ofstream(dir / ".out.tmp1") << "half";
  fs::create_directories(dir / "frames.tmp-1");
  std::ofstream(dir / "frames.tmp-1" / "frame_000000.png") << "png";
  {
    const ScopedTemporary a(dir / ".out.tmp1");
    const ScopedTemporary b(dir / "frames.tmp-1");
    EXPECT_EQ(RemoveRegisteredTemporaries(), 2);
  }
  EXPECT_FALSE(fs::exists(dir / ".out.tmp1"));
  EXPECT_FALSE(fs::exists(dir / "frames.tmp-1"));
  // Once unregistered, a path is not touched.
  std::ofstream(dir / "kept") << "x";
  { const ScopedTemporary c(dir / "kept"); }
  EXPECT_EQ(RemoveRegisteredTemporaries(), 0);
  EXPECT_TRUE(fs::exists(dir / "kept"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro
