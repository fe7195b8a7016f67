// The robustness suite (issue "hardening", docs/limits.md): each class of bad input, made from the
// samples, given to the real acrolab binary. Every case asserts the exit status (1 for a bad file,
// 2 for a bad command line, 130/143 for a signal), the message's first words, that the command
// ends within 10 s under a 2 GB address-space limit, and that nothing is left behind: no output
// directory, no staging directory, no temporary file.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <nlohmann/json.hpp>

#include "acro/capture/c3d.h"
#include "acro/capture/trial.h"
#include "acro/capture/trial_io.h"
#include "refdata.h"
#include "run_command.h"

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;  // exit status, or 128 + the signal
  std::string err;
  double seconds = 0;
};

std::string Quote(const fs::path& p) {
  return "'" + p.string() + "'";
}

// AddressSanitizer reserves terabytes of address space for its shadow memory: under it
// (scripts/test.sh --sanitize) the address-space limit is left to the ordinary build, which
// asserts it, and ASan's own allocator limit stands in.
// The runs that must succeed (a reconstruction of the sample jump) take several times as long
// under it: their bound is raised; every bad input is still held to 10 s by Expect().
#if defined(__SANITIZE_ADDRESS__)
constexpr const char* kMemoryLimit = "";
constexpr const char* kTimeout = "timeout 120 ";
#else
constexpr const char* kMemoryLimit = "ulimit -v 2000000 && ";
constexpr const char* kTimeout = "timeout 10 ";
#endif

// Runs acrolab with `args` (shell words) under `timeout 10` and a 2 GB address-space limit (see
// above for ASan);
// stdout goes to `out` when given; `timeout` replaces the 10 s bound of runs that do real work.
Outcome Acrolab(const std::string& args,
                const fs::path& dir,
                std::string* out = nullptr,
                const char* timeout = kTimeout) {
  const fs::path err_path = dir / "stderr.txt";
  const fs::path out_path = dir / "stdout.txt";
  const std::string line =
      "cd " + Quote(dir) + " && " + kMemoryLimit + timeout + std::string(ACROLAB_EXE) + " " + args +
      " >" + (out ? Quote(out_path) : std::string("/dev/null")) + " 2>" + Quote(err_path);
  const auto start = std::chrono::steady_clock::now();
  const int raw = std::system(("sh -c " + Quote(line)).c_str());
  Outcome run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream err(err_path);
  run.err.assign(std::istreambuf_iterator<char>(err), {});
  fs::remove(err_path);
  if (out) {
    std::ifstream o(out_path, std::ios::binary);
    out->assign(std::istreambuf_iterator<char>(o), {});
    fs::remove(out_path);
  }
  return run;
}

using acro::testing::LastLine;

// Whatever a run left in `dir` besides the inputs in `keep`.
std::vector<std::string> Leftovers(const fs::path& dir, const std::vector<std::string>& keep) {
  std::vector<std::string> left;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (std::find(keep.begin(), keep.end(), name) == keep.end()) left.push_back(name);
  }
  return left;
}

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

fs::path Samples() {
  return acro::testing::SourceDir() / "samples";
}

// Starts acrolab with `args` in `dir` (after `in_child`, run in the child before the exec: its
// environment, its output), sends it SIGTERM after `after_s` and returns its exit status, or 128 +
// the signal that ended it.
// True once process `pid` blocks SIGTERM (bit 15 of SigBlk in /proc/PID/status), false while it
// does not or has gone.
bool TermBlocked(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigBlk:", 0) != 0) continue;
    const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
    return (mask >> (SIGTERM - 1)) & 1ULL;
  }
  return false;
}

// From when the SIGTERM delay counts: acrolab's handler in place, or the fork itself (a signal
// that may come while the dynamic loader still works, before any of acrolab's code runs).
enum class From { kHandler, kFork };

int TerminatedAfter(double after_s,
                    const fs::path& dir,
                    const std::vector<std::string>& args,
                    const std::function<void()>& in_child = {},
                    From from = From::kHandler) {
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    fs::current_path(dir);
    if (in_child) in_child();
    std::vector<char*> argv = {const_cast<char*>(ACROLAB_EXE)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(ACROLAB_EXE, argv.data());
    _exit(127);
  }
  // The clock starts once acrolab has its interrupt handling in place (SIGTERM blocked for the
  // thread that waits for it): before that the dynamic loader is still mapping ~290 libraries
  // (0.5 s here, over 1 s under ASan on a loaded machine), and a signal then is the default death
  // with nothing written (acro/base/interrupts.h). A timer from fork() made the test depend on
  // load. (From::kFork tests that case: the same status, and nothing left behind.)
  for (int waited_ms = 0; from == From::kHandler && waited_ms < 60000 && !TermBlocked(pid);
       waited_ms += 5)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::duration<double>(after_s));
  kill(pid, SIGTERM);
  int raw = 0;
  waitpid(pid, &raw, 0);
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
}

// A skill file of the samples, its athlete path made absolute, with `from` replaced by `to`.
std::string SkillWith(const std::string& from, const std::string& to) {
  std::string s = ReadText(Samples() / "skills" / "back_tuck.yaml");
  const std::string athlete = "../athletes/sample_athlete.yaml";
  s.replace(s.find(athlete), athlete.size(), (Samples() / "athletes/sample_athlete.yaml").string());
  if (!from.empty()) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
  }
  return s;
}

// The sample straight jump as a TRC with its rate (header line 3, columns 1, 2 and 6) replaced.
std::string TrcWithRate(const fs::path& dir, const std::string& rate) {
  const fs::path trc = dir / "jump.trc";
  if (!fs::exists(trc))
    acro::capture::WriteTrial(
        acro::capture::ReadTrial(Samples() / "trials/straight_jump/straight_jump.c3d"), trc);
  std::istringstream in(ReadText(trc));
  std::string out, line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 3) {
      std::vector<std::string> cells;
      std::istringstream row(line);
      for (std::string c; std::getline(row, c, '\t');) cells.push_back(c);
      cells[0] = cells[1] = cells[5] = rate;
      line.clear();
      for (size_t k = 0; k < cells.size(); ++k) line += (k ? "\t" : "") + cells[k];
    }
    out += line + "\n";
  }
  return out;
}

struct Case {
  const char* name;
  int status;
  const char* message;  // a fragment of the last line of stderr
};

