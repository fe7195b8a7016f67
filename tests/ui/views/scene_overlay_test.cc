// `acrolab overlay`'s drawing: the Pose2Sim balancing trial's keypoints drawn by the 3D views on
// its four cameras land where `acrolab project` puts them (vision::ProjectTrialOnFrames): the
// issue asks for 0.5 px. The frames are drawn on a black video of the cameras' size so that each
// sphere's centroid can be measured, and read back from lossless PNGs.

#include "acro/views/scene_overlay.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/vision/projection.h"
#include "refdata.h"

namespace acro::ui {
namespace {

namespace fs = std::filesystem;

TEST(SceneOverlay, KeypointsLandWhereProjectPutsThemOnAllFourCameras) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  const fs::path trc = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  ACRO_REQUIRE_REFDATA_FILE(trc);
  const capture::Trial trial = capture::ReadTrial(trc);
  const std::vector<vision::Camera> cameras =
      vision::ReadPose2SimToml(root / "calibration/Calib_qualisys.toml");
  const vision::AxisMapping axes = vision::ParseAxisMapping("zxy");
  const fs::path dir = acro::testing::ScratchDir("scene_overlay");

  // A black video of the real videos' size and rate (1080 x 1920, 60 fps; the calibration says
  // 1088 wide, the coded width), three frames.
  const capture::VideoInfo real = capture::VideoReader(root / "videos/cam01.mp4").info();
  const fs::path black = dir / "black.mp4";
  {
    capture::VideoWriterOptions w;
    w.fps = 60;
    w.crf = 0;
    w.preset = "ultrafast";
    capture::VideoWriter writer(black, real.width, real.height, w);
    const std::vector<std::uint8_t> pixels(size_t(real.width) * real.height * 3, 0);
    for (int i = 0; i < 3; ++i) writer.Write(pixels);
    writer.Finish();
  }

  double worst = 0;
  int measured = 0;
  for (const vision::Camera& camera : cameras) {
    analysis::TrialScene scene(trial, axes);
    capture::VideoReader video(black);
    SceneOverlayOptions options;
    options.show.markers = true;
    options.heads_up = false;
    options.shaded = false;
    const fs::path frames = dir / camera.name;
    WriteSceneOverlay(video, scene, camera, frames, options);
    const std::vector<vision::ProjectedPoint> points =
        vision::ProjectTrialOnFrames(trial, camera, video.frame_times_s(), options.sync, axes);
    ASSERT_FALSE(points.empty());
    std::map<int, capture::VideoFrame> decoded;
    for (const vision::ProjectedPoint& p : points) {
      // Only points with no other point within 30 px: a keypoint is a 2 cm sphere, 9–14 px
      // in radius at these distances.
      bool alone = true;
      for (const vision::ProjectedPoint& q : points)
        if (q.frame == p.frame && q.marker != p.marker && (q.uv_px - p.uv_px).norm() < 30)
          alone = false;
      if (!alone || p.uv_px.x() < 16 || p.uv_px.y() < 16 || p.uv_px.x() > real.width - 16 ||
          p.uv_px.y() > real.height - 16)
        continue;
      if (!decoded.count(p.frame)) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%06d.png", p.frame);
        decoded[p.frame] = capture::VideoReader(frames / name).Frame(0);
      }
      const capture::VideoFrame& f = decoded[p.frame];
      double sum = 0, su = 0, sv = 0;
      for (int v = int(p.uv_px.y()) - 15; v <= int(p.uv_px.y()) + 15; ++v) {
        for (int u = int(p.uv_px.x()) - 15; u <= int(p.uv_px.x()) + 15; ++u) {
          const double w = f.pixels[(size_t(v) * f.width + u) * 3 + 0];  // red: the marker colour
          sum += w;
          su += w * u;
          sv += w * v;
        }
      }
      ASSERT_GT(sum, 255.0 * 20) << camera.name << " frame " << p.frame << " point " << p.marker;
      const double e = (Eigen::Vector2d(su / sum, sv / sum) - p.uv_px).norm();
      worst = std::max(worst, e);
      ++measured;
    }
  }
  EXPECT_GT(measured, 100);
  EXPECT_LT(worst, 0.5) << "worst keypoint " << worst << " px from acrolab project's pixel";
  std::printf(
      "%d keypoints on 4 cameras: worst %.3f px from acrolab project's pixel\n", measured, worst);
}

}  // namespace
}  // namespace acro::ui
