// The model fitted to the views' 2D keypoints (docs/markerless.md, "The model fitted to the
// views"): a frame's pose recovered from its exact rays, and on the sample routine — its motion
// capture's motion as the truth, its model's BODY_25B keypoints projected into the four sample
// cameras with a detector's noise, wrong detections and confidences — the fit to the views nearer
// the truth's joint angles than triangulate-then-IK.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/capture/trial_io.h"
#include "acro/dynamics/configuration.h"
#include "acro/reconstruct/reconstruction.h"
#include "acro/reconstruct/triangulation.h"
#include "acro/reconstruct/view_fit.h"
#include "acro/vision/camera.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::filesystem::path Sample(const std::string& name) {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine" / name;
}

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Rays from each camera's centre through its exact projection of every marker.
std::vector<MarkerRay> ExactRays(const std::vector<vision::Camera>& cameras,
                                 const Eigen::Matrix3Xd& p_WM) {
  std::vector<MarkerRay> rays;
  for (int m = 0; m < p_WM.cols(); ++m)
    for (const vision::Camera& c : cameras) {
      MarkerRay ray;
      ray.marker = m;
      ray.origin_W = c.CentreInWorld();
      ray.direction_W = (p_WM.col(m) - ray.origin_W).normalized();
      rays.push_back(ray);
    }
  return rays;
}

TEST(ViewFit, ExactRaysOfFourCamerasGiveThePoseBack) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  const dynamics::Model<double> model = MakeStandardHumanModel(body);
  const std::vector<ModelMarker> markers =
      PlaceMarkers(BuiltinMarkerSet("body25b"), model, body.height_m);
  const std::vector<vision::Camera> cameras = vision::ReadCameras(Sample("views.toml"));
  // A pike with the arms forward, turned and lifted above the bed.
  const std::vector<std::string> names = MakeCoordinateNames(model);
  Eigen::VectorXd truth = dynamics::MakeNeutralConfiguration(model);
  truth.head<3>() << 0.2, -0.1, 2.6;
  dynamics::SetRootQuaternion<double>(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1, 0.2).normalized())), truth);
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].find("hip_flexion") != std::string::npos) truth[Eigen::Index(i)] = -80 * kDeg;
    if (names[i].find("shoulder_flexion") != std::string::npos) truth[Eigen::Index(i)] = -60 * kDeg;
    if (names[i].find("elbow_flexion") != std::string::npos) truth[Eigen::Index(i)] = -30 * kDeg;
    if (names[i].find("knee_flexion") != std::string::npos) truth[Eigen::Index(i)] = 10 * kDeg;
  }
  InverseKinematicsOptions options;
  options.max_iterations = 50;
  InverseKinematics ik(model, markers, StandardJointLimits(model), options);
  Eigen::Matrix3Xd p_WM;
  ik.CalcMarkerPositions(truth, p_WM);
  // The warm start 5 cm and 8° off at the root, every seen angle 6° off.
  Eigen::VectorXd q = truth;
  q.head<3>() += Eigen::Vector3d(0.05, -0.03, 0.02);
  dynamics::SetRootQuaternion<double>(
      dynamics::GetRootQuaternion(q) *
          Eigen::Quaterniond(Eigen::AngleAxisd(8 * kDeg, Eigen::Vector3d::UnitX())),
      q);
  for (size_t i = 7; i < names.size(); ++i)
    if (names[i].find("flexion") != std::string::npos &&
        names[i].find("wrist") == std::string::npos)
      q[Eigen::Index(i)] += 6 * kDeg;
  const IkFrameResult r = ik.SolveRays(ExactRays(cameras, p_WM), q);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.rms_m, 1e-4);
  EXPECT_LT((q.head<3>() - truth.head<3>()).norm(), 1e-3);
  for (size_t i = 7; i < names.size(); ++i)
    if (names[i].find("flexion") != std::string::npos &&
        names[i].find("wrist") == std::string::npos) {
      EXPECT_NEAR(q[Eigen::Index(i)], truth[Eigen::Index(i)], 0.5 * kDeg) << names[i];
    }
  // One camera alone has no depth: the rays are met (the pose is not asked for).
  Eigen::VectorXd q1 = truth;
  q1.head<3>() += Eigen::Vector3d(0.02, 0.02, 0.0);
  const IkFrameResult one = ik.SolveRays(ExactRays({cameras[0]}, p_WM), q1);
  EXPECT_LT(one.rms_m, 2e-3);
}

// The sample routine's motion capture reconstructed (the truth), its BODY_25B keypoints projected
// into the four sample cameras at 30 Hz with 4 px of noise, 4 % of the detections 40–150 px off
// and confidences between 0.4 and 1.
struct NoisyViews {
  ReconstructionResult truth;
  std::vector<int> truth_frame;  // per video frame, the motion capture's frame
  std::vector<CameraView> views;
  int wrong = 0;  // detections put 40–150 px off
};