class Robustness : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        acro::testing::ScratchDir(std::string("robustness_") +
                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  // Runs `args` in the scratch directory and checks the case; `inputs` are the files it made.
  void Expect(const Case& c, const std::string& args, const std::vector<std::string>& inputs) {
    SCOPED_TRACE(c.name);
    const Outcome run = Acrolab(args, dir_);
    EXPECT_EQ(run.status, c.status) << run.err;
    const std::string last = LastLine(run.err);
    EXPECT_NE(last.find(c.message), std::string::npos) << last;
    EXPECT_EQ(last.rfind("acrolab", 0), 0u) << last;  // one line of ours, not a library's dump
    EXPECT_LT(run.seconds, 10.0);
    EXPECT_EQ(Leftovers(dir_, inputs), std::vector<std::string>{}) << run.err;
    std::printf("%-28s exit %d in %.2f s: %s\n", c.name, run.status, run.seconds, last.c_str());
  }
  // `trc` reconstructed: it succeeds, and stderr holds the `warning`.
  void ExpectWarning(const std::string& trc, const std::string& warning) {
    WriteText(dir_ / "jump.trc", trc);
    const Outcome run = Acrolab("reconstruct jump.trc --quiet -o out", dir_);
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_NE(run.err.find(warning), std::string::npos) << run.err;
    fs::remove_all(dir_ / "out");
  }
  fs::path dir_;
};

TEST_F(Robustness, DeeplyNestedYaml) {
  WriteText(dir_ / "nested.yaml", "height_m: " + std::string(30000, '[') + "\n");
  Expect(
      {"30000 nested [", 1, "nested deeper than"}, "body --profile nested.yaml", {"nested.yaml"});
}

// Every parser of nested text has a depth check in front of it (acro/base/nesting.h): OpenCV's
// FileStorage crashed (SIGSEGV) on a calibration nested 100,000 deep. Each route, 10^5 levels.
TEST_F(Robustness, EveryNestedFormatDeepIsOneLine) {
  const fs::path routine = Samples() / "trials/trampoline_routine";
  const std::string trial = Quote(routine / "trampoline_routine.c3d");
  const int n = 100000;
  std::string open_xml;
  for (int i = 0; i < n; ++i) open_xml += "<a>";
  const std::vector<std::pair<std::string, std::string>> calibrations = {
      {"deep.yml", "%YAML:1.0\ncam: " + std::string(n, '[') + "\n"},
      {"deep.json", "{\"cam\": " + std::string(n, '[') + "\n"},
      {"deep.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>" + open_xml + "\n"},
      {"deep.toml", "[cam]\nmatrix = " + std::string(n, '[') + "\n"},
      {"deep.qca", "<?xml version=\"1.0\"?>\n<calibration>" + open_xml + "\n"},
  };
  std::vector<std::string> inputs;
  for (const auto& [file, text] : calibrations) {
    WriteText(dir_ / file, text);
    inputs.push_back(file);
    Expect({file.c_str(), 1, "nested deeper than 64 levels"},
           "project " + trial + " --calib " + file + " --csv out.csv",
           inputs);
  }
  // OpenPose JSON detections.
  fs::create_directories(dir_ / "detections");
  WriteText(dir_ / "detections/side_000000000000_keypoints.json", std::string(n, '['));
  inputs.push_back("detections");
  Expect({"detections", 1, "nested deeper than 64 levels"},
         "overlay --detections detections --video " + Quote(routine / "side_camera.mp4") +
             " -o out.mp4",
         inputs);
  // A link loop among them: the folder's fault, one line (was a filesystem exception, exit 3).
  fs::remove(dir_ / "detections/side_000000000000_keypoints.json");
  fs::create_symlink("loop_000000000001_keypoints.json",
                     dir_ / "detections/loop_000000000001_keypoints.json");
  Expect({"link loop", 1, "loop_000000000001_keypoints.json: cannot be read"},
         "overlay --detections detections --video " + Quote(routine / "side_camera.mp4") +
             " -o out.mp4",
         inputs);
}

// Every number option of every command is finite, and every time given by hand lands in the
// media (`--offset-s nan`, `--time nan`, `--event 1e300:0` were taken).
TEST_F(Robustness, TimesAndOffsetsAreFiniteAndInsideTheMedia) {
  const fs::path routine = Samples() / "trials/trampoline_routine";
  const std::string trial = Quote(routine / "trampoline_routine.c3d");
  const std::string video = Quote(routine / "side_camera.mp4");
  const std::string calib = Quote(routine / "side_camera.toml");
  Expect({"--time nan", 2, "--time: 'nan' is not a finite number"},
         "video frame " + video + " --time nan -o a.png",
         {});
  Expect({"--time 1e6", 2, "--time 1000000 s is outside the video's 0 … 9.967 s"},
         "video frame " + video + " --time 1e6 -o a.png",
         {});
  Expect({"--offset-s inf", 2, "--offset-s: 'inf' is not a finite number"},
         "project " + trial + " --calib " + calib + " --video " + video +
             " --offset-s inf --csv a.csv",
         {});
  Expect({"--offset-s 1e300", 1, "outside the video's 0 … 9.967 s"},
         "project " + trial + " --calib " + calib + " --video " + video +
             " --offset-s 1e300 --csv a.csv",
         {});
  Expect({"--event 1e300:0", 1, "outside the video's 0 … 9.967 s"},
         "overlay " + trial + " --calib " + calib + " --video " + video +
             " --event 1e300:0 --frames 0:5 -o a.mp4",
         {});
  Expect({"--height nan", 2, "--height: 'nan' is not a finite number"},
         "body --height nan --mass 60 --sex f",
         {});
  // An output extension that cannot be written: refused before any work.
  Expect({"-o x.avi", 2, ".avi cannot be written"},
         "overlay " + trial + " --calib " + calib + " --video " + video + " -o x.avi",
         {});
}

