// The sample routine's video (samples/trials/trampoline_routine/side_camera.mp4, made by
// tools/make_sample_video.cc from the routine's true motion, 0.575 s after the mocap started)
// against the analysis of its C3D: the automatic sync finds the offset within a third of a frame;
// the reconstructed athlete's silhouette matches the video's over the flights (median IoU ≥ 0.85,
// the figure); with the sync 3 frames off the IoU drops by at least 0.1 — the silhouette
// sees a wrong sync.

#include "acro/scene/silhouette_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/capture/trial_io.h"
#include "acro/vision/sync.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

namespace fs = std::filesystem;

struct Sample {
  capture::Trial trial;
  AthleteBody body;
  TrialAnalysis analysis;
  vision::Camera camera;
  double offset_s = 0;
  fs::path video;
};

const Sample& TheSample() {
  static const Sample sample = [] {
    const fs::path dir = acro::testing::SourceDir() / "samples/trials/trampoline_routine";
    Sample s;
    s.trial = capture::ReadTrial(dir / "trampoline_routine.c3d");
    s.body = MakeAthleteBody(
        ReadAthleteProfile(acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml"));
    s.analysis = AnalyzeTrial(s.trial, nullptr, s.body);
    s.camera = vision::ReadPose2SimToml(dir / "side_camera.toml").at(0);
    std::ifstream truth(dir / "video_truth.json");
    s.offset_s = nlohmann::json::parse(truth)["offset_s"].get<double>();
    s.video = dir / "side_camera.mp4";
    return s;
  }();
  return sample;
}

SilhouetteCheck Check(double offset_s) {
  const Sample& s = TheSample();
  TrialScene scene(s.trial, s.analysis, s.body, MakeEllipsoidBodyMesh(s.body));
  capture::VideoReader video(s.video);
  SilhouetteCheckOptions options;
  options.sync.offset_s = offset_s;
  return CheckSilhouettes(video, scene, s.camera, options);
}

TEST(SilhouetteCheck, TheAutomaticSyncFindsTheSampleVideosOffset) {
  const Sample& s = TheSample();
  capture::VideoReader video(s.video, {.pixels = capture::VideoPixels::kGrey});
  const vision::AutoSyncResult found = vision::SyncFromImageMotion(s.trial, s.camera, video);
  const double frame_s = 1.0 / video.info().average_fps;
  std::printf("sync: %.4f s found, %.4f s true (%.2f frames off)\n",
              found.sync.offset_s,
              s.offset_s,
              (found.sync.offset_s - s.offset_s) / frame_s);
  EXPECT_NEAR(found.sync.offset_s, s.offset_s, frame_s / 3);

  // Refined by the silhouettes (±1 frame, one trial sample at a time): the true sample.
  TrialScene scene(s.trial, s.analysis, s.body, MakeEllipsoidBodyMesh(s.body));
  capture::VideoReader colour(s.video);
  SilhouetteCheckOptions options;
  options.sync = found.sync;
  const SilhouetteSync refined = RefineSyncBySilhouettes(colour, scene, s.camera, options, frame_s);
  std::printf("refined by the silhouettes: %.4f s (%.2f frames off), median IoU %.3f\n",
              refined.sync.offset_s,
              (refined.sync.offset_s - s.offset_s) / frame_s,
              refined.median_iou);
  EXPECT_NEAR(refined.sync.offset_s, s.offset_s, 0.5 / s.trial.point_rate_hz);
  EXPECT_GE(refined.median_iou, 0.85);
}

TEST(SilhouetteCheck, TheReconstructionMatchesTheVideoAndAWrongSyncShows) {
  const Sample& s = TheSample();
  const SilhouetteCheck right = Check(s.offset_s);
  ASSERT_GT(right.iou.size(), 150u);  // six flights, about 8.5 s of flight at 30 fps
  ASSERT_EQ(right.flight_median_iou.size(), s.analysis.phases.flights.size());
  std::printf(
      "IoU over %zu flight frames: median %.3f; per flight:", right.iou.size(), right.median_iou);
  for (const double m : right.flight_median_iou) std::printf(" %.3f", m);
  std::printf("\n");
  EXPECT_GE(right.median_iou, 0.85);
  const double frame_s = 1.0 / 30;
  const SilhouetteCheck late = Check(s.offset_s + 3 * frame_s);
  const SilhouetteCheck early = Check(s.offset_s - 3 * frame_s);
  std::printf(
      "3 frames late: median %.3f; 3 frames early: %.3f\n", late.median_iou, early.median_iou);
  EXPECT_LE(late.median_iou, right.median_iou - 0.1);
  EXPECT_LE(early.median_iou, right.median_iou - 0.1);
}

// The comparison with the foreground worked out in the athlete's box alone (what the check and the
// overlay do) gives the IoU, the box and the masks in it of the whole frame's foreground.
TEST(SilhouetteCheck, TheForegroundInTheBoxGivesTheWholeFramesComparison) {
  const Sample& s = TheSample();
  TrialScene scene(s.trial, s.analysis, s.body, MakeEllipsoidBodyMesh(s.body));
  capture::VideoReader video(s.video);
  const vision::BackgroundModel background(video, 25);
  vision::VideoSync sync;
  sync.offset_s = s.offset_s;
  int compared = 0;
  for (int k = 20; k < video.num_frames(); k += 23) {
    const int sample = sync.NearestSample(s.trial, video.frame_times_s()[size_t(k)]);
    if (sample < 0) continue;
    TrialFrame tf;
    scene.Frame(sample, &tf);
    const capture::VideoFrame frame = video.Frame(k);
    const vision::BackgroundOptions options;
    SilhouetteFrame whole, boxed;
    const vision::Mask all = background.Foreground(frame, options);
    CompareSilhouettes(all, tf, s.camera, 0.1, &whole);
    vision::Mask part;
    CompareSilhouettes(background, frame, options, tf, s.camera, 0.1, &part, &boxed);
    ASSERT_GT(whole.x1, whole.x0) << "frame " << k;
    EXPECT_EQ(boxed.iou, whole.iou) << "frame " << k;
    EXPECT_GT(boxed.iou, 0.3) << "frame " << k;
    EXPECT_EQ(boxed.x0, whole.x0);
    EXPECT_EQ(boxed.y0, whole.y0);
    EXPECT_EQ(boxed.x1, whole.x1);
    EXPECT_EQ(boxed.y1, whole.y1);
    for (int y = whole.y0; y < whole.y1; ++y)
      for (int x = whole.x0; x < whole.x1; ++x)
        ASSERT_EQ(part.pixels[size_t(y) * size_t(part.width) + size_t(x)],
                  all.pixels[size_t(y) * size_t(all.width) + size_t(x)])
            << "frame " << k << " pixel " << x << "," << y;
    ++compared;
  }
  EXPECT_GE(compared, 8);
}

}  // namespace
}  // namespace acro::analysis
