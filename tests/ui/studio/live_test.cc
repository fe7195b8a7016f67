// The studio's live mode under Xvfb (docs/live.md, "The window"): the sample routine's side video
// streamed over UDP on the loopback at real time (ffmpeg -re) into the live window set 5 s late.
// ffmpeg's tee sends the same packets to a port of the test's own, whose first datagram is the
// stream's start on the test's clock: stream time τ was sent at that instant + τ. Checked:
// - every picture the window puts up while 5 s late is the frame sent 5 s before (± 1 frame), the
//   frame told by its pixels against the file's own decoded frames, not by the window's word;
// - slow motion falls behind by half the time it runs at ½×, a frame step is one frame, back to
//   the delay is 5 s again;
// - when the stream ends, the routine is cut and its replay starts by itself, with the overlay
//   drawn over its frames (the numbers' box), and plays on; the routine is analysed in the
//   background (acrolab, the lite detector) and its report offered beside the replay.
// With ACRO_STUDIO_SCREENSHOTS=DIR the window is saved there (docs/live.md).

#include "live_window.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QTest>
#include <QThread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/capture/live_source.h"
#include "acro/capture/video.h"
#include "acro/library/library.h"
#include "acro/views/display.h"
#include "join_on_exit.h"
#include "qt_wait.h"
#include "refdata.h"
#include "udp_ports.h"
#include "wire_clock.h"