// One image-size policy for every command that puts the calibrated camera on a video: a scaled
// copy of the calibrated size is drawn with the camera scaled (said); any other size is refused in
// one line. A 320×240 proxy of the 1080p camera ended in "internal error: SceneRenderer: size
// -333 x -57 px" in overlay.
TEST_F(Robustness, VideosOfAnotherSizeThanTheCalibration) {
  const fs::path routine = Samples() / "trials/trampoline_routine";
  const std::string trial = Quote(routine / "trampoline_routine.c3d");
  const std::string calib = Quote(routine / "side_camera.toml");
  // Each size as a short lossless grey video (FFV1 takes any size, odd ones too; lavfi's colour
  // source refuses 1x1 itself, so each is scaled from 16x16).
  auto make = [&](const std::string& file, const std::string& size) {
    std::string scale = size;
    scale.replace(scale.find('x'), 1, ":");
    const std::string line =
        "ffmpeg -v error -y -f lavfi -i color=c=gray:s=16x16:r=30,scale=" + scale +
        " -t 1 -pix_fmt gray -c:v ffv1 " + Quote(dir_ / file) + " 2>&1";
    return std::system(line.c_str()) == 0;
  };
  if (!make("scaled.mkv", "320x180")) GTEST_SKIP() << "the ffmpeg command is not installed";
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"proxy.mkv", "320x240"}, {"dot.mkv", "1x1"}, {"strip.mkv", "16000x16"}};
  std::vector<std::string> inputs = {"scaled.mkv"};
  for (const auto& [file, size] : refused) {
    ASSERT_TRUE(make(file, size)) << size;
    inputs.push_back(file);
  }
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"overlay",
       "overlay " + trial + " --calib " + calib + " --video {V} --offset-s 0 -o out.mp4"},
      {"project", "project " + trial + " --calib " + calib + " --video {V} -o out.mp4"},
      {"sync", "sync " + trial + " --calib " + calib + " --video {V}"},
      {"analyze", "analyze " + trial + " --calib " + calib + " --video {V} --offset-s 0 -o out"},
  };
  for (const auto& [name, command] : commands) {
    for (const auto& [file, size] : refused) {
      std::string line = command;
      line.replace(line.find("{V}"), 3, file);
      Expect({(name + " " + size).c_str(), 1, "neither that size nor a scaled copy of it"},
             line,
             inputs);
    }
  }
  // The scaled copy: the camera scaled and said (project's CSV is quick to check).
  const Outcome run = Acrolab(
      "project " + trial + " --calib " + calib + " --video scaled.mkv --csv points.csv", dir_);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("the camera is scaled by 0.1667 to it"), std::string::npos) << run.err;
}

// A library another process holds locked: `library add` says at once that it waits and for how
// long, then refuses in one line when the lock outlives the wait (it sat silent for a minute, then
// said "database is locked").
TEST_F(Robustness, ALockedLibraryIsSaidAtOnce) {
  const std::string add = "library add --library lib.sqlite --athlete " +
                          Quote(Samples() / "athletes/sample_athlete.yaml") + " " +
                          Quote(Samples() / "trials/straight_jump/straight_jump.c3d");
  ASSERT_EQ(Acrolab(add, dir_).status, 0);
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open((dir_ / "lib.sqlite").c_str(), &holder), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(holder, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  ::setenv("ACROLAB_LIBRARY_WAIT_S", "2", 1);
  // --force: analysed again and written (an unchanged trial is only read, and WAL readers are
  // never blocked).
  const Outcome run = Acrolab(add + " --force --quiet", dir_);
  ::unsetenv("ACROLAB_LIBRARY_WAIT_S");
  sqlite3_exec(holder, "COMMIT", nullptr, nullptr, nullptr);
  sqlite3_close(holder);
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("lib.sqlite: locked by another process (a batch, a window or another add "
                         "writing to it); waiting up to 2 s"),
            std::string::npos)
      << run.err;
  EXPECT_NE(LastLine(run.err).find("is locked by another process, still after 2 s"),
            std::string::npos)
      << run.err;
  EXPECT_GT(run.seconds, 1.9);
  EXPECT_LT(run.seconds, 8.0);
  std::printf("locked library: exit %d in %.2f s: %s\n",
              run.status,
              run.seconds,
              LastLine(run.err).c_str());
}

TEST_F(Robustness, YamlWithManyKeys) {
  std::string keys;
  for (int i = 0; i < 200000; ++i)
    keys += "k" + std::to_string(i) + ": " + std::to_string(i) + "\n";
  WriteText(dir_ / "keys.yaml", ReadText(Samples() / "athletes/sample_athlete.yaml") + keys);
  Expect({"200000 keys", 1, "unknown key 'k0'"}, "body --profile keys.yaml", {"keys.yaml"});
}

TEST_F(Robustness, SkillFilesOutOfRange) {
  const std::string velocity = "  com_velocity_mps: [0, 0, 7.0]";
  const struct {
    Case c;
    std::string from, to;
  } cases[] = {
      {{"flight time .inf", 1, "a flight time of inf s, outside 0.2–4.0 s"},
       velocity,
       "  flight_time_s: .inf"},
      {{"flight time 1e6 s", 1, "outside 0.2–4.0 s"}, velocity, "  flight_time_s: 1e6"},
      {{"take-off 1e3 m/s up",
        1,
        "com_velocity_mps: the vertical velocity gives a flight time of 203.874 s"},
       velocity,
       "  com_velocity_mps: [0, 0, 1000]"},
      {{"time_s .nan", 1, "time_s: not finite"},
       "somersault_deg: -40",
       "somersault_deg: -40\n    time_s: .nan"},
      {{"somersault −40 → −250", 1, "somersault_deg changes by -210.0°"},
       "somersault_deg: -110",
       "somersault_deg: -250"},
      {{"angle 1e9°", 1, "somersault_deg: 1000000000.0° is outside ±3600°"},
       "somersault_deg: -110",
       "somersault_deg: 1e9"},
      {{"tolerance −1 m", 1, "tolerances: must be within"}, "position_m: 0.05", "position_m: -1"},
  };
  for (const auto& k : cases) {
    WriteText(dir_ / "skill.yaml", SkillWith(k.from, k.to));
    Expect(k.c, "optimize skill.yaml -o out", {"skill.yaml"});
  }
  // 20,000 keyframes.
  std::string many = SkillWith("", "");
  many.erase(many.find("keyframes:"));
  many += "keyframes:\n";
  for (int j = 0; j < 20000; ++j)
    many += "  - name: k" + std::to_string(j) +
            "\n    somersault_deg: " + std::to_string(-j * 330.0 / 19999) + "\n";
  WriteText(dir_ / "skill.yaml", many);
  Expect({"20000 keyframes", 1, "20000 keyframes; at most 100"},
         "optimize skill.yaml -o out",
         {"skill.yaml"});
}

