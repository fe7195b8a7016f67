// Cameras started at different moments, found on one time line from their detections alone
// (docs/markerless.md, "Sync"): s2mLab's routine projected into its 8 calibrated cameras, with
// noise, one camera late by 7 frames, one by a fraction of a frame, one filming at half the rate.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/reconstruct/triangulation.h"
#include "acro/reconstruct/view_sync.h"
#include "acro/vision/camera.h"
#include "refdata.h"

namespace {

using acro::analysis::CameraView;
using acro::vision::Camera;

std::filesystem::path S2m(const std::string& rel) {
  return acro::testing::RefdataFile("s2mLab-EKF_multicamera-trampoline/inputs/" + rel);
}

// The truth's point j at fractional frame s (linear between frames), NaN outside or in a gap.
Eigen::Vector3d TruthAt(const acro::capture::Trial& truth, double s, int j) {
  const int i = static_cast<int>(std::floor(s));
  if (i < 0 || i + 1 >= truth.num_frames) return Eigen::Vector3d::Constant(NAN);
  const double w = s - i;
  if (!truth.valid(i, j) || !truth.valid(i + 1, j)) return Eigen::Vector3d::Constant(NAN);
  return (1 - w) * truth.position(i, j) + w * truth.position(i + 1, j);
}

// What `camera` films at `rate_hz` when its frame 0 is the truth's (120 Hz) frame `start`: the
// projections, 1.5 px of noise, `frames` frames.
CameraView Film(const Camera& camera,
                const acro::capture::Trial& truth,
                double start,
                double rate_hz,
                int frames,
                std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, 1.5);
  CameraView view;
  view.camera = camera;
  for (const auto& p : truth.points) view.detections.names.push_back(p.label);
  const int n = truth.num_points();
  for (int k = 0; k < frames; ++k) {
    const double s = start + k * truth.point_rate_hz / rate_hz;
    acro::capture::DetectedPerson person = acro::capture::DetectedPerson::Zero(3, n);
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d X = TruthAt(truth, s, j);
      if (!X.allFinite()) continue;
      const auto uv = camera.Project(X);
      if (!uv) continue;
      person.col(j) << *uv + Eigen::Vector2d(noise(*rng), noise(*rng)), 0.9;
    }
    view.detections.frames.push_back({person});
  }
  return view;
}

TEST(ViewSync, FindsEachCamerasOffsetToATenthOfAFrame) {
  ACRO_REQUIRE_REFDATA_FILE(S2m("trc/1_partie_0429_002.trc"));
  const std::vector<Camera> cameras = acro::vision::ReadPose2SimToml(S2m("calibration/Calib.toml"));
  const acro::capture::Trial truth = acro::capture::ReadTrial(S2m("trc/1_partie_0429_002.trc"));
  ASSERT_EQ(truth.point_rate_hz, 120.0);
  std::mt19937 rng(11);
  // Camera 0 starts at the truth's frame 100 and films 700 frames; camera 3 started 7 frames
  // later, camera 5 7.4 frames earlier, camera 6 films at 60 Hz from 20.25 frames later; the
  // others with camera 0.
  const std::vector<double> starts = {100, 100, 100, 107, 100, 92.6, 120.25, 100};
  const std::vector<double> rates = {120, 120, 120, 120, 120, 120, 60, 120};
  std::vector<CameraView> views;
  for (size_t c = 0; c < cameras.size(); ++c)
    views.push_back(Film(cameras[c], truth, starts[c], rates[c], rates[c] == 60 ? 340 : 700, &rng));
  const auto offsets = acro::analysis::SyncViews(views, rates);
  ASSERT_EQ(offsets.size(), 8u);
  for (size_t c = 0; c < cameras.size(); ++c) {
    const double expected = starts[c] - starts[0];
    std::printf("%s: offset %.3f frames (true %.2f), cost %.2f px, runner-up %.2f px, %d pairs\n",
                offsets[c].camera.c_str(),
                offsets[c].offset_frames,
                expected,
                offsets[c].cost_px,
                offsets[c].runner_up_cost_px,
                offsets[c].pairs);
    EXPECT_NEAR(offsets[c].offset_frames, expected, 1.0 / 3.0) << offsets[c].camera;
    if (c > 0) {
      EXPECT_GT(offsets[c].runner_up_cost_px, 2 * offsets[c].cost_px) << offsets[c].camera;
      EXPECT_TRUE(offsets[c].distinct) << offsets[c].camera;
    }
  }
  // On the first camera's time line, the triangulation is the truth again (1.5 px noise).
  std::vector<CameraView> synced;
  for (size_t c = 0; c < cameras.size(); ++c) {
    CameraView v{views[c].camera,
                 acro::analysis::ResampleDetections(
                     views[c].detections, rates[c], 120, offsets[c].offset_frames, 700)};
    synced.push_back(std::move(v));
  }
  const acro::analysis::Triangulation t = acro::analysis::TriangulateKeypoints(synced);
  std::vector<double> d;
  for (int k = 0; k < 700; ++k)
    for (int j = 0; j < t.num_points(); ++j)
      if (t.position(k, j).allFinite() && truth.valid(100 + k, j))
        d.push_back((t.position(k, j) - truth.position(100 + k, j)).norm());
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  EXPECT_GT(d.size(), 700u * 15u);
  EXPECT_LT(d[d.size() / 2], 0.006);
}

TEST(ViewSync, ResamplesBetweenFramesAndRefusesWhatCannotBeSynced) {
  acro::capture::KeypointDetections d;
  d.names = {"Nose"};
  for (int k = 0; k < 5; ++k) {
    acro::capture::DetectedPerson p(3, 1);
    p << 10.0 * k, 100.0, k == 3 ? 0.0 : 0.8;
    d.frames.push_back({p});
  }
  // Half the rate, 1 frame late: target frame k is source frame (k − 1) / 2.
  const auto r = acro::analysis::ResampleDetections(d, 60, 120, 1.0, 8);
  ASSERT_EQ(r.num_frames(), 8);
  EXPECT_TRUE(r.frames[0].empty());
  EXPECT_NEAR(r.frames[1][0](0, 0), 0.0, 1e-12);
  EXPECT_NEAR(r.frames[2][0](0, 0), 5.0, 1e-12);
  EXPECT_NEAR(r.frames[3][0](0, 0), 10.0, 1e-12);
  EXPECT_NEAR(r.frames[4][0](0, 0), 15.0, 1e-12);
  EXPECT_NEAR(r.frames[5][0](0, 0), 20.0, 1e-12);
  EXPECT_TRUE(r.frames[6].empty());  // between frame 2 and frame 3, which has no nose
  EXPECT_TRUE(r.frames[7].empty());
  acro::analysis::CameraView a, b;
  a.camera.name = "a";
  a.camera.K << 1000, 0, 500, 0, 1000, 500, 0, 0, 1;
  a.camera.width_px = a.camera.height_px = 1000;
  b = a;
  b.camera.name = "b";
  b.camera.t_KW = Eigen::Vector3d(1, 0, 0);
  a.detections = d;
  b.detections = d;
  EXPECT_THROW(acro::analysis::SyncViews({a, b}, {120, 120}), acro::InputError);  // too few pairs
  EXPECT_THROW(acro::analysis::SyncViews({a}, {120}), acro::InputError);
  EXPECT_THROW(acro::analysis::SyncViews({a, b}, {120, 0}), acro::InputError);
}

}  // namespace
