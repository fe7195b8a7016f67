// `acrolab overlay`'s drawing: the Pose2Sim balancing trial's keypoints drawn by the 3D views on
// its four cameras land where `acrolab project` puts them (vision::ProjectTrialOnFrames): the
// issue asks for 0.5 px. The frames are drawn on a black video of the cameras' size so that each
// sphere's centroid can be measured, and read back from lossless PNGs.

#include "acro/views/scene_overlay.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/vision/projection.h"
#include "acro/vision/silhouette.h"
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

// The silhouettes' mismatch on the sample video (its true offset −0.575 s): drawn alone (no actor,
// no heads-up), the frame changes only where the filmed and the modelled athlete differ — a thin
// rim with the right sync, whole limbs with the sync 3 frames late.
TEST(SceneOverlay, TheMismatchShowsAWrongSync) {
  const fs::path dir = acro::testing::SourceDir() / "samples/trials/trampoline_routine";
  const capture::Trial trial = capture::ReadTrial(dir / "trampoline_routine.c3d");
  const analysis::AthleteBody body = analysis::MakeAthleteBody(analysis::ReadAthleteProfile(
      acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml"));
  const analysis::TrialAnalysis analysis = analysis::AnalyzeTrial(trial, nullptr, body);
  const vision::Camera camera = vision::ReadPose2SimToml(dir / "side_camera.toml").at(0);
  capture::VideoReader frames(dir / "side_camera.mp4");
  const vision::BackgroundModel background(frames);
  const capture::VideoFrame filmed = capture::VideoReader(dir / "side_camera.mp4").Frame(110);
  const fs::path out = acro::testing::ScratchDir("overlay_mismatch");
  std::map<std::string, int> tinted;
  for (const auto& [name, offset_s] :
       std::map<std::string, double>{{"right", -0.575}, {"late", -0.575 + 3.0 / 30}}) {
    analysis::TrialScene scene(
        trial,
        analysis,
        body,
        analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()));
    capture::VideoReader video(dir / "side_camera.mp4");
    SceneOverlayOptions options;
    options.show.mismatch = true;
    options.heads_up = false;
    options.background = &background;
    options.sync.offset_s = offset_s;
    options.first_frame = options.last_frame = 110;
    WriteSceneOverlay(video, scene, camera, out / name, options);
    const capture::VideoFrame drawn =
        capture::VideoReader(out / name / "frame_000110.png").Frame(0);
    ASSERT_EQ(drawn.pixels.size(), filmed.pixels.size());
    int changed = 0;
    for (size_t i = 0; i < drawn.pixels.size(); i += 3) {
      int d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(drawn.pixels[i + c] - filmed.pixels[i + c]));
      changed += d > 30 ? 1 : 0;
    }
    tinted[name] = changed;
  }
  std::printf("mismatch pixels at frame 110: %d with the right sync, %d with 3 frames late\n",
              tinted["right"],
              tinted["late"]);
  EXPECT_GT(tinted["right"], 0);
  EXPECT_GT(tinted["late"], 4 * tinted["right"]);
}

}  // namespace
}  // namespace acro::ui