TEST_F(Robustness, CommandLineMistakesExit2NamingTheOption) {
  const std::string skill = Quote(Samples() / "skills/back_tuck.yaml");
  Expect({"--intervals 2e9", 2, "--intervals"},
         "optimize " + skill + " --intervals 2000000000 -o out",
         {});
  Expect({"--intervals 4x", 2, "--intervals"}, "optimize " + skill + " --intervals 4x -o out", {});
  Expect({"--intervals 41", 2, "--intervals 41 is odd"},
         "optimize " + skill + " --intervals 41 -o out",
         {});
  WriteText(dir_ / "jump.trc", TrcWithRate(dir_, "200"));
  Expect({"--cutoff above Nyquist", 2, "--cutoff 150 Hz is at or above the trial's Nyquist"},
         "reconstruct jump.trc --cutoff 150 -o out",
         {"jump.trc"});
  Expect({"--height 170", 2, "--height"}, "analyze jump.trc --height 170 -o out", {"jump.trc"});
}

TEST_F(Robustness, TrialRatesOutOfRange) {
  for (const char* rate : {"1000000", "1e30", "9"}) {
    WriteText(dir_ / "jump.trc", TrcWithRate(dir_, rate));
    Expect({rate, 1, "rate"}, "analyze jump.trc -o out", {"jump.trc"});
  }
  // A rate of 0 or nan in the header: the time column's 200 Hz, with a warning the user sees.
  for (const char* rate : {"0", "nan"})
    ExpectWarning(TrcWithRate(dir_, rate),
                  "warning: jump.trc: header DataRate missing or not positive; 200.000000 Hz "
                  "taken from the time column");
}

// What a trial holds is checked once, in the pipeline, before any command uses it (issue "Rules,
// not examples"): each case is one line with the counts, exit 1, nothing written.
TEST_F(Robustness, TrialsWithNothingToUse) {
  const std::string trc = TrcWithRate(dir_, "200");
  std::vector<std::string> lines;
  std::istringstream in(trc);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  const std::vector<std::string> header(lines.begin(), lines.begin() + 5);
  std::vector<std::string> rows;
  for (auto l = lines.begin() + 5; l != lines.end(); ++l)
    if (!l->empty()) rows.push_back(*l);
  auto write = [&](const std::string& file, const std::vector<std::string>& body) {
    std::string out;
    for (const std::string& l : header) out += l + "\n";
    for (const std::string& l : body) out += l + "\n";
    WriteText(dir_ / file, out);
  };
  // Every coordinate of a row replaced by `value` (the frame number and time kept).
  auto with_coordinates = [](const std::string& row, const std::string& value) {
    std::istringstream cells(row);
    std::string out, cell;
    for (int k = 0; std::getline(cells, cell, '\t'); ++k)
      out += (k ? "\t" : "") + (k < 2 ? cell : value);
    return out;
  };
  write("one.trc", {rows[0]});
  Expect({"one frame", 1, "one.trc: holds 1 frame; the analysis needs at least 2"},
         "analyze one.trc -o out",
         {"jump.trc", "one.trc"});
  std::vector<std::string> nan_rows;
  for (const std::string& r : rows) nan_rows.push_back(with_coordinates(r, "NaN"));
  write("nan.trc", nan_rows);
  Expect({"all NaN", 1, "none of its 16 markers has a position in any of its 444 frames"},
         "analyze nan.trc -o out",
         {"jump.trc", "one.trc", "nan.trc"});
  // The first frame's pose held for the whole trial: no flight.
  std::vector<std::string> still;
  for (const std::string& r : rows) {
    const size_t time_end = r.find('\t', r.find('\t') + 1);
    still.push_back(r.substr(0, time_end) +
                    rows[0].substr(rows[0].find('\t', rows[0].find('\t') + 1)));
  }
  write("still.trc", still);
  Expect({"never leaves the floor", 1, "no flight in its 444 frames"},
         "analyze still.trc -o out",
         {"jump.trc", "one.trc", "nan.trc", "still.trc"});
  Expect({"never leaves the floor (library)", 1, "no flight in its 444 frames"},
         "library add --library lib.sqlite --athlete " +
             Quote(Samples() / "athletes/sample_athlete.yaml") + " still.trc",
         {"jump.trc", "one.trc", "nan.trc", "still.trc"});
  // A header naming 100,000 markers over 400 rows of one marker: refused before the 1 GB grid.
  {
    std::string big =
        lines[0] + "\n" + lines[1] + "\n200\t200\t400\t100000\tmm\t200\t1\t400\nFrame#\tTime";
    for (int m = 0; m < 100000; ++m) big += "\tM" + std::to_string(m) + "\t\t";
    big += "\n";
    for (int f = 0; f < 400; ++f)
      big += std::to_string(f + 1) + "\t" + std::to_string(f * 0.005) + "\t1\t2\t3\n";
    WriteText(dir_ / "names.trc", big);
    Expect({"100000 names over 400 rows", 1, "names 100000 markers over 400 rows"},
           "info names.trc",
           {"jump.trc", "one.trc", "nan.trc", "still.trc", "names.trc"});
  }
  // Infinite and absurd coordinates: gaps, said.
  std::vector<std::string> inf_rows = rows;
  inf_rows[10] = with_coordinates(rows[10], "inf");
  inf_rows[11] = with_coordinates(rows[11], "1e300");
  write("jump.trc", inf_rows);
  std::string out;
  const Outcome run = Acrolab("info jump.trc", dir_, &out);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(out.find("32 positions are not finite or farther than 10 km from the origin, read as "
                     "gaps (the first: HEAD at frame 11: (inf, inf, inf))"),
            std::string::npos)
      << out;
}

