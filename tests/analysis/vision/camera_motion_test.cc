// Whether the camera held still (camera_motion.h): the sample routine's side video, a tripod, reads
// no shift; a pan made from it with ffmpeg's crop (the window still for a second, then sliding
// 200 px at 100 px/s) reads the window's slide, and the flights timed while it slid are named.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/vision/camera_motion.h"
#include "refdata.h"

namespace acro::vision {
namespace {

std::filesystem::path SideVideo() {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";
}

// Flights at 30 fps, each from its last frame on the bed to its first back on it (−1: in the air
// at the video's end).
ImageFlights Flights(const std::vector<std::pair<int, int>>& contacts) {
  ImageFlights flights;
  flights.rate_hz = 30;
  for (const auto& [last_on_bed, back_on_bed] : contacts) {
    ImageFlight f;
    f.last_contact_frame = last_on_bed;
    f.first_contact_frame = back_on_bed;
    flights.flights.push_back(f);
  }
  return flights;
}

TEST(CameraMotion, TheSampleTripodHoldsStill) {
  const CameraMotion m = MeasureCameraMotion(SideVideo());
  ASSERT_GT(m.frames.size(), 90u);
  EXPECT_EQ(m.FirstMovedFrame(), -1);
  EXPECT_LT(m.LargestShiftPx(0, 1 << 30), 1.0);
  const ImageFlights flights = Flights({{40, 80}});
  EXPECT_TRUE(CameraMotionWarnings(m, flights).empty());
}

TEST(CameraMotion, APanIsMeasuredAndTheFlightsDuringItAreNamed) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  const std::filesystem::path dir = acro::testing::ScratchDir("camera_motion");
  const std::filesystem::path pan = dir / "pan.mp4";
  const std::string cmd = "ffmpeg -v error -y -i '" + SideVideo().string() +
                          "' -t 4 -vf \"crop=1600:900:'min(200,max(0,(t-1)*100))':90\" "
                          "-c:v libx264 -crf 18 -pix_fmt yuv420p '" +
                          pan.string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const CameraMotion m = MeasureCameraMotion(pan);
  ASSERT_GT(m.frames.size(), 35u);
  // Still for the first second, then the window's slide, 200 px at the end.
  for (size_t i = 0; i < m.frames.size(); ++i) {
    const double t = m.frames[i] / 30.0;
    const double expected = std::min(200.0, std::max(0.0, (t - 1) * 100));
    EXPECT_NEAR(m.shift[i].norm(), expected, 3.0) << "frame " << m.frames[i];
    EXPECT_LT(std::abs(m.shift[i].y()), 2.0) << "frame " << m.frames[i];
  }
  EXPECT_GT(m.FirstMovedFrame(), 30);
  EXPECT_LT(m.FirstMovedFrame(), 36);
  // A flight before the pan is not named; one during it is, with the shift.
  const ImageFlights flights = Flights({{2, 25}, {60, 100}});
  const std::vector<std::string> w = CameraMotionWarnings(m, flights);
  for (const std::string& line : w) std::printf("%s\n", line.c_str());
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("the camera moves"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find(pan.string()), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("flight 2 (2.03–3.30 s)"), std::string::npos) << w[1];
}

// A camera knocked: the picture jumps 200 px between two frames, too far to follow — every flight
// from there on is named, none before.
TEST(CameraMotion, AKnockedCameraIsLostAndEveryLaterFlightNamed) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "the ffmpeg command is not installed (scripts/install-deps.sh)";
  const std::filesystem::path dir = acro::testing::ScratchDir("camera_knock");
  const std::filesystem::path knock = dir / "knock.mp4";
  const std::string cmd = "ffmpeg -v error -y -i '" + SideVideo().string() +
                          "' -t 4 -vf \"crop=1600:900:'if(gt(t,1.5),200,0)':90\" "
                          "-c:v libx264 -crf 18 -pix_fmt yuv420p '" +
                          knock.string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const CameraMotion m = MeasureCameraMotion(knock);
  ASSERT_EQ(m.lost_frames.size(), 1u);
  // The knock at frame 45 (1.5 s): lost within a few compared frames, and moved from the first
  // frame compared after it (a few patches may agree on a wrong shift for a frame or two).
  EXPECT_GE(m.lost_frames[0], 45);
  EXPECT_LE(m.lost_frames[0], 54);
  EXPECT_GE(m.FirstMovedFrame(), 45);
  EXPECT_LE(m.FirstMovedFrame(), m.lost_frames[0]);
  const ImageFlights flights = Flights({{2, 40}, {44, 80}, {85, 110}});
  const std::vector<std::string> w = CameraMotionWarnings(m, flights);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("turned too far to follow"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("flight 2"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("flight 3"), std::string::npos) << w[2];
}

// The rules on measured motion, without a video: a background lost with no shift before it is a
// camera that moved; a flight still in the air at the video's end, after the loss, is named; a
// motion that could not be measured is said, not taken for a still camera.
TEST(CameraMotion, ALossIsAMoveAndTheFlightsAfterItAreNamed) {
  CameraMotion m;
  m.path = "v.mp4";
  m.frames = {0, 3, 6};
  m.shift.assign(3, Eigen::Vector2d(0.5, 0));
  m.lost_frames = {9};
  EXPECT_EQ(m.FirstMovedFrame(), 9);
  const ImageFlights flights = Flights({{0, 6}, {10, -1}});  // the second in the air at the end
  const std::vector<std::string> w = CameraMotionWarnings(m, flights);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("turned too far to follow"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("flight 2 (from 0.37 s)"), std::string::npos) << w[1];
  CameraMotion unmeasured;
  unmeasured.path = "dark.mp4";
  unmeasured.unmeasured = "its first frame has too little texture to follow";
  const std::vector<std::string> u = CameraMotionWarnings(unmeasured, flights);
  ASSERT_EQ(u.size(), 1u);
  EXPECT_NE(u[0].find("dark.mp4: whether the camera held still is not known"), std::string::npos)
      << u[0];
}

TEST(CameraMotion, NoVideoIsOneLineNamingTheFile) {
  try {
    MeasureCameraMotion("/nonexistent/pan.mp4");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/pan.mp4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace acro::vision