namespace acro::studio {
namespace {

namespace fs = std::filesystem;

fs::path SideVideo() {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";
}

bool WaitUntil(const std::function<bool()>& done, int ms) {
  return acro::testing::WaitUntil(done, ms, 10);
}

void Pump(int ms) {
  WaitUntil([] { return false; }, ms);
}

void Shot(QWidget& window, const std::string& name) {
  const char* dir = std::getenv("ACRO_STUDIO_SCREENSHOTS");
  if (dir == nullptr || *dir == 0) return;
  window.grab().save(QString::fromStdString((fs::path(dir) / (name + ".png")).string()));
}

// A picture as 320 × 180 grey: enough to tell a frame from the next by the athlete's motion.
std::vector<int> Small(const QImage& image) {
  const QImage small = image.convertToFormat(QImage::Format_RGB32)
                           .scaled(320, 180, Qt::IgnoreAspectRatio, Qt::SmoothTransformation)
                           .convertToFormat(QImage::Format_Grayscale8);
  std::vector<int> v;
  v.reserve(320 * 180);
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) v.push_back(small.constScanLine(y)[x]);
  return v;
}

double Distance(const std::vector<int>& a, const std::vector<int>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d += std::abs(a[i] - b[i]);
  return d / double(a.size());
}

// The file's frames, decoded by the capture layer, as Small pictures.
std::vector<std::vector<int>> ReferenceFrames() {
  capture::VideoReader reader(SideVideo());
  std::vector<std::vector<int>> frames;
  for (int i = 0; i < reader.num_frames(); ++i) {
    const capture::VideoFrame f = reader.Frame(i);
    frames.push_back(
        Small(QImage(f.pixels.data(), f.width, f.height, 3 * f.width, QImage::Format_RGB888)));
  }
  return frames;
}

// The frame of the file a picture is (the nearest of all by mean absolute grey difference).
int WhichFrame(const std::vector<std::vector<int>>& frames, const QImage& picture) {
  const std::vector<int> p = Small(picture);
  int best = -1;
  double best_d = 1e300;
  for (size_t i = 0; i < frames.size(); ++i) {
    const double d = Distance(frames[i], p);
    if (d < best_d) {
      best_d = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

TEST(LiveWindow, ShowsTheFrameSentFiveSecondsEarlierAndReplaysTheRoutineByItself) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed";
  const std::vector<std::vector<int>> reference = ReferenceFrames();
  ASSERT_EQ(reference.size(), 299u);
  const int port = acro::testing::FreeUdpPort(), clock_port = acro::testing::FreeUdpPort();
  ASSERT_GT(port, 0);
  acro::testing::WireClock wire(clock_port);
  ASSERT_TRUE(wire.bound());

  const fs::path out = acro::testing::ScratchDir("studio_live") / "session";
  fs::remove_all(out);
  pipeline::LiveRequest request;
  request.sources = {fmt::format("udp://127.0.0.1:{}", port)};
  request.out_dir = out;
  request.source.open_timeout_s = 30;
  request.source.stall_timeout_s = 2;
  request.reconnect_s = 0;
  // Each routine analysed by acrolab as it is cut (the lite detector: the quickest).
  pipeline::RoutineAnalysisOptions analyses;
  analyses.acrolab = ACROLAB_EXE;
  analyses.model = "lite";
  // Stored in a season library under the athlete chosen on screen: given the sample athlete, the
  // coach picks the other profile beside it before the routine.
  const fs::path athletes = acro::testing::SourceDir() / "samples/athletes";
  analyses.athlete = athletes / "sample_athlete.yaml";
  analyses.library = out.parent_path() / "season.sqlite";
  fs::remove(analyses.library);
  LiveWindow w(request, 5.0, analyses);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  // The profiles in the given one's folder, then "no athlete" and "another profile…".
  int profiles = 0;
  for (const auto& e : fs::directory_iterator(athletes))
    profiles += e.path().extension() == ".yaml" || e.path().extension() == ".yml";
  const QStringList choices = w.athlete_choices();
  EXPECT_EQ(choices.size(), profiles + 2) << choices.join(" | ").toStdString();
  EXPECT_TRUE(choices.join("|").contains("Sample Athlete (Yeadon measurements)"))
      << choices.join(" | ").toStdString();
  EXPECT_EQ(w.athlete(), athletes / "sample_athlete.yaml");
  w.SetAthlete(athletes / "sample_athlete_yeadon.yaml");
  ASSERT_TRUE(acro::testing::WaitForUdpListener(port, 20));
  std::thread sender;
  // A failed assertion returns with the sender still running: joined, never left to terminate().
  const acro::testing::JoinOnExit join_sender(sender);
  sender = std::thread([&] {
    const std::string cmd = fmt::format(
        "ffmpeg -v error -re -i '{}' -map 0:v -c copy -f tee "
        "'[f=mpegts]udp://127.0.0.1:{}?pkt_size=1316|[f=mpegts]udp://127.0.0.1:{}?pkt_size=1316'",
        SideVideo().string(),
        port,
        clock_port);
    EXPECT_EQ(std::system(cmd.c_str()), 0);
  });
  ASSERT_TRUE(WaitUntil([&] { return wire.pictures() >= 60; }, 20000)) << "nothing was sent";
  const double t0 = wire.origin();

  // 5 s late: from 5.5 s to 11.5 s after the start, every new picture checked (the stream ends at
  // 10 s; its last 1.5 s are shown from the buffer). The frame is told by its pixels, among the
  // file's frames within half a second of the one expected.
  constexpr double kFrame = 1.0 / 30;
  int checked = 0, exact = 0, index_matches = 0;
  double worst = 0, worst_distance = 0;
  WaitUntil([&] { return capture::LiveClockNow() > t0 + 5.5; }, 20000);
  int last_index = -1;
  while (capture::LiveClockNow() < t0 + 11.5) {
    Pump(5);
    const LiveWindow::Shown s = w.shown(0);
    if (s.index == last_index || s.index < 0) continue;
    last_index = s.index;
    // The frame the source was sending 5 s before the picture went up.
    const double expected = (s.at_s - 5.0 - t0) / kFrame;
    const std::vector<int> shown = Small(w.shown_image(0));
    int k = -1;
    double best = 1e300;
    for (int i = std::max(0, int(expected) - 15); i <= std::min(298, int(expected) + 15); ++i) {
      const double d = Distance(reference[size_t(i)], shown);
      if (d < best) {
        best = d;
        k = i;
      }
    }
    worst_distance = std::max(worst_distance, best);
    const double off = k - expected;
    worst = std::max(worst, std::abs(off));
    EXPECT_LE(std::abs(off), 1.0) << "frame " << k << " up at " << s.at_s - t0
                                  << " s, expected frame " << expected;
    ++checked;
    if (std::abs(off) < 0.5) ++exact;
    if (k == s.index) ++index_matches;
    if (checked == 60) Shot(w, "live_window_delay");
  }
  std::printf("the window's sent offset − the wire's: %.1f ms\n", 1e3 * (w.sent_offset(0) - t0));
  std::printf(
      "5 s late: %d pictures checked, %d within half a frame, worst %.2f frames, worst "
      "grey difference %.2f; the window's own index agreed with the pixels %d times\n",
      checked,
      exact,
      worst,
      worst_distance,
      index_matches);
  EXPECT_GE(checked, 150);  // 6 s at 30 fps, a few missed by a busy machine at most
  EXPECT_GE(index_matches, checked - 2);
  EXPECT_LT(worst_distance, 4.0) << "a picture that is none of the file's frames around";

  // Slow motion inside the delay: for 1 s at ½× the picture moves on half as many frames (told
  // by its pixels), and falls 0.5 s further behind.
  const double before = w.shown_delay(), slow_from = capture::LiveClockNow();
  const int k_before = WhichFrame(reference, w.shown_image(0));
  w.SetSpeed(0.5);
  Pump(1000);
  const double slow_s = capture::LiveClockNow() - slow_from;
  const int k_after = WhichFrame(reference, w.shown_image(0));
  EXPECT_NEAR(k_after - k_before, 0.5 * slow_s / kFrame, 2.0);
  EXPECT_NEAR(w.shown_delay() - before, 0.5 * slow_s, 0.1);
  // A frame at a time, paused.
  w.StepFrame(1);
  Pump(50);
  const int at = w.shown(0).index;
  w.StepFrame(1);
  Pump(50);
  EXPECT_EQ(w.shown(0).index, at + 1);
  w.StepFrame(-1);
  Pump(50);
  EXPECT_EQ(w.shown(0).index, at);
  EXPECT_EQ(WhichFrame(reference, w.shown_image(0)), at);
  // Back to the delay: the picture is again the frame sent 5 s before (told by its pixels, the
  // wire's clock; the buffer still holds the stream's last 5 s).
  w.BackToLive();
  Pump(100);
  {
    const LiveWindow::Shown s = w.shown(0);
    const double expected = (s.at_s - 5.0 - t0) / kFrame;
    ASSERT_LT(expected, 298.0) << "the stream's end passed before the check";
    EXPECT_NEAR(WhichFrame(reference, w.shown_image(0)), expected, 1.0);
  }

  // The routine cut when the stream stopped (2 s of silence), its replay started by itself.
  ASSERT_TRUE(WaitUntil([&] { return w.replay_routine() == 1; }, 30000))
      << w.lines().join("\n").toStdString();
  const double first = w.replay_time_s();
  Pump(700);
  EXPECT_GT(w.replay_time_s(), first + 0.4) << "the replay does not play";
  // Its frames are the routine's, with the numbers drawn over them: the box top left differs
  // from the frame, the rest of the picture is the frame.
  const QImage replay = w.replay_image();
  ASSERT_FALSE(replay.isNull());
  // (the frame up is the last at or before the replay's time)
  const int k = static_cast<int>(std::floor(w.replay_time_s() / kFrame + 1e-6));
  const std::vector<int> drawn = Small(replay), frame = reference.at(size_t(std::min(k, 298)));
  double in_box = 0, outside = 0;
  int n_box = 0, n_out = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) {
      const double d = std::abs(drawn[size_t(y * 320 + x)] - frame[size_t(y * 320 + x)]);
      if (x >= 8 && x < 150 && y >= 8 && y < 34) {
        in_box += d;
        ++n_box;
      } else if (y < 120) {  // above the bed (its dashed line and the landing marks below)
        outside += d;
        ++n_out;
      }
    }
  EXPECT_GT(in_box / n_box, 20.0) << "no numbers drawn over the replay";
  EXPECT_LT(outside / n_out, 4.0) << "the replay is not the routine's frame " << k;
  // For the documentation: the fourth jump in the air, three landings marked (the replay plays
  // the routine in about 11 s, then again).
  if (std::getenv("ACRO_STUDIO_SCREENSHOTS") != nullptr) {
    WaitUntil([&] { return w.replay_time_s() > 6.9 && w.replay_time_s() < 7.3; }, 15000);
    Shot(w, "live_window_replay");
  }
  // The routine's analysis done in the background, its report offered beside the replay.
  ASSERT_TRUE(WaitUntil([&] { return !w.replay_report().empty(); }, 180000))
      << w.lines().join("\n").toStdString();
  EXPECT_TRUE(fs::exists(w.replay_report())) << w.replay_report();
  EXPECT_TRUE(w.lines().join("\n").contains("routine 1 analysed in"));
  // Stored under the athlete chosen on screen.
  ASSERT_TRUE(WaitUntil([&] { return w.lines().join("\n").contains("in the library"); }, 60000))
      << w.lines().join("\n").toStdString();
  {
    const library::Library season(analyses.library, library::Library::Mode::kReadOnly);
    const std::vector<library::TrialSummary> trials = season.ListTrials();
    ASSERT_EQ(trials.size(), 1u);
    EXPECT_EQ(trials[0].athlete, "Sample Athlete (Yeadon measurements)");
  }
  // Then the replay shows the full analysis: the analysis's overlay video (the athlete's model
  // drawn over the picture) with its skills in the table.
  ASSERT_TRUE(WaitUntil([&] { return w.replay_shows_analysis(); }, 30000))
      << w.lines().join("\n").toStdString();
  {
    const fs::path dir = w.replay_report().parent_path();
    // The overlay's frames, read by the test itself, and the clip's start on the session's line.
    capture::VideoReader overlay(dir / "overlay.mp4");
    std::vector<std::vector<int>> drawn_frames;
    for (int i = 0; i < overlay.num_frames(); ++i) {
      const capture::VideoFrame f = overlay.Frame(i);
      drawn_frames.push_back(
          Small(QImage(f.pixels.data(), f.width, f.height, 3 * f.width, QImage::Format_RGB888)));
    }
    std::ifstream routine_json(dir.parent_path() / "routine.json");
    const double clip_start = nlohmann::json::parse(routine_json).at("clip_start_s").get<double>();
    Pump(300);
    const int j = static_cast<int>(std::floor((w.replay_time_s() - clip_start) / kFrame + 1e-6));
    const std::vector<int> shown = Small(w.replay_image());
    const std::vector<int>& expected =
        drawn_frames.at(size_t(std::clamp(j, 0, overlay.num_frames() - 1)));
    double off = 0;
    int n = 0;
    for (int y = 0; y < 140; ++y)  // above the numbers' box
      for (int x = 0; x < 320; ++x, ++n)
        off += std::abs(shown[size_t(y * 320 + x)] - expected[size_t(y * 320 + x)]);
    EXPECT_LT(off / n, 4.0) << "the replay is not the analysis's overlay frame " << j;
    // …and not the plain clip: the overlay's drawing differs from the camera's frame.
    const std::vector<int>& plain = reference.at(size_t(
        std::clamp(static_cast<int>(std::floor(w.replay_time_s() / kFrame + 1e-6)), 0, 298)));
    double from_plain = 0;
    for (int y = 40; y < 180; ++y)
      for (int x = 0; x < 320; ++x)
        from_plain += std::abs(shown[size_t(y * 320 + x)] - plain[size_t(y * 320 + x)]);
    EXPECT_GT(from_plain / n, off / n + 0.5) << "the overlay's drawing is not seen";
    // The table: each complete jump's skill as the analysis named it, and the score sheet.
    std::ifstream jumps_json(dir / "jumps.json");
    std::vector<std::string> codes;
    for (const nlohmann::json& jump : nlohmann::json::parse(jumps_json))
      if (!jump.at("partial").get<bool>()) codes.push_back(jump.at("fig_code").get<std::string>());
    const std::vector<std::vector<std::string>> table = w.replay_table();
    ASSERT_EQ(table.size(), codes.size() + 1);
    for (size_t i = 0; i < codes.size(); ++i)
      EXPECT_EQ(table[i].at(1).substr(0, codes[i].size() + 1), codes[i] + " ") << i;
    EXPECT_NE(table.back().at(1).find("T "), std::string::npos) << table.back().at(1);
    if (std::getenv("ACRO_STUDIO_SCREENSHOTS") != nullptr) {
      WaitUntil([&] { return w.replay_time_s() > 6.9 && w.replay_time_s() < 7.3; }, 15000);
      Shot(w, "live_window_analysed");
    }
  }
  sender.join();
  w.Stop();
  ASSERT_TRUE(WaitUntil([&] { return !w.running(); }, 20000));
  Pump(100);
  ASSERT_TRUE(w.summary().has_value());
  EXPECT_EQ(w.summary()->routines.size(), 1u);
  EXPECT_EQ(w.summary()->sources.at(0).packets_recorded, 299);
  EXPECT_TRUE(w.last_error().empty()) << w.last_error();
}

// Paused while the source goes on sending: the picture holds still — the same frame, pixel for
// pixel, for 1.5 s while frames keep coming into the buffer (the sources' offsets frozen: the 95th
// percentile they come from moves with each frame) — a step moves it one frame either way, and
// playing on falls behind by the pause; back to the delay, the slider's again.
TEST(LiveWindow, APauseHoldsStillWhileTheSourceSends) {
  const fs::path out = acro::testing::ScratchDir("studio_live_pause") / "session";
  fs::remove_all(out);
  pipeline::LiveRequest request;
  request.sources = {SideVideo().string()};  // played at its own pace: a camera's
  request.out_dir = out;
  LiveWindow w(request, 1.0);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  ASSERT_TRUE(WaitUntil([&] { return w.shown(0).index >= 45; }, 20000)) << "nothing shown";
  w.SetSpeed(0.0);
  Pump(50);
  const LiveWindow::Shown held = w.shown(0);
  const QImage picture = w.shown_image(0);
  const double behind = w.shown_delay();
  int checks = 0;
  const double until = capture::LiveClockNow() + 1.5;
  while (capture::LiveClockNow() < until) {
    Pump(50);
    ASSERT_EQ(w.shown(0).index, held.index) << "the paused picture moved";
    ASSERT_TRUE(w.shown_image(0) == picture) << "the paused picture changed";
    ++checks;
  }
  EXPECT_GE(checks, 20);
  EXPECT_NEAR(w.shown_delay() - behind, 1.5, 0.15) << "a pause falls behind by its length";
  EXPECT_TRUE(w.running()) << "the source stopped sending";
  w.StepFrame(1);
  Pump(30);
  EXPECT_EQ(w.shown(0).index, held.index + 1);
  w.StepFrame(-1);
  w.StepFrame(-1);
  Pump(30);
  EXPECT_EQ(w.shown(0).index, held.index - 1);
  const double paused_behind = w.shown_delay();
  w.SetSpeed(1.0);
  Pump(500);
  EXPECT_NEAR(w.shown_delay(), paused_behind, 0.1) << "playing on keeps the pause's lateness";
  EXPECT_GT(w.shown(0).index, held.index + 5) << "it does not play on";
  w.BackToLive();
  Pump(300);
  EXPECT_NEAR(w.shown_delay(), 1.0, 0.1);
  w.Stop();
  ASSERT_TRUE(WaitUntil([&] { return !w.running(); }, 20000));
}

// A session that cannot start (the folder holds an earlier one) is a dialog naming the folder;
// the window stays.
TEST(LiveWindow, AFolderInUseIsADialog) {
  const fs::path out = acro::testing::ScratchDir("studio_live_used");
  std::ofstream(out / "jumps.jsonl") << "{}\n";
  pipeline::LiveRequest request;
  request.sources = {SideVideo().string()};
  request.out_dir = out;
  LiveWindow w(request, 1.0);
  w.show();
  ASSERT_TRUE(WaitUntil([&] { return !w.last_error().empty(); }, 10000));
  EXPECT_NE(w.last_error().find(out.string()), std::string::npos) << w.last_error();
  EXPECT_TRUE(w.isVisible());
  for (QWidget* top : QApplication::topLevelWidgets())
    if (top != &w && top->isVisible()) top->close();
}

}  // namespace
}  // namespace acro::studio

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const acro::ui::XDisplay display;
  QApplication app(argc, argv);
  return RUN_ALL_TESTS();
}
