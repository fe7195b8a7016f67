// Outputs that are not regular files (issue "Rules, not examples", docs/limits.md "Outputs"): every
// command that writes a file is given a FIFO, a character device and a symbolic link as its output.
// The FIFO, the device and the link must survive as what they were; the data goes where the user
// meant (read from the FIFO, through the link into its target) or the command refuses in one line.
// Before this, `video frame -o /dev/null` run as root replaced the machine's /dev/null by a PNG.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "refdata.h"
#include "run_command.h"

namespace {

namespace fs = std::filesystem;
using acro::testing::Execute;
using acro::testing::ProcessResult;
using acro::testing::Quote;

struct Writer {
  std::string name;
  std::string command;  // "{OUT}" is the output
  std::string extension;
  std::string starts_with;  // the output's first bytes, when they are known
};

fs::path Samples() {
  return acro::testing::SourceDir() / "samples";
}

std::string CommandLine(const Writer& w, const fs::path& out) {
  std::string line = w.command;
  line.replace(line.find("{OUT}"), 5, Quote(out));
  return std::string(ACROLAB_EXE) + " " + line + " >/dev/null";
}

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string LastLine(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const size_t at = t.rfind('\n');
  return at == std::string::npos ? t : t.substr(at + 1);
}

class SpecialOutputs : public ::testing::TestWithParam<Writer> {
 protected:
  void SetUp() override {
    dir_ = acro::testing::TempDir() / ("special_outputs_" + GetParam().name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const fs::path& Library() {
  // One library with the sample jump, for `library export`.
  static const fs::path path = [] {
    const fs::path lib = acro::testing::TempDir() / "special_outputs_library.sqlite";
    fs::remove(lib);
    const ProcessResult add =
        Execute(std::string(ACROLAB_EXE) + " library add --library " + Quote(lib) + " --athlete " +
                Quote(Samples() / "athletes/sample_athlete.yaml") + " " +
                Quote(Samples() / "trials/straight_jump/straight_jump.c3d") + " >/dev/null");
    EXPECT_EQ(add.status, 0) << add.err;
    return lib;
  }();
  return path;
}

TEST_P(SpecialOutputs, AFifoWithNoReaderIsRefusedAndStaysAFifo) {
  const Writer& w = GetParam();
  const fs::path fifo = dir_ / ("out" + w.extension);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const ProcessResult run = Execute("timeout 30 " + CommandLine(w, fifo));
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(LastLine(run.err).find("is a FIFO that no program reads"), std::string::npos)
      << run.err;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
}

TEST_P(SpecialOutputs, AFifoWithAReaderGetsTheOutputAndStaysAFifo) {
  const Writer& w = GetParam();
  const fs::path fifo = dir_ / ("out" + w.extension);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  // The reader is there before the command starts (opened without waiting for a writer).
  const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(fd, 0);
  std::atomic<bool> done{false};
  std::string received;
  std::thread reader([&] {
    char buffer[65536];
    for (;;) {
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n > 0) {
        received.append(buffer, static_cast<size_t>(n));
        continue;
      }
      if (done) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  const ProcessResult run = Execute("timeout 60 " + CommandLine(w, fifo));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  done = true;
  reader.join();
  ::close(fd);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  ASSERT_GT(received.size(), 100u);
  EXPECT_EQ(received.substr(0, w.starts_with.size()), w.starts_with);
}

TEST_P(SpecialOutputs, ADeviceIsWrittenThroughNeverReplaced) {
  if (::geteuid() != 0) GTEST_SKIP() << "making a device node needs root";
  const Writer& w = GetParam();
  // The null device (1, 3) and the full one (1, 7), made here: the machine's own are not risked.
  const fs::path null_device = dir_ / ("null" + w.extension);
  const fs::path full_device = dir_ / ("full" + w.extension);
  ASSERT_EQ(::mknod(null_device.c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
  ASSERT_EQ(::mknod(full_device.c_str(), S_IFCHR | 0666, makedev(1, 7)), 0);
  const ProcessResult to_null = Execute("timeout 60 " + CommandLine(w, null_device));
  EXPECT_EQ(to_null.status, 0) << to_null.err;
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(null_device)));
  const ProcessResult to_full = Execute("timeout 60 " + CommandLine(w, full_device));
  EXPECT_EQ(to_full.status, 1) << to_full.err;
  EXPECT_NE(LastLine(to_full.err).find("No space left on device"), std::string::npos)
      << to_full.err;
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status(full_device)));
  EXPECT_EQ(fs::status(full_device).permissions() & fs::perms::owner_write, fs::perms::owner_write);
}

TEST_P(SpecialOutputs, ALinkKeepsItsPlaceAndItsTargetGetsTheOutput) {
  const Writer& w = GetParam();
  fs::create_directories(dir_ / "elsewhere");
  const fs::path target = dir_ / "elsewhere" / ("real" + w.extension);
  const fs::path link = dir_ / ("out" + w.extension);
  { std::ofstream(target) << "old"; }
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink(fs::path("elsewhere") / target.filename(), link);
  const ProcessResult run = Execute("timeout 60 " + CommandLine(w, link));
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(fs::read_symlink(link), fs::path("elsewhere") / target.filename());
  const std::string written = ReadAll(target);
  ASSERT_GT(written.size(), 100u);
  EXPECT_EQ(written.substr(0, w.starts_with.size()), w.starts_with);
  // The file replaced behind the link keeps its permissions.
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  // And a dangling link makes its target.
  fs::remove(target);
  const ProcessResult again = Execute("timeout 60 " + CommandLine(w, link));
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_GT(fs::file_size(target), 100u);
}

std::vector<Writer> Writers() {
  const fs::path routine = Samples() / "trials/trampoline_routine";
  const std::string trial = Quote(routine / "trampoline_routine.c3d");
  const std::string calib = Quote(routine / "side_camera.toml");
  const std::string video = Quote(routine / "side_camera.mp4");
  // The side camera posed on the bed it sees (calibrate extrinsics --detect-bed).
  const std::string bed_camera = "calibrate extrinsics --points3d " + trial + " --intrinsics " +
                                 calib + " --detect-bed " + video + " --frame 100";
  const auto jump = [&](int k) {
    return Quote(fs::path((routine / "trampoline_routine.c3d").string() + ":" + std::to_string(k)));
  };
  return {
      {"convert", "convert " + trial + " {OUT}", ".trc", "PathFileType"},
      {"video_frame", "video frame " + video + " --frame 3 -o {OUT}", ".png", "\x89PNG"},
      {"project_csv", "project " + trial + " --calib " + calib + " --csv {OUT}", ".csv", "camera,"},
      {"sync_csv",
       "sync " + trial + " --calib " + calib + " --video " + video + " --csv {OUT}",
       ".csv",
       ""},
      {"overlay",
       "overlay " + trial + " --video " + video + " --calib " + calib + " --frames 0:5 -o {OUT}",
       ".mp4",
       ""},
      {"library_export", "library export --library " + Quote(Library()) + " -o {OUT}", ".csv", ""},
      {"library_query",
       "library query --library " + Quote(Library()) + " --csv -o {OUT}",
       ".csv",
       ""},
      {"calibrate_extrinsics", bed_camera + " -o {OUT}", ".toml", "[side]"},
      {"calibrate_corners",
       bed_camera + " --corners-csv {OUT} -o " +
           Quote(acro::testing::TempDir() / "special_outputs_corners_camera.toml"),
       ".csv",
       "name,u_px,v_px"},
      {"compare",
       "compare " + jump(2) + " " + jump(3) + " --athlete " +
           Quote(Samples() / "athletes/sample_athlete.yaml") + " -o {OUT}",
       ".mp4",
       ""},
  };
}

INSTANTIATE_TEST_SUITE_P(EveryWriter,
                         SpecialOutputs,
                         ::testing::ValuesIn(Writers()),
                         [](const ::testing::TestParamInfo<Writer>& param) {
                           return param.param.name;
                         });

// A command whose outputs are a folder (analyze's OutputTransaction): a file in it that is a link
// stays a link, its target rewritten.
TEST(SpecialOutputsInAFolder, ALinkedFileInTheOutputFolderStaysALink) {
  const fs::path dir = acro::testing::TempDir() / "special_outputs_folder";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  fs::create_directories(dir / "kept");
  { std::ofstream(dir / "kept/jumps.json") << "old"; }
  fs::create_symlink(dir / "kept/jumps.json", dir / "out/jumps.json");
  const ProcessResult run = Execute(std::string(ACROLAB_EXE) + " analyze " +
                                    Quote(Samples() / "trials/straight_jump/straight_jump.c3d") +
                                    " -o " + Quote(dir / "out") + " >/dev/null");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "out/jumps.json")));
  EXPECT_EQ(ReadAll(dir / "kept/jumps.json").substr(0, 1), "[");  // the jumps, not "old"
  EXPECT_TRUE(fs::is_regular_file(dir / "out/report.html"));
  fs::remove_all(dir);
}

}  // namespace
