// `acrolab live` (docs/live.md), the acceptance set-up: the sample routine's side video
// streamed over UDP on the loopback interface at real time (ffmpeg -re) into `acrolab live`; every
// jump's line against the motion capture's flights (truth.json, shifted to the video's clock by
// video_truth.json), its delay after the landing, the routine cut, the recording frame-exact.

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/capture/video.h"
#include "acro/library/library.h"
#include "refdata.h"
#include "udp_ports.h"
#include "wire_clock.h"

namespace {

std::filesystem::path Sample(const std::string& name) {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine" / name;
}

nlohmann::json ReadJson(const std::filesystem::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

std::vector<nlohmann::json> ReadLines(const std::filesystem::path& p) {
  std::vector<nlohmann::json> out;
  std::ifstream in(p);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

std::vector<std::uint64_t> Hashes(const std::filesystem::path& video) {
  acro::capture::VideoReader reader(video);
  std::vector<std::uint64_t> h;
  acro::capture::VideoFrame f;
  while (reader.ReadNext(&f)) h.push_back(acro::capture::HashFrame(f));
  return h;
}

// Every frame one source's segments hold (live.json's "segments", from `first` on), in order.
std::vector<std::uint64_t> RecordedHashes(const std::filesystem::path& dir,
                                          const nlohmann::json& source,
                                          size_t first = 0) {
  std::vector<std::uint64_t> out;
  const auto& segments = source.at("segments");
  for (size_t k = first; k < segments.size(); ++k) {
    const auto h = Hashes(dir / "recording" / segments[k].get<std::string>());
    out.insert(out.end(), h.begin(), h.end());
  }
  return out;
}

struct LiveRun {
  int status = -1;  ///< the exit status (128 + the signal that ended it)
  std::string out;
};

// Runs a shell command, its standard output and error read whole.
LiveRun Shell(const std::string& cmd) {
  LiveRun run;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) run.out += buffer;
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

// Runs `acrolab live` on a UDP port while ffmpeg streams the side video to it at real time (the
// first `send_s` seconds of it; 0: all), once it listens. The sender writes each picture's length
// in its MPEG-TS packet header, as a low-latency sender does: without it (FFmpeg's default) a
// receiver knows a picture is whole only when the next begins, and the last picture before the
// sender stops only when the stop is known (--stall-timeout later; docs/live.md).
LiveRun LiveWithStream(const std::filesystem::path& dir,
                       int port,
                       double send_s,
                       const std::string& extra = "") {
  std::thread sender([&] {
    EXPECT_TRUE(acro::testing::WaitForUdpListener(port, 30.0)) << "nothing listens on " << port;
    const std::string cmd =
        "ffmpeg -v error -re -i '" + Sample("side_camera.mp4").string() + "'" +
        (send_s > 0 ? fmt::format(" -t {}", send_s) : std::string()) +
        " -c copy -omit_video_pes_length 0 -f mpegts 'udp://127.0.0.1:" + std::to_string(port) +
        "?pkt_size=1316'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  });
  const std::string cmd =
      fmt::format("'{}' live udp://127.0.0.1:{} --stall-timeout 1.5 --reconnect 0 {} -o '{}' 2>&1",
                  ACROLAB_EXE,
                  port,
                  extra,
                  dir.string());
  const LiveRun run = Shell(cmd);
  sender.join();
  return run;
}

TEST(LiveCli, TheSideVideoStreamedAtRealTime) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const auto dir = acro::testing::ScratchDir("live_cli") / "session";
  const int port = acro::testing::FreeUdpPort();
  const std::filesystem::path library = dir.parent_path() / "season.sqlite";
  const std::filesystem::path athlete =
      acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
  const LiveRun run = LiveWithStream(
      dir,
      port,
      0,
      fmt::format("--athlete '{}' --library '{}'", athlete.string(), library.string()));
  ASSERT_EQ(run.status, 0) << run.out;
  std::printf("%s", run.out.c_str());

  // The truth: the motion capture's flights on the video's clock (the first is in the air when
  // the video starts: not a jump the picture can time).
  const nlohmann::json truth = ReadJson(Sample("truth.json"));
  const double offset = ReadJson(Sample("video_truth.json")).at("offset_s").get<double>();
  std::vector<std::pair<double, double>> flights;
  for (const auto& f : truth.at("flights")) {
    const double t0 = f.at("takeoff_s").get<double>() + offset;
    const double t1 = f.at("landing_s").get<double>() + offset;
    if (t0 > 0 && t1 < 299.0 / 30.0) flights.emplace_back(t0, t1);
  }
  ASSERT_EQ(flights.size(), 5u);

  const std::vector<nlohmann::json> jumps = ReadLines(dir / "jumps.jsonl");
  ASSERT_EQ(jumps.size(), flights.size()) << run.out;
  double worst_takeoff = 0, worst_landing = 0, worst_latency = 0, sum = 0, truth_sum = 0;
  for (size_t k = 0; k < jumps.size(); ++k) {
    const double t0 = jumps[k].at("takeoff_s").get<double>();
    const double t1 = jumps[k].at("landing_s").get<double>();
    worst_takeoff = std::max(worst_takeoff, std::abs(t0 - flights[k].first));
    worst_landing = std::max(worst_landing, std::abs(t1 - flights[k].second));
    worst_latency = std::max(worst_latency, jumps[k].at("latency_s").get<double>());
    sum += t1 - t0;
    truth_sum += flights[k].second - flights[k].first;
    // Every landing of the sample routine is in zone A (the motion capture's score sheet).
    EXPECT_EQ(jumps[k].at("zone"), "A") << jumps[k].dump();
  }
  std::printf(
      "live: take-offs within %.0f ms, landings within %.0f ms, ToF sum %+.0f ms, "
      "lines at most %.2f s after the landing\n",
      1e3 * worst_takeoff,
      1e3 * worst_landing,
      1e3 * (sum - truth_sum),
      worst_latency);
  EXPECT_LT(worst_takeoff, 2.0 / 30.0);
  EXPECT_LT(worst_landing, 2.0 / 30.0);
  EXPECT_LE(worst_latency, 1.0) << "every jump's line within a second of its landing";

  // One routine, cut within 0.5 s of its first take-off and last landing, its clip frame-exact.
  const nlohmann::json live = ReadJson(dir / "live.json");
  ASSERT_EQ(live.at("routines").size(), 1u) << live.dump(2);
  const auto routine_dir = dir / live.at("routines")[0].at("folder").get<std::string>();
  const nlohmann::json routine = ReadJson(routine_dir / "routine.json");
  EXPECT_EQ(routine.at("jumps").size(), 5u);
  EXPECT_NEAR(routine.at("first_takeoff_s").get<double>(), flights.front().first, 0.5);
  EXPECT_NEAR(routine.at("last_landing_s").get<double>(), flights.back().second, 0.5);
  EXPECT_FALSE(routine.at("interrupted").get<bool>());
  const std::vector<std::uint64_t> source = Hashes(Sample("side_camera.mp4"));
  const std::vector<std::uint64_t> clip = Hashes(routine_dir / "clip.ts");
  const int first = static_cast<int>(std::lround(routine.at("clip_start_s").get<double>() * 30));
  ASSERT_GT(clip.size(), 200u);
  for (size_t k = 0; k < clip.size(); ++k)
    ASSERT_EQ(clip[k], source.at(first + k)) << "clip frame " << k;
  // The routine analysed in its folder by `acrolab analyze --video clip.ts --detect-bed`.
  EXPECT_TRUE(std::filesystem::exists(routine_dir / "analysis" / "report.html")) << run.out;
  EXPECT_TRUE(std::filesystem::exists(routine_dir / "analysis" / "jumps.json")) << run.out;
  EXPECT_NE(run.out.find("routine 1 analysed in"), std::string::npos) << run.out;
  // Its time of flight is the score's: within 0.1 s of the motion capture's over the five flights
  // (the faster full model's came 0.38 s long).
  const nlohmann::json score = ReadJson(routine_dir / "analysis" / "score.json");
  std::printf("the routine's analysis: time of flight %.3f s, the motion capture's %.3f s\n",
              score.at("time_of_flight_sum_s").get<double>(),
              truth_sum);
  EXPECT_NEAR(score.at("time_of_flight_sum_s").get<double>(), truth_sum, 0.1);
  // And stored in the season library under the athlete, with its jumps.
  {
    const acro::library::Library season(library, acro::library::Library::Mode::kReadOnly);
    const auto stored = season.FindTrialSummary((routine_dir / "clip.ts").string());
    ASSERT_TRUE(stored.has_value()) << run.out;
    EXPECT_EQ(stored->athlete, "Sample Athlete");
    EXPECT_GE(stored->num_jumps, 5);
  }
  EXPECT_NE(run.out.find("routine 1 in the library"), std::string::npos) << run.out;
  // The analysis is the clip's: another file it read (the bed's picture) cannot pass for it.
  const std::string bed_picture =
      (dir / live.at("sources")[0].at("bed_picture").get<std::string>()).string();
  const LiveRun other =
      Shell(fmt::format("'{}' library add '{}' --analysis '{}' --athlete '{}' --library '{}' 2>&1",
                        ACROLAB_EXE,
                        bed_picture,
                        (routine_dir / "analysis").string(),
                        athlete.string(),
                        (dir.parent_path() / "other.sqlite").string()));
  EXPECT_EQ(other.status, 1) << other.out;
  EXPECT_NE(other.out.find("an analysis of another file"), std::string::npos) << other.out;
  // The recording, every frame the source sent.
  const std::vector<std::uint64_t> recorded = RecordedHashes(dir, live.at("sources")[0]);
  EXPECT_EQ(recorded, source);
}

TEST(LiveCli, TheStreamCutOffInTheAirInterruptsTheRoutine) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const auto dir = acro::testing::ScratchDir("live_cut") / "session";
  const int port = acro::testing::FreeUdpPort();
  // 5.2 s: in the third complete flight (4.579–5.984 s of the video).
  const LiveRun run = LiveWithStream(dir, port, 5.2, "--no-analysis");
  ASSERT_EQ(run.status, 0) << run.out;
  const std::vector<nlohmann::json> jumps = ReadLines(dir / "jumps.jsonl");
  EXPECT_EQ(jumps.size(), 2u) << run.out;
  const nlohmann::json live = ReadJson(dir / "live.json");
  ASSERT_EQ(live.at("routines").size(), 1u) << live.dump(2);
  EXPECT_TRUE(live.at("routines")[0].at("interrupted").get<bool>());
  EXPECT_NE(run.out.find("interrupted"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("stopped sending after 1.5 s"), std::string::npos) << run.out;
  // Nothing recorded is lost: the recording holds every frame sent, playable.
  const std::vector<std::uint64_t> source = Hashes(Sample("side_camera.mp4"));
  const std::vector<std::uint64_t> recorded = RecordedHashes(dir, live.at("sources")[0]);
  ASSERT_GT(recorded.size(), 150u);
  // (the sender's own cut leaves its last frames without the later pictures they refer to)
  for (size_t k = 0; k + 3 < recorded.size(); ++k) ASSERT_EQ(recorded[k], source[k]) << k;
}

TEST(LiveCli, AStreamCutOffAndResumedLosesNothing) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const auto dir = acro::testing::ScratchDir("live_resume") / "session";
  const int port = acro::testing::FreeUdpPort();
  // The stream cut at 5.2 s (in the third complete flight), back 2.7 s later with the whole video.
  std::thread sender([&] {
    const std::string send = "ffmpeg -v error -re -i '" + Sample("side_camera.mp4").string() + "'";
    const std::string to =
        " -c copy -f mpegts 'udp://127.0.0.1:" + std::to_string(port) + "?pkt_size=1316'";
    EXPECT_TRUE(acro::testing::WaitForUdpListener(port, 30.0));
    EXPECT_EQ(std::system((send + " -t 5.2" + to).c_str()), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(2700));
    EXPECT_EQ(std::system((send + to).c_str()), 0);
  });
  const std::string cmd = fmt::format(
      "'{}' live udp://127.0.0.1:{} --stall-timeout 1.5 --reconnect 5 --no-analysis -o '{}' 2>&1",
      ACROLAB_EXE,
      port,
      dir.string());
  const LiveRun run = Shell(cmd);
  const std::string& out = run.out;
  sender.join();
  ASSERT_EQ(run.status, 0) << out;
  std::printf("%s", out.c_str());
  EXPECT_NE(out.find("waiting up to 5 s for it to come back"), std::string::npos) << out;
  EXPECT_NE(out.find("sending again"), std::string::npos) << out;
  // The routine the cut interrupted, then the next one whole.
  const nlohmann::json live = ReadJson(dir / "live.json");
  ASSERT_EQ(live.at("routines").size(), 2u) << live.dump(2);
  EXPECT_TRUE(live.at("routines")[0].at("interrupted").get<bool>());
  EXPECT_EQ(live.at("routines")[0].at("jumps").get<int>(), 2);
  EXPECT_FALSE(live.at("routines")[1].at("interrupted").get<bool>());
  EXPECT_EQ(live.at("routines")[1].at("jumps").get<int>(), 5);
  // On one time line: the second stream began 5.2 + 2.7 s after the first (and an ffmpeg's
  // start), so its first take-off (1.162 s into the video) is about 9.1 s on the first's clock.
  EXPECT_NEAR(live.at("routines")[1].at("first_takeoff_s").get<double>(), 5.2 + 2.7 + 1.162, 0.5);
  // Jumps numbered on through the gap.
  const std::vector<nlohmann::json> jumps = ReadLines(dir / "jumps.jsonl");
  ASSERT_EQ(jumps.size(), 7u);
  for (size_t k = 0; k < jumps.size(); ++k) EXPECT_EQ(jumps[k].at("jump").get<int>(), int(k) + 1);
  EXPECT_TRUE(std::filesystem::exists(dir / live.at("routines")[1].at("folder").get<std::string>() /
                                      "clip.ts"));
  // Nothing recorded is lost: both connections' frames, each the file's.
  const std::vector<std::uint64_t> source = Hashes(Sample("side_camera.mp4"));
  const auto& segments = live.at("sources")[0].at("segments");
  ASSERT_GE(segments.size(), 2u);
  std::vector<std::uint64_t> cut = Hashes(dir / "recording" / segments[0].get<std::string>());
  ASSERT_GT(cut.size(), 150u);
  for (size_t k = 0; k + 3 < cut.size(); ++k) ASSERT_EQ(cut[k], source[k]) << k;
  EXPECT_EQ(RecordedHashes(dir, live.at("sources")[0], 1), source);
}

TEST(LiveCli, TwoSourcesStartedApartAreBothRecordedAndPutOnOneTimeLine) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const auto dir = acro::testing::ScratchDir("live_two") / "session";
  // Each stream also goes to a receiver of the test's own (a tee in the sender): when each was
  // really sent is read off the wire there, whatever the two ffmpeg processes took to start on a
  // busy machine. That, not the 0.3 s the test waits between starting them, is the truth.
  acro::testing::WireClock wire_a(acro::testing::FreeUdpPort()),
      wire_b(acro::testing::FreeUdpPort());
  ASSERT_TRUE(wire_a.bound() && wire_b.bound());
  // (bound before the session's ports are chosen, so that none can be chosen twice)
  const int a = acro::testing::FreeUdpPort();
  int b = acro::testing::FreeUdpPort();
  while (b == a) b = acro::testing::FreeUdpPort();
  const auto send = [](int port, int wire_port) {
    return std::thread([=] {
      const std::string cmd = fmt::format(
          "ffmpeg -v error -re -i '{}' -t 5 -map 0:v -c copy -f tee "
          "'[f=mpegts]udp://127.0.0.1:{}?pkt_size=1316|[f=mpegts]udp://127.0.0.1:{}?pkt_size=1316'",
          Sample("side_camera.mp4").string(),
          port,
          wire_port);
      EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    });
  };
  // Both listening first, then the second sent 0.3 s after the first.
  std::thread first, second;
  std::thread starter([&] {
    EXPECT_TRUE(acro::testing::WaitForUdpListener(a, 30.0));
    EXPECT_TRUE(acro::testing::WaitForUdpListener(b, 30.0));
    first = send(a, wire_a.port());
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    second = send(b, wire_b.port());
  });
  const std::string cmd = fmt::format(
      "'{}' live udp://127.0.0.1:{} udp://127.0.0.1:{} --stall-timeout 1.5 --reconnect 0 "
      "--no-analysis "
      "-o '{}' "
      "2>&1",
      ACROLAB_EXE,
      a,
      b,
      dir.string());
  const LiveRun run = Shell(cmd);
  const std::string& out = run.out;
  starter.join();
  first.join();
  second.join();
  ASSERT_EQ(run.status, 0) << out;
  const nlohmann::json live = ReadJson(dir / "live.json");
  ASSERT_EQ(live.at("sources").size(), 2u);
  const std::vector<std::uint64_t> source = Hashes(Sample("side_camera.mp4"));
  for (const auto& s : live.at("sources")) {
    const std::vector<std::uint64_t> recorded = RecordedHashes(dir, s);
    ASSERT_GT(recorded.size(), 140u) << s.dump();
    // (the sender's own cut leaves its last frames without the later pictures they refer to)
    for (size_t k = 0; k + 3 < recorded.size(); ++k)
      ASSERT_EQ(recorded[k], source[k]) << s.at("name") << " frame " << k;
  }
  const double offset = live.at("sources")[1].at("offset_to_first_s").get<double>();
  const double sent = wire_b.origin() - wire_a.origin();
  std::printf(
      "two sources: the second's stream started %.3f s after the first's (sent %.3f s later, "
      "read off the wire; started 0.300 s later)\n",
      offset,
      sent);
  ASSERT_TRUE(std::isfinite(sent)) << "the test's own receivers saw no picture";
  EXPECT_NEAR(offset, sent, 1.0 / 30.0) << "synced within a frame";
}

// A disk that fills up, as a file-size limit makes it (ulimit -f, SIGXFSZ ignored: a write past it
// fails with EFBIG as one past a full disk fails with ENOSPC): the recording stops with one line
// naming its file, and what it holds plays.
TEST(LiveCli, ARecordingThatCannotBeWrittenStopsWithOneLineAndStaysPlayable) {
  const auto dir = acro::testing::ScratchDir("live_full") / "session";
  const std::string cmd = fmt::format(
      "bash -c \"trap '' XFSZ; ulimit -f 200; exec '{}' live '{}' --as-fast-as-decoded "
      "--no-analysis -o '{}'\" 2>&1",
      ACROLAB_EXE,
      Sample("side_camera.mp4").string(),
      dir.string());
  const std::string out = Shell(cmd).out;
  const std::string file = (dir / "recording" / "side_camera-000.ts").string();
  EXPECT_NE(out.find("recording stopped: " + file), std::string::npos) << out;
  EXPECT_NE(out.find("File too large"), std::string::npos) << out;
  // What was recorded (200 KB of the 470 KB) plays, and is the file's first frames.
  const std::vector<std::uint64_t> source = Hashes(Sample("side_camera.mp4"));
  const std::vector<std::uint64_t> recorded = Hashes(file);
  ASSERT_GT(recorded.size(), 60u) << out;
  ASSERT_LT(recorded.size(), 250u) << out;
  for (size_t k = 0; k + 3 < recorded.size(); ++k) ASSERT_EQ(recorded[k], source[k]) << k;
  EXPECT_TRUE(std::filesystem::exists(dir / "live.json"));
}

// The camera's intrinsics from a calibration (here the sample's side camera file): the focal length
// known, the pose found on the bed — every landing spot along the bed within 10 cm of where the
// motion capture's feet came down (truth.json, against the bed's centre). A calibration that
// cannot be read is one line before anything is written; --camera needs --intrinsics.
TEST(LiveCli, TheCamerasIntrinsicsWithItsPoseFromTheBed) {
  const auto dir = acro::testing::ScratchDir("live_intrinsics");
  const std::string calib = Sample("side_camera.toml").string();
  const LiveRun run = Shell(fmt::format(
      "'{}' live '{}' --as-fast-as-decoded --no-analysis --intrinsics '{}' -o '{}' 2>&1",
      ACROLAB_EXE,
      Sample("side_camera.mp4").string(),
      calib,
      (dir / "s").string()));
  ASSERT_EQ(run.status, 0) << run.out;
  const nlohmann::json live = ReadJson(dir / "s" / "live.json");
  const std::string bed = live.at("sources")[0].at("bed").get<std::string>();
  EXPECT_NE(bed.find("posed on it with the intrinsics of " + calib), std::string::npos) << bed;
  std::ifstream truth_file(Sample("truth.json"));
  const nlohmann::json truth = nlohmann::json::parse(truth_file);
  const double centre_x = truth.at("bed").at("centre_m")[0].get<double>();
  const std::vector<nlohmann::json> jumps = ReadLines(dir / "s" / "jumps.jsonl");
  ASSERT_EQ(jumps.size(), 5u);
  for (size_t k = 0; k < jumps.size(); ++k) {
    // The video's jumps are the trial's flights 2–6 (it starts in the first).
    const double expected =
        truth.at("flights")[k + 1].at("landing_feet_m")[0].get<double>() - centre_x;
    const double along = jumps[k].at("landing_along_bed_m").get<double>();
    std::printf("jump %zu: landed %+.3f m along the bed, the motion capture's feet %+.3f m\n",
                k + 1,
                along,
                expected);
    EXPECT_NEAR(along, expected, 0.10) << "jump " << k + 1;
  }
  // Refusals: one line each, nothing written.
  const std::filesystem::path bad = dir / "bad.toml";
  std::ofstream(bad) << "[cam]\nsize = [ 1920.0 ]\n";
  const LiveRun unreadable = Shell(fmt::format("'{}' live '{}' --intrinsics '{}' -o '{}' 2>&1",
                                               ACROLAB_EXE,
                                               Sample("side_camera.mp4").string(),
                                               bad.string(),
                                               (dir / "t").string()));
  EXPECT_EQ(unreadable.status, 1) << unreadable.out;
  EXPECT_NE(unreadable.out.find(bad.string()), std::string::npos) << unreadable.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "t"));
  const LiveRun camera_alone = Shell(fmt::format("'{}' live '{}' --camera side -o '{}' 2>&1",
                                                 ACROLAB_EXE,
                                                 Sample("side_camera.mp4").string(),
                                                 (dir / "u").string()));
  EXPECT_EQ(camera_alone.status, 2) << camera_alone.out;
  EXPECT_NE(camera_alone.out.find("--camera names a camera of --intrinsics"), std::string::npos)
      << camera_alone.out;
}

