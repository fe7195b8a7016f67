// `acrolab live` under load (docs/live.md, "Measured"; issue "In the hall"): a session of routines
// with rests streamed over UDP at real time. The routine is the sample's side video from the
// athlete's first landing on (four jumps), then the athlete standing on the bed for the rest (the
// last frame held), encoded once by ffmpeg and looped by it. Checked: no frame is missing from the
// recording (ffprobe counts its packets: the unit's frames × the loops), every routine cut with
// its four jumps, analysed and in the season library; with ACRO_LONG_TESTS=1 the 30
// minutes (a routine a minute, the heavy detector), and the live process's memory flat — at most
// 10 % above its size at 5 minutes for the rest of the session. The default run: 3 routines with
// 10-s rests and the lite detector (about 2 minutes).

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acro/library/library.h"
#include "join_on_exit.h"
#include "refdata.h"
#include "udp_ports.h"

namespace {

namespace fs = std::filesystem;

std::string Output(const std::string& cmd) {
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) out += buffer;
  pclose(pipe);
  return out;
}

// Packets of the first video stream of a file, counted by ffprobe.
long long PacketCount(const fs::path& file) {
  const std::string out = Output(fmt::format(
      "ffprobe -v error -select_streams v:0 -count_packets -show_entries stream=nb_read_packets "
      "-of csv=p=0 '{}'",
      file.string()));
  return out.empty() ? -1 : std::atoll(out.c_str());
}

// A process's resident memory (kB), or -1 when it has ended.
long ResidentKb(int pid) {
  std::ifstream in(fmt::format("/proc/{}/status", pid));
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
  return -1;
}

TEST(LiveLoad, RoutinesWithRestsStreamedAtRealTimeAreAllRecordedCutAnalysedAndStored) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const bool full = std::getenv("ACRO_LONG_TESTS") != nullptr;
  const int routines = full ? 30 : 3;
  const double rest_s = full ? 52.7 : 10.0;  // full: a routine a minute
  const std::string model = full ? "heavy" : "lite";
  const fs::path root = acro::testing::ScratchDir("live_load");
  const fs::path unit = root / "routine.mp4";
  const fs::path side =
      acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";
  ASSERT_EQ(std::system(fmt::format("ffmpeg -v error -ss 2.7 -i '{}' -vf "
                                    "tpad=stop_mode=clone:stop_duration={} -an -c:v libx264 "
                                    "-preset ultrafast -bf 0 -g 30 -pix_fmt yuv420p '{}'",
                                    side.string(),
                                    rest_s,
                                    unit.string())
                            .c_str()),
            0);
  const long long unit_frames = PacketCount(unit);
  ASSERT_GT(unit_frames, 200);

  const fs::path dir = root / "session", library = root / "season.sqlite";
  const fs::path athlete = acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
  const int port = acro::testing::FreeUdpPort();
  std::thread sender;
  // A failed assertion returns with the sender (and the session) still running: joined, never
  // left to terminate().
  const acro::testing::JoinOnExit join_sender(sender);
  sender = std::thread([&] {
    EXPECT_TRUE(acro::testing::WaitForUdpListener(port, 30.0));
    const std::string cmd = fmt::format(
        "ffmpeg -v error -re -stream_loop {} -i '{}' -c copy -omit_video_pes_length 0 -f mpegts "
        "'udp://127.0.0.1:{}?pkt_size=1316'",
        routines - 1,
        unit.string(),
        port);
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  });
  // The session in the background: its process id first, then its lines.
  const std::string cmd = fmt::format(
      "'{}' live udp://127.0.0.1:{} --stall-timeout 3 --reconnect 0 --athlete '{}' --library '{}' "
      "--analysis-model {} -o '{}' > '{}' 2>&1 & echo $!; wait",
      ACROLAB_EXE,
      port,
      athlete.string(),
      library.string(),
      model,
      dir.string(),
      (root / "live.txt").string());
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char line[64] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, pipe), nullptr);
  const int pid = std::atoi(line);
  ASSERT_GT(pid, 0);
  // Its memory every 5 s.
  std::vector<std::pair<double, long>> rss;
  std::atomic<bool> done{false};
  std::thread watch([&] {
    const auto start = std::chrono::steady_clock::now();
    while (!done.load()) {
      const long kb = ResidentKb(pid);
      if (kb > 0)
        rss.emplace_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), kb);
      for (int i = 0; i < 50 && !done.load(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  const int status = pclose(pipe);
  done = true;
  watch.join();
  sender.join();
  std::ifstream text(root / "live.txt");
  const std::string out((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;

  // Every frame sent is in the recording.
  std::ifstream in(dir / "live.json");
  const nlohmann::json live = nlohmann::json::parse(in);
  long long recorded = 0;
  for (const auto& segment : live.at("sources")[0].at("segments"))
    recorded += PacketCount(dir / "recording" / segment.get<std::string>());
  EXPECT_EQ(recorded, unit_frames * routines) << out;
  // Every routine cut with its four jumps, analysed, in the library.
  ASSERT_EQ(live.at("routines").size(), static_cast<size_t>(routines)) << out;
  for (const auto& r : live.at("routines")) {
    EXPECT_EQ(r.at("jumps").get<int>(), 4) << r.dump();
    EXPECT_FALSE(r.at("interrupted").get<bool>()) << r.dump();
    EXPECT_TRUE(fs::exists(dir / r.at("folder").get<std::string>() / "analysis" / "report.html"))
        << r.dump() << out;
  }
  const acro::library::Library season(library, acro::library::Library::Mode::kReadOnly);
  int stored = 0;
  for (const auto& r : live.at("routines"))
    if (season.FindTrialSummary((dir / r.at("folder").get<std::string>() / "clip.ts").string()))
      ++stored;
  EXPECT_EQ(stored, routines) << out;

  // Memory: its size after 5 minutes, and the most it took afterwards.
  long at5 = 0, most = 0;
  for (const auto& [t, kb] : rss) {
    if (t <= 300) at5 = kb;
    if (t > 300) most = std::max(most, kb);
  }
  long first = rss.empty() ? 0 : rss.front().second, peak = 0;
  for (const auto& [t, kb] : rss) peak = std::max(peak, kb);
  std::printf(
      "%d routines, %lld frames recorded of %lld sent; memory %ld kB at the start, %ld kB "
      "at 5 min, at most %ld kB after it, peak %ld kB\n",
      routines,
      recorded,
      unit_frames * routines,
      first,
      at5,
      most,
      peak);
  if (full) {
    ASSERT_GT(at5, 0);
    EXPECT_LE(most, at5 * 11 / 10) << "memory grew more than 10 % after the first 5 minutes";
  }
}

}  // namespace
