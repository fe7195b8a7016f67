// The detector on the sample routine's side video (rendered by Acrolab itself from the simulator's
// true motion): the detections' shoulders, elbows, wrists, hips, knees and ankles against the true
// joint centres projected through the sample's calibration, per skill over every flight frame
// (docs/pose.md, "The sample routine"). Frame k of the video shows the trial's sample 69 + 4k
// (video_truth.json). Also: a keypoint far from the truth carries a low confidence — the
// confidence is honest where the pose is wrong.

#include <algorithm>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "acro/capture/video.h"
#include "acro/dynamics/kinematics.h"
#include "acro/pose/left_right.h"
#include "acro/pose/pose_tracker.h"
#include "acro/vision/camera.h"
#include "pose_model_cache.h"
#include "refdata.h"
#include "sample_routine.h"

namespace acro::pose {
namespace {

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

// BlazePose index ← the standard human's joint centre.
const std::vector<std::pair<int, const char*>> kJoints = {
    {11, "l_shoulder_jc"}, {12, "r_shoulder_jc"}, {13, "l_elbow_jc"}, {14, "r_elbow_jc"},
    {15, "l_wrist_jc"},    {16, "r_wrist_jc"},    {23, "l_hip_jc"},   {24, "r_hip_jc"},
    {25, "l_knee_jc"},     {26, "r_knee_jc"},     {27, "l_ankle_jc"}, {28, "r_ankle_jc"}};

struct Errors {
  std::vector<double> px;
  std::vector<std::pair<double, double>> error_confidence;
};

// Runs the tracker over frames [0, end) and compares every flight frame with the truth.
std::map<std::string, Errors> Measure(LandmarkModel model, int end) {
  const auto root = testing::SourceDir() / "samples";
  const samples::SampleRoutine routine =
      samples::MakeSampleRoutine(root / "athletes/sample_athlete.yaml", "samples/athletes/sample_athlete.yaml");
  const auto cameras = vision::ReadCameras(root / "trials/trampoline_routine/side_camera.toml");
  const vision::Camera& camera = cameras.front();
  capture::VideoReader video(root / "trials/trampoline_routine/side_camera.mp4");
  PoseTrackerOptions options;
  options.model = model;
  PoseTracker tracker(options);

  dynamics::Workspace<double> ws(routine.model);
  std::vector<int> points;
  for (const auto& [index, name] : kJoints) points.push_back(routine.model.FindPoint(name));
  std::map<std::string, Errors> by_skill;
  capture::VideoFrame frame;
  std::vector<FramePose> poses;
  for (int k = 0; k < std::min(end, video.num_frames()) && video.ReadNext(&frame); ++k) poses.push_back(tracker.Track(frame));
  RepairLeftRight(&poses);
  for (int k = 0; k < static_cast<int>(poses.size()); ++k) {
    const FramePose& pose = poses[k];
    const int sample = 69 + 4 * k;
    const double t = sample / routine.options.point_rate_hz;
    const samples::SampleFlightTruth* flight = nullptr;
    for (const auto& f : routine.flights)
      if (t > f.takeoff_s && t < f.landing_s) flight = &f;
    if (flight == nullptr || sample >= routine.num_frames()) continue;
    dynamics::CalcForwardKinematics<double>(routine.model, ws, routine.q.col(sample));
    Errors& e = by_skill[flight->fig_code];
    for (std::size_t j = 0; j < kJoints.size(); ++j) {
      const auto uv = camera.Project(dynamics::CalcPointPosition(routine.model, ws, points[j]));
      if (!uv) continue;
      const int b = kJoints[j].first;
      const double error = pose.found ? (pose.keypoints.block<2, 1>(0, b) - *uv).norm() : 1e9;
      e.px.push_back(error);
      if (pose.found) e.error_confidence.emplace_back(error, pose.keypoints(2, b));
    }
  }
  return by_skill;
}

TEST(SampleVideo, HeavyModelFollowsTheRenderedAthleteThroughEveryFlight) {
  ACRO_REQUIRE_POSE_MODELS();
  const auto by_skill = Measure(LandmarkModel::kHeavy, 1 << 30);
  ASSERT_EQ(by_skill.size(), 6u);
  std::vector<std::pair<double, double>> all;
  std::printf("skill   frames×joints   median px   p90 px\n");
  for (const auto& [code, e] : by_skill) {
    const double median = Quantile(e.px, 0.5), p90 = Quantile(e.px, 0.9);
    std::printf("%-6s  %13zu   %9.1f   %6.1f\n", code.c_str(), e.px.size(), median, p90);
    all.insert(all.end(), e.error_confidence.begin(), e.error_confidence.end());
    // The athlete is about 250 px tall in this 1080p view: a joint within 12 px (median) is on
    // the right limb, close to where the joint is.
    EXPECT_LT(median, 12.0) << code;
  }
  // Honest confidence: keypoints more than 40 px off (a limb put where it is not) have a lower
  // median confidence than those within 10 px.
  std::vector<double> wrong, right;
  for (const auto& [error, confidence] : all) {
    if (error > 40) wrong.push_back(confidence);
    if (error < 10) right.push_back(confidence);
  }
  std::printf("confidence: %zu keypoints > 40 px off, median %.2f; %zu within 10 px, median %.2f\n", wrong.size(),
              Quantile(wrong, 0.5), right.size(), Quantile(right, 0.5));
  if (!wrong.empty()) {
    EXPECT_LT(Quantile(wrong, 0.5), Quantile(right, 0.5) - 0.2);
  }
}

}  // namespace
}  // namespace acro::pose