// POINT:SCALE 0 would scale every integer coordinate to 0 (and its sign gives the storage): the
// header's scale when it has one, said; refused when it has none.
TEST_F(Robustness, C3dPointScaleOfZero) {
  const acro::capture::Trial jump =
      acro::capture::ReadTrial(Samples() / "trials/straight_jump/straight_jump.c3d");
  std::vector<std::uint8_t> bytes = acro::capture::WriteC3dToMemory(jump);
  const float stored = static_cast<float>(*jump.parameters.FindDouble("POINT", "SCALE"));
  const std::string name = "SCALE";
  auto at = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  ASSERT_NE(at, bytes.end());
  std::array<std::uint8_t, 4> value;
  std::memcpy(value.data(), &stored, 4);
  at = std::search(at, bytes.end(), value.begin(), value.end());
  ASSERT_NE(at, bytes.end());
  std::fill(at, at + 4, 0);
  auto save = [&](const char* file) {
    std::ofstream(dir_ / file, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  };
  save("zero.c3d");
  std::string out;
  const Outcome run = Acrolab("info zero.c3d", dir_, &out);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(out.find("POINT:SCALE: is 0; the header's scale"), std::string::npos) << out;
  EXPECT_NE(out.find("float storage"), std::string::npos) << out;
  std::fill(bytes.begin() + 12, bytes.begin() + 16, 0);  // the header's copy (words 7–8)
  save("both.c3d");
  Expect({"POINT:SCALE 0 twice", 1, "POINT:SCALE: is 0 (and so is the header's)"},
         "info both.c3d",
         {"zero.c3d", "both.c3d"});
}

// Control bytes in a file reach the message escaped, never raw (an escape sequence would act on
// the terminal; a NUL byte cut the message short).
TEST_F(Robustness, ControlBytesInAFileAreEscaped) {
  std::string trc = TrcWithRate(dir_, "200");
  // The first data row's third coordinate cell: a terminal escape, a NUL byte and letters.
  size_t row = 0;
  for (int n = 0; n < 6; ++n) row = trc.find('\n', row) + 1;
  size_t cell = row;
  for (int n = 0; n < 4; ++n) cell = trc.find('\t', cell) + 1;
  trc.replace(cell, trc.find('\t', cell) - cell, std::string("1\x1b[2J\0x", 7));
  WriteText(dir_ / "jump.trc", trc);
  const Outcome run = Acrolab("info jump.trc", dir_);
  const std::string last = LastLine(run.err);
  std::printf("control bytes: exit %d: %s\n", run.status, last.c_str());
  EXPECT_EQ(run.err.find('\x1b'), std::string::npos) << last;
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(last.find("1\\x1b[2J\\x00x"), std::string::npos) << last;
}

// A TRC's structure against itself: a time column that goes back is an error naming the line;
// a marker name given twice, or a time column at another rate than the header's, is a warning
// the user sees (never a silent reinterpretation).
TEST_F(Robustness, TrcStructureIsChecked) {
  const std::string trc = TrcWithRate(dir_, "200");
  std::vector<std::string> lines;
  std::istringstream in(trc);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  auto join = [](const std::vector<std::string>& ls) {
    std::string out;
    for (const std::string& l : ls) out += l + "\n";
    return out;
  };
  auto cell = [](const std::string& line, int k) {
    size_t a = 0;
    for (int n = 0; n < k; ++n) a = line.find('\t', a) + 1;
    return std::pair<size_t, size_t>(a, line.find('\t', a) - a);
  };
  // Rows 8 and 9 (1-based lines) with their times exchanged.
  std::vector<std::string> back = lines;
  const auto t8 = cell(back[7], 1), t9 = cell(back[8], 1);
  const std::string time8 = back[7].substr(t8.first, t8.second);
  back[7].replace(t8.first, t8.second, back[8].substr(t9.first, t9.second));
  back[8].replace(t9.first, t9.second, time8);
  WriteText(dir_ / "jump.trc", join(back));
  Expect({"time going back", 1, "line 9, column 2: time"}, "info jump.trc", {"jump.trc"});
  // The second marker named as the first.
  std::vector<std::string> twice = lines;
  const auto n1 = cell(twice[3], 2), n2 = cell(twice[3], 5);
  const std::string first = twice[3].substr(n1.first, n1.second);
  twice[3].replace(n2.first, n2.second, first);
  ExpectWarning(join(twice), "line 4: marker name '" + first + "' repeats (markers 1 and 2)");
  // 100,000 markers of one name: read in well under the 10 s (pairwise comparison took minutes),
  // the first ten repeats said and the rest counted.
  {
    const int n = 100000;
    std::string big = lines[0] + "\n" + lines[1] + "\n100\t100\t2\t" + std::to_string(n) +
                      "\tmm\t100\t1\t2\nFrame#\tTime";
    for (int m = 0; m < n; ++m) big += "\tX\t\t";
    big += "\n";
    for (int f = 0; f < 2; ++f) {
      big += std::to_string(f + 1) + "\t" + std::to_string(f * 0.01);
      for (int m = 0; m < n; ++m) big += "\t1\t2\t3";
      big += "\n";
    }
    WriteText(dir_ / "names.trc", big);  // not jump.trc: TrcWithRate starts from that
    std::string out;
    const Outcome run = Acrolab("info names.trc", dir_, &out);
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_LT(run.seconds, 10.0);
    EXPECT_NE(out.find("99989 more repeated marker names"), std::string::npos);
    std::printf("100000 equal names: %.2f s\n", run.seconds);
  }
  // The header at 100 Hz, the time column at 200 Hz.
  ExpectWarning(TrcWithRate(dir_, "100"),
                "the time column runs at 200.000000 Hz but the header's DataRate is 100.000000 Hz");
}

// A C3D label in Latin-1 (an old Windows lab's "Genou_é"): valid UTF-8 in info --json, and the
// file's own bytes kept when the trial is written back.
TEST_F(Robustness, Latin1LabelsAreUtf8InJsonAndKeptInC3d) {
  acro::capture::Trial t;
  t.source.format = "generated";
  t.point_rate_hz = 100;
  t.num_frames = 3;
  t.points.push_back({"Genou_\xe9", "", acro::capture::PointType::kMarker, "m"});
  t.positions.setZero(3, 3);
  const std::vector<std::uint8_t> bytes = acro::capture::WriteC3dToMemory(t);
  std::ofstream(dir_ / "latin1.c3d", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  std::string json;
  const Outcome info = Acrolab("info --json latin1.c3d", dir_, &json);
  ASSERT_EQ(info.status, 0) << info.err;
  const nlohmann::json parsed = nlohmann::json::parse(json);  // throws on invalid UTF-8
  EXPECT_EQ(parsed["marker_labels"][0], "Genou_\xc3\xa9");    // é in UTF-8
  const Outcome convert = Acrolab("convert latin1.c3d back.c3d", dir_);
  ASSERT_EQ(convert.status, 0) << convert.err;
  const std::string written = ReadText(dir_ / "back.c3d");
  EXPECT_NE(written.find("Genou_\xe9"), std::string::npos);  // the file's byte, not transcoded
}

TEST_F(Robustness, PipesAndDirectoriesAreNotFiles) {
  ASSERT_EQ(mkfifo((dir_ / "fifo.trc").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((dir_ / "fifo.yaml").c_str(), 0600), 0);
  Expect({"FIFO as TRC", 1, "is not a regular file"}, "info fifo.trc", {"fifo.trc", "fifo.yaml"});
  Expect({"FIFO as profile", 1, "is not a regular file"},
         "body --profile fifo.yaml",
         {"fifo.trc", "fifo.yaml"});
}

TEST_F(Robustness, BadOutputPlacesFailBeforeAnyWork) {
  WriteText(dir_ / "existing", "");
  const std::string trial = Quote(Samples() / "trials/straight_jump/straight_jump.c3d");
  Expect({"-o an existing file", 1, "is a file, not a directory"},
         "analyze " + trial + " -o existing",
         {"existing"});
  fs::create_directory(dir_ / "readonly");
  fs::permissions(dir_ / "readonly", fs::perms::owner_read | fs::perms::owner_exec);
  if (geteuid() != 0) {  // root writes anywhere
    Expect({"-o in a read-only directory", 1, "cannot"},
           "analyze " + trial + " -o readonly/out",
           {"existing", "readonly"});
  }
  fs::permissions(dir_ / "readonly", fs::perms::owner_all);
}

// A failure after the work leaves no directory on the way to -o: here the analysis fails (a rate
// out of range) with -o two levels below directories that do not exist.
TEST_F(Robustness, AFailedRunCreatesNoDirectory) {
  WriteText(dir_ / "jump.trc", TrcWithRate(dir_, "9"));
  Expect({"-o new/deep/out, failing", 1, "rate"}, "analyze jump.trc -o new/deep/out", {"jump.trc"});
  // The same place for a run that succeeds: created, with the outputs in it and nothing beside.
  WriteText(dir_ / "jump.trc", TrcWithRate(dir_, "200"));
  const Outcome run = Acrolab("reconstruct jump.trc --quiet -o new/deep/out", dir_);
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir_ / "new/deep/out/jump.mot"));
  EXPECT_EQ(Leftovers(dir_, {"jump.trc", "new"}), std::vector<std::string>{});
  EXPECT_EQ(Leftovers(dir_ / "new/deep", {"out"}), std::vector<std::string>{});
}

TEST_F(Robustness, YeadonFileInTheWrongUnit) {
  std::string profile = ReadText(Samples() / "athletes/sample_athlete_yeadon.yaml");
  const std::string factor = "measurementconversionfactor: 0.01";
  profile.replace(profile.find(factor), factor.size(), "measurementconversionfactor: 1");
  WriteText(dir_ / "cm.yaml", profile);
  Expect({"Yeadon cm read as m", 1, "the measurements give an athlete of 175 m"},
         "body --profile cm.yaml",
         {"cm.yaml"});
}

// A 3 KB C3D with no points and no analog channels whose TRIAL:ACTUAL_END_FIELD declares 2³¹
// frames: nothing backs them; the reader reads none and convert says the trial is empty.
TEST_F(Robustness, C3dDeclaringTwoBillionEmptyFrames) {
  acro::capture::Trial t;
  t.source.format = "generated";
  t.point_rate_hz = 100;
  t.first_frame = 1;
  t.num_frames = 70000;  // > 65535: the writer stores TRIAL:ACTUAL_START/END_FIELD
  std::vector<std::uint8_t> bytes = acro::capture::WriteC3dToMemory(t);
  const std::string name = "ACTUAL_END_FIELD";
  auto at = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  ASSERT_NE(at, bytes.end());
  // Its value, [70000 & 0xffff, 70000 >> 16] as two 16-bit words, becomes [0xffff, 0x7fff].
  const std::array<std::uint8_t, 4> value = {0x70, 0x11, 0x01, 0x00};
  at = std::search(at, bytes.end(), value.begin(), value.end());
  ASSERT_NE(at, bytes.end());
  at[0] = 0xff, at[1] = 0xff, at[2] = 0xff, at[3] = 0x7f;
  std::ofstream(dir_ / "empty.c3d", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  EXPECT_LT(bytes.size(), 8000u);
  Expect({"2^31 empty frames", 1, "no frame"}, "convert empty.c3d out.trc", {"empty.c3d"});
}

// SIGTERM while analyze works: exit 143, its temporaries removed, and the previous run's outputs
// exactly as they were (the new set is moved into place only when complete).
TEST_F(Robustness, SigtermKeepsThePreviousOutputs) {
  const std::string trial = Quote(Samples() / "trials/trampoline_routine/trampoline_routine.c3d");
  const std::string args = "analyze " + trial + " --no-images -o out";
  const Outcome first = Acrolab(args, dir_);
  ASSERT_EQ(first.status, 0) << first.err;
  const std::string jumps = ReadText(dir_ / "out/jumps.json");
  ASSERT_FALSE(jumps.empty());
  std::vector<std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir_ / "out"))
    files.push_back(e.path().filename().string());
  int interrupted = 0;  // measured: 3 of the 4 (the analysis takes about 1.1 s here)
  for (const double after_s : {0.3, 0.6, 0.9, 1.2}) {
    const int status =
        TerminatedAfter(after_s,
                        dir_,
                        {"analyze",
                         (Samples() / "trials/trampoline_routine/trampoline_routine.c3d").string(),
                         "--no-images",
                         "--quiet",
                         "-o",
                         "out"});
    std::printf("SIGTERM after %.1f s: exit %d\n", after_s, status);
    EXPECT_TRUE(status == 143 || status == 0) << status;  // 0: it had finished
    interrupted += status == 143;
    EXPECT_EQ(Leftovers(dir_, {"out"}), std::vector<std::string>{});
    std::vector<std::string> now;
    for (const fs::directory_entry& e : fs::directory_iterator(dir_ / "out"))
      now.push_back(e.path().filename().string());
    std::sort(now.begin(), now.end());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(now, files);
    EXPECT_EQ(ReadText(dir_ / "out/jumps.json"), jumps);  // the same analysis, or untouched
  }
  EXPECT_GE(interrupted, 1);  // the test interrupted at least one run
}