TEST(LiveCli, BadSourcesAreOneLineEach) {
  const auto dir = acro::testing::ScratchDir("live_bad");
  const std::string cmd = fmt::format(
      "'{}' live /dev/video-acrolab-none udp://127.0.0.1:{} --open-timeout 1 -o '{}' 2>&1",
      ACROLAB_EXE,
      acro::testing::FreeUdpPort(),
      (dir / "s").string());
  const LiveRun run = Shell(cmd);
  const std::string& out = run.out;
  EXPECT_EQ(run.status, 1) << out;
  EXPECT_NE(out.find("video-acrolab-none: not recorded"), std::string::npos) << out;
  EXPECT_NE(out.find("no such device"), std::string::npos) << out;
  EXPECT_NE(out.find("sent nothing within 1 s"), std::string::npos) << out;
  // A folder with an earlier session is never written over.
  std::filesystem::create_directories(dir / "old");
  std::ofstream(dir / "old" / "jumps.jsonl") << "{}\n";
  const std::string again =
      fmt::format("'{}' live /dev/null -o '{}' 2>&1", ACROLAB_EXE, (dir / "old").string());
  const LiveRun refused = Shell(again);
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.out.find("not empty: a live session never replaces"), std::string::npos)
      << refused.out;
  std::ifstream in(dir / "old" / "jumps.jsonl");
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "{}");
}

}  // namespace