NoisyViews ProjectSampleRoutine() {
  NoisyViews out;
  const capture::Trial trial = capture::ReadTrial(Sample("trampoline_routine.c3d"));
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  ReconstructionOptions options;
  out.truth = Reconstruct(trial, nullptr, body, options);
  const ReconstructionResult& t = out.truth;
  const MarkerSet set = BuiltinMarkerSet("body25b");
  const std::vector<ModelMarker> keypoints = PlaceMarkers(set, t.model, body.height_m);
  InverseKinematics ik(t.model, keypoints, t.joint_limits, t.ik_options);
  std::vector<std::string> names;
  for (const ModelMarker& k : keypoints) names.push_back(k.name);
  const std::vector<vision::Camera> cameras = vision::ReadCameras(Sample("views.toml"));
  const int step = static_cast<int>(std::lround(trial.point_rate_hz / 30.0));
  for (int f = 0; f < t.motion.num_frames(); f += step) out.truth_frame.push_back(f);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 4.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const vision::Camera& c : cameras) {
    CameraView view;
    view.camera = c;
    view.detections.names = names;
    for (const int f : out.truth_frame) {
      Eigen::Matrix3Xd p_WM;
      ik.CalcMarkerPositions(t.motion.q.col(f), p_WM);
      capture::DetectedPerson person = capture::DetectedPerson::Zero(3, Eigen::Index(names.size()));
      for (int j = 0; j < p_WM.cols(); ++j) {
        const auto uv = c.Project(p_WM.col(j));
        if (!uv) continue;
        Eigen::Vector2d px = *uv + Eigen::Vector2d(noise(rng), noise(rng));
        if (uniform(rng) < 0.04) {
          ++out.wrong;
          const double angle = 2 * std::numbers::pi * uniform(rng);
          px += (40 + 110 * uniform(rng)) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        }
        person.col(j) << px, 0.4 + 0.6 * uniform(rng);
      }
      view.detections.frames.push_back({person});
    }
    out.views.push_back(std::move(view));
  }
  return out;
}

// Median absolute joint-angle error (deg) of the hips', knees' and elbows' flexions in every frame
// against the truth (the shoulders' three Euler angles can differ by an equivalent triple for the
// same arm: compared nowhere).
double MedianAngleErrorDeg(const Motion& motion, const NoisyViews& v) {
  std::vector<double> errors;
  const std::vector<std::string>& names = motion.coordinate_names;
  for (size_t i = 7; i < names.size(); ++i) {
    const std::string& n = names[i];
    if (n != "r_hip_flexion" && n != "l_hip_flexion" && n != "r_knee_flexion" &&
        n != "l_knee_flexion" && n != "r_elbow_flexion" && n != "l_elbow_flexion")
      continue;
    for (int k = 0; k < motion.num_frames(); ++k) {
      const double a = motion.q(Eigen::Index(i), k);
      const double b = v.truth.motion.q(Eigen::Index(i), v.truth_frame[size_t(k)]);
      if (std::isfinite(a)) errors.push_back(std::abs(a - b) / kDeg);
    }
  }
  return Median(errors);
}

TEST(ViewFit, TheFitToTheViewsIsNearerTheTruthThanTriangulateThenIk) {
  const NoisyViews v = ProjectSampleRoutine();
  const Triangulation tri = TriangulateKeypoints(v.views);
  const capture::Trial trial = tri.ToTrial(30.0, "projected sample routine");
  const AthleteBody body = MakeDeLevaBody(1.75, 65.0, Sex::kFemale);
  ReconstructionOptions options;
  const ReconstructionResult points = Reconstruct(trial, nullptr, body, options);
  options.views =
      std::make_shared<const ViewsToFit>(MakeViewsToFit(tri, Eigen::Matrix3d::Identity()));
  const ReconstructionResult fitted = Reconstruct(trial, nullptr, body, options);
  ASSERT_TRUE(fitted.summary.view_fit);
  const ViewFitSummary& s = *fitted.summary.view_fit;
  std::printf("%s", s.Report().c_str());
  const double e_points = MedianAngleErrorDeg(points.motion, v);
  const double e_views = MedianAngleErrorDeg(fitted.motion, v);
  std::printf(
      "joint angles: median error %.2f deg triangulate-then-IK, %.2f deg fitted to the views\n",
      e_points,
      e_views);
  EXPECT_EQ(s.frames, fitted.summary.frames_fitted);
  // The wrong detections left out by the gate (nearly all of them, and few others); the rest
  // fitted.
  EXPECT_GT(s.detections_gated, 0.9 * v.wrong);
  EXPECT_LT(s.detections_gated, 1.2 * v.wrong);
  EXPECT_GT(s.detections_used, 20 * 3 * s.frames);
  EXPECT_LT(e_views, e_points);
  // The root: the fitted pelvis no farther from the truth's than the triangulated fit's.
  std::vector<double> root_points, root_views;
  for (int k = 0; k < points.motion.num_frames(); ++k) {
    const Eigen::Vector3d truth = v.truth.motion.q.col(v.truth_frame[size_t(k)]).head<3>();
    root_points.push_back((points.motion.q.col(k).head<3>() - truth).norm());
    root_views.push_back((fitted.motion.q.col(k).head<3>() - truth).norm());
  }
  std::printf("pelvis: median %.1f mm / %.1f mm from the truth's\n",
              1e3 * Median(root_points),
              1e3 * Median(root_views));
  EXPECT_LT(Median(root_views), Median(root_points) + 0.005);
}

}  // namespace
}  // namespace acro::analysis