// SIGTERM to a batch while its jobs run: exit 143 with the one line saying so, every time, its
// jobs stopped with it (nothing of theirs left in TMPDIR), and the batch run again stores the
// rest. CI once saw such a batch exit 1: its main thread, finding its jobs killed under it,
// returned with their failures before the interrupt thread had finished and exited 143.
TEST_F(Robustness, SigtermStopsABatchWithItsJobs) {
  fs::create_directories(dir_ / "season");
  fs::create_directories(dir_ / "tmp");
  for (int k = 1; k <= 8; ++k)
    fs::copy_file(Samples() / "trials/straight_jump/straight_jump.c3d",
                  dir_ / "season" / ("jump_" + std::to_string(k) + ".c3d"));
  const std::string athlete = (Samples() / "athletes/sample_athlete.yaml").string();
  // The whole batch takes about 4.4 s here (8 jobs of 1.1 s, 2 at a time): every one of these
  // is stopped half-way.
  for (const double after_s : {0.6, 1.2, 1.8, 2.4}) {
    fs::remove(dir_ / "lib.sqlite");
    const int status =
        TerminatedAfter(after_s,
                        dir_,
                        {"batch",
                         "season",
                         "-j",
                         "2",
                         "--athlete",
                         athlete,
                         "--session",
                         "2026-09-01",
                         "--library",
                         "lib.sqlite"},
                        [this] {
                          setenv("TMPDIR", (dir_ / "tmp").c_str(), 1);
                          const int err = open("stderr.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
                          const int out = open("stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
                          if (err < 0 || out < 0 || dup2(err, 2) < 0 || dup2(out, 1) < 0)
                            _exit(126);
                        });
    const std::string err = ReadText(dir_ / "stderr.txt");
    std::printf("SIGTERM to the batch after %.1f s: exit %d\n", after_s, status);
    EXPECT_EQ(status, 143) << err;
    EXPECT_NE(LastLine(err).find("acrolab: interrupted (SIGTERM)"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_empty(dir_ / "tmp")) << "after " << after_s << " s: " << [this] {
      std::string left;
      for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir_ / "tmp"))
        left += " " + e.path().lexically_relative(dir_ / "tmp").string();
      return left;
    }();
    // No summary: the jobs the signal stopped are not failures.
    const std::string summary = ReadText(dir_ / "stdout.txt");
    EXPECT_EQ(summary.find("failed"), std::string::npos) << summary;
  }
  fs::remove(dir_ / "stdout.txt");
  // The rest (up to 8 jobs, 4.4 s alone) under a bound that leaves room for a loaded machine.
  std::string out;
  const Outcome rest = Acrolab("batch season -j 2 --athlete " + Quote(athlete) +
                                   " --session 2026-09-01 --library lib.sqlite",
                               dir_,
                               &out,
                               "timeout 120 ");
  EXPECT_EQ(rest.status, 0) << rest.err;
  EXPECT_NE(out.find("batch: 8 trials: "), std::string::npos) << out;
  EXPECT_NE(out.find(" unchanged, 0 failed"), std::string::npos) << out;
}

// A SIGTERM at any instant of a batch's life, counted from its start: before acrolab's handler is
// in place (the loader maps ~290 libraries first, before any of its code runs) the signal's default
// action ends it with the same status and nothing has been started or written; after, the line
// saying so. Never a job left running, a temporary left in TMPDIR, or a job counted as failed.
TEST_F(Robustness, SigtermAtAnyInstantEndsABatchCleanly) {
  fs::create_directories(dir_ / "season");
  fs::create_directories(dir_ / "tmp");
  for (int k = 1; k <= 4; ++k)
    fs::copy_file(Samples() / "trials/straight_jump/straight_jump.c3d",
                  dir_ / "season" / ("jump_" + std::to_string(k) + ".c3d"));
  const std::string athlete = (Samples() / "athletes/sample_athlete.yaml").string();
  for (const double after_s : {0.0, 0.01, 0.05, 0.2, 0.5, 0.8}) {
    fs::remove(dir_ / "lib.sqlite");
    const int status = TerminatedAfter(
        after_s,
        dir_,
        {"batch",
         "season",
         "-j",
         "2",
         "--athlete",
         athlete,
         "--session",
         "2026-09-01",
         "--library",
         "lib.sqlite"},
        [this] {
          setenv("TMPDIR", (dir_ / "tmp").c_str(), 1);
          const int err = open("stderr.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
          const int out = open("stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
          if (err < 0 || out < 0 || dup2(err, 2) < 0 || dup2(out, 1) < 0) _exit(126);
        },
        From::kFork);
    const std::string err = ReadText(dir_ / "stderr.txt");
    std::printf("SIGTERM %.2f s after the start: exit %d, %s\n",
                after_s,
                status,
                err.empty() ? "before the handler (nothing said)" : "said so");
    EXPECT_EQ(status, 143) << err;
    if (!err.empty()) {
      EXPECT_NE(LastLine(err).find("acrolab: interrupted (SIGTERM)"), std::string::npos) << err;
    }
    EXPECT_TRUE(fs::is_empty(dir_ / "tmp")) << "after " << after_s << " s: " << [this] {
      std::string left;
      for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir_ / "tmp"))
        left += " " + e.path().lexically_relative(dir_ / "tmp").string();
      return left;
    }();
    EXPECT_EQ(ReadText(dir_ / "stdout.txt").find("failed"), std::string::npos);
  }
}

// Two converts to the same file at once: each completes or fails cleanly, and the file is one of
// them whole (their temporary names are unique).
TEST_F(Robustness, TwoConvertsToTheSameFile) {
  const std::string a = Quote(Samples() / "trials/straight_jump/straight_jump.c3d");
  const std::string b = Quote(Samples() / "trials/trampoline_routine/trampoline_routine.c3d");
  for (int round = 0; round < 3; ++round) {
    const std::string line = "cd " + Quote(dir_) + " && (" + std::string(ACROLAB_EXE) +
                             " convert " + a + " out.c3d & " + std::string(ACROLAB_EXE) +
                             " convert " + b + " out.c3d & wait) >/dev/null 2>&1";
    ASSERT_EQ(std::system(("sh -c " + Quote(line)).c_str()), 0);
    EXPECT_EQ(Leftovers(dir_, {"out.c3d"}), std::vector<std::string>{});
    const acro::capture::Trial back = acro::capture::ReadTrial(dir_ / "out.c3d");
    EXPECT_TRUE(back.num_frames == 444 || back.num_frames == 1266) << back.num_frames;
    EXPECT_TRUE(back.warnings.empty());
  }
}

// Two analyses into the same -o at once: both complete, and the directory holds one of them
// whole — its report and its jumps.json from the same run (the commits take turns).
// The season library (docs/library.md): a file that is not a library, through every command that
// reads one, is one line and stays as it was; a job list's mistake names its line; a batch with
// bad files goes on and names each one.
TEST_F(Robustness, LibraryFilesAndBatchMistakes) {
  const std::string notes = "my notes, not a database\n" + std::string(3000, 'x');
  WriteText(dir_ / "notes.sqlite", notes);
  for (const char* command : {"library list",
                              "library query --athlete A",
                              "library show 1",
                              "library export -o all.csv"}) {
    Expect({command, 1, "notes.sqlite: not an Acrolab library"},
           std::string(command) + " --library notes.sqlite",
           {"notes.sqlite"});
    EXPECT_EQ(ReadText(dir_ / "notes.sqlite"), notes);
  }
  const std::string athlete = Quote(Samples() / "athletes/sample_athlete.yaml");
  Expect({"library add to notes", 1, "not an Acrolab library"},
         "library add " + Quote(Samples() / "trials/straight_jump/straight_jump.c3d") +
             " --athlete " + athlete + " --library notes.sqlite",
         {"notes.sqlite"});
  EXPECT_EQ(ReadText(dir_ / "notes.sqlite"), notes);
  Expect({"query dates reversed", 2, "--to 2026-01-01 is before --from 2026-02-01"},
         "library query --from 2026-02-01 --to 2026-01-01 --library notes.sqlite",
         {"notes.sqlite"});
  WriteText(dir_ / "jobs.txt", "a.c3d --athlete x.yaml --frames 3\n");
  Expect({"job list option", 1, "jobs.txt: line 1: '--frames' is not one of"},
         "batch jobs.txt --library lib.sqlite",
         {"notes.sqlite", "jobs.txt", "lib.sqlite", "lib.sqlite-wal", "lib.sqlite-shm"});
  // Two good trials, a C3D cut in its parameter section, a text file named .c3d and a missing
  // file: the batch goes on, stores the good ones and names each bad one with its error.
  fs::create_directories(dir_ / "season");
  fs::copy_file(Samples() / "trials/straight_jump/straight_jump.c3d", dir_ / "season/good_1.c3d");
  fs::copy_file(Samples() / "trials/trampoline_routine/trampoline_routine.c3d",
                dir_ / "season/good_2.c3d");
  const std::string c3d = ReadText(Samples() / "trials/straight_jump/straight_jump.c3d");
  WriteText(dir_ / "season/cut.c3d", c3d.substr(0, 700));  // in its parameter section
  WriteText(dir_ / "season/text.c3d", "hello\n");
  WriteText(dir_ / "list.txt",
            "season/good_1.c3d\nseason/cut.c3d\nseason/missing.c3d\nseason/text.c3d\n"
            "season/good_2.c3d\n");
  std::string out;
  const Outcome run = Acrolab(
      "batch list.txt -j 2 --athlete " + athlete + " --session 2026-09-01 --library lib.sqlite",
      dir_,
      &out);
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(out.find("batch: 5 trials: 2 added, 0 unchanged, 3 failed"), std::string::npos) << out;
  for (const char* bad : {"cut.c3d: byte 699: POINT:DESCRIPTIONS",
                          "missing.c3d: no such file",
                          "text.c3d: file holds 6 bytes"})
    EXPECT_NE(out.find(bad), std::string::npos) << bad << "\n" << out;
  // Run again: nothing to do for the good ones, the bad ones said again.
  const Outcome again =
      Acrolab("batch list.txt --athlete " + athlete + " --library lib.sqlite", dir_, &out);
  EXPECT_EQ(again.status, 1);
  EXPECT_NE(out.find("0 added, 2 unchanged, 3 failed"), std::string::npos) << out;
  // --print-jobs: the commands of what is left (the three bad files).
  Acrolab("batch list.txt --print-jobs --athlete " + athlete + " --library lib.sqlite", dir_, &out);
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 2) << out;  // missing.c3d is not a job
  EXPECT_NE(out.find("acrolab library add"), std::string::npos) << out;
  // A stored trial by its path as the user types it: shown, removed (the file stays), gone.
  EXPECT_EQ(Acrolab("library show season/good_1.c3d --library lib.sqlite", dir_, &out).status, 0);
  EXPECT_NE(out.find("back somersault"), std::string::npos) << out;
  EXPECT_EQ(Acrolab("library remove season/good_1.c3d --library lib.sqlite", dir_, &out).status, 0);
  EXPECT_TRUE(fs::exists(dir_ / "season/good_1.c3d"));
  EXPECT_EQ(Acrolab("library remove season/good_1.c3d --library lib.sqlite", dir_, &out).status, 1);
  Acrolab("library list --library lib.sqlite", dir_, &out);
  EXPECT_NE(out.find("1 trials in lib.sqlite"), std::string::npos) << out;
}

