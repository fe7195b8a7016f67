// Jumps from the image motion alone (docs/live.md): a drawn athlete bouncing on a drawn bed with
// exact ballistic flights (the oracle is the physics that drew it) — take-offs and landings found
// to a fraction of a frame, at 30 and 60 frames a second, the frames before the background was
// made looked at too; nothing found while the athlete stands still.

#include "acro/vision/motion_flights.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::vision {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr double kLine = 410.0;                // the bed's middle line, image y
constexpr double kMetresPerPx = 4.28 / 400.0;  // the bed 400 px long
constexpr double kG = 9.81;

BedDetection Bed() {
  BedDetection bed;
  bed.source = "drawn";
  bed.width_px = kWidth;
  bed.height_px = kHeight;
  bed.corners_px = {Eigen::Vector2d(120, 400),
                    Eigen::Vector2d(520, 400),
                    Eigen::Vector2d(520, 420),
                    Eigen::Vector2d(120, 420)};
  return bed;
}

// The soles' height above the bed's line (m) at time t: contacts of 0.45 s sinking 0.35 m, then
// flights of the given lengths.
struct Bounces {
  std::vector<double> flight_s;
  double contact_s = 0.45;
  double first_contact_s = 0.3;
  std::vector<std::pair<double, double>> Flights() const {
    std::vector<std::pair<double, double>> out;
    double t = first_contact_s;
    for (double f : flight_s) {
      out.emplace_back(t, t + f);
      t += f + contact_s;
    }
    return out;
  }
  double Height(double t) const {
    double start = 0;
    for (const auto& [t0, t1] : Flights()) {
      if (t < t0) return -0.35 * std::sin(M_PI * (t - start) / (t0 - start));
      if (t <= t1) {
        const double v0 = kG * (t1 - t0) / 2;
        return v0 * (t - t0) - kG * (t - t0) * (t - t0) / 2;
      }
      start = t1;
    }
    return t - start < contact_s ? -0.35 * std::sin(M_PI * (t - start) / contact_s) : 0.0;
  }
};

capture::VideoFrame Draw(const Bounces& b, double t, int index, bool athlete = true) {
  capture::VideoFrame f;
  f.index = index;
  f.time_s = t;
  f.width = kWidth;
  f.height = kHeight;
  f.channels = 1;
  f.pixels.assign(static_cast<size_t>(kWidth) * kHeight, 0);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      int v = 120 + ((x * 7 + y * 13) % 9) - 4;                // a textured wall
      if (y >= 400 && y < 420 && x >= 120 && x < 520) v = 20;  // the bed
      f.pixels[static_cast<size_t>(y) * kWidth + x] = static_cast<std::uint8_t>(v);
    }
  if (!athlete) return f;
  // The athlete: 1.8 m tall, 0.3 m wide, drifting along the bed; pixel rows fully above the soles.
  const double sole_y = kLine - b.Height(t) / kMetresPerPx;
  const double x0 = 300 + 20 * std::sin(t);
  const int top = static_cast<int>(std::floor(sole_y - 1.8 / kMetresPerPx));
  for (int y = std::max(0, top); y < kHeight && y + 1 <= sole_y; ++y)
    for (int x = static_cast<int>(x0); x < static_cast<int>(x0 + 0.3 / kMetresPerPx); ++x)
      f.pixels[static_cast<size_t>(y) * kWidth + x] = 230;
  return f;
}

void CheckTiming(double fps) {
  Bounces b;
  b.flight_s = {1.2, 1.45, 1.3, 0.9};
  MotionFlightWatcher watcher(Bed());
  std::vector<MotionJump> jumps;
  const double end = b.Flights().back().second + 2.0;
  for (int k = 0; k / fps < end; ++k)
    for (const MotionJump& j : watcher.Add(Draw(b, k / fps, k), k / fps)) jumps.push_back(j);
  const auto truth = b.Flights();
  ASSERT_EQ(jumps.size(), truth.size()) << fps << " fps";
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(jumps[i].number, static_cast<int>(i + 1));
    // A pixel row is 1.07 cm, the soles cross at 5–7 m/s: about 2 ms; 4 ms allowed.
    EXPECT_NEAR(jumps[i].takeoff_s, truth[i].first, 0.004) << fps << " fps, jump " << i + 1;
    EXPECT_NEAR(jumps[i].landing_s, truth[i].second, 0.004) << fps << " fps, jump " << i + 1;
    const double apex = kG * std::pow(truth[i].second - truth[i].first, 2) / 8;
    EXPECT_NEAR(jumps[i].apex_above_bed_m, apex, 0.03 + kG / 8 / fps / fps * 4);
    // The first frame counted back on the bed (the soles within the bed's far side: 12.7 cm above
    // the line here), and where the soles were.
    EXPECT_NEAR(jumps[i].landing_frame / fps, truth[i].second, 0.03 + 1.0 / fps);
    EXPECT_NEAR(jumps[i].landing_px.y(), kLine, 0.35 / kMetresPerPx + 2);
  }
  EXPECT_FALSE(watcher.in_air());
}

TEST(MotionFlights, BallisticFlightsTimedWithinAFewMilliseconds) {
  CheckTiming(30.0);
  CheckTiming(60.0);
}

TEST(MotionFlights, NothingWhileTheAthleteStandsOrIsAbsent) {
  Bounces still;  // no flight: stands on the bed after one dip
  MotionFlightWatcher watcher(Bed());
  int found = 0;
  for (int k = 0; k < 150; ++k)
    found += static_cast<int>(watcher.Add(Draw(still, k / 30.0, k), 0).size());
  EXPECT_EQ(found, 0);
  // An empty hall: nothing found, nothing in the air.
  MotionFlightWatcher empty(Bed());
  Bounces none;
  for (int k = 0; k < 90; ++k) {
    EXPECT_TRUE(empty.Add(Draw(none, k / 30.0, k, false), 0).empty());
  }
  EXPECT_EQ(empty.frames_with_athlete(), 0);
  EXPECT_FALSE(empty.in_air());
}

TEST(MotionFlights, RefusesAPictureThatChangesSize) {
  Bounces b;
  b.flight_s = {1.0};
  MotionFlightWatcher watcher(Bed());
  watcher.Add(Draw(b, 0, 0), 0);
  capture::VideoFrame small;
  small.width = 320;
  small.height = 240;
  small.channels = 1;
  small.pixels.assign(320 * 240, 0);
  EXPECT_THROW(watcher.Add(small, 0), InputError);
}

}  // namespace
}  // namespace acro::vision