TEST_F(Robustness, TwoAnalysesIntoTheSameDirectory) {
  fs::create_directories(dir_ / "a");
  fs::create_directories(dir_ / "b");
  fs::copy_file(Samples() / "trials/straight_jump/straight_jump.c3d", dir_ / "a/trial.c3d");
  fs::copy_file(Samples() / "trials/trampoline_routine/trampoline_routine.c3d",
                dir_ / "b/trial.c3d");
  std::map<std::string, std::string> alone;  // jumps.json of each run on its own
  for (const char* which : {"a", "b"}) {
    const Outcome run = Acrolab(
        std::string("analyze ") + which + "/trial.c3d --no-images --quiet -o " + which + "/out",
        dir_);
    ASSERT_EQ(run.status, 0) << run.err;
    alone[which] = ReadText(dir_ / which / "out/jumps.json");
  }
  ASSERT_NE(alone["a"], alone["b"]);
  for (int round = 0; round < 3; ++round) {
    const std::string exe = ACROLAB_EXE;
    const std::string line = "cd " + Quote(dir_) + " && (" + exe +
                             " analyze a/trial.c3d --no-images --quiet -o out & " + exe +
                             " analyze b/trial.c3d --no-images --quiet -o out & wait) "
                             ">/dev/null 2>&1";
    ASSERT_EQ(std::system(("sh -c " + Quote(line)).c_str()), 0);
    const std::string report = ReadText(dir_ / "out/report.html");
    const bool from_a = report.find("a/trial.c3d") != std::string::npos;
    EXPECT_NE(from_a, report.find("b/trial.c3d") != std::string::npos);
    EXPECT_EQ(ReadText(dir_ / "out/jumps.json"), alone[from_a ? "a" : "b"]) << round;
    EXPECT_EQ(Leftovers(dir_, {"a", "b", "out"}), std::vector<std::string>{});
  }
}

}  // namespace
