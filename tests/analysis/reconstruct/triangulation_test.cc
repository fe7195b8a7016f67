// Triangulation of 2D keypoints from calibrated views (docs/markerless.md): exact on exact
// projections, robust to a wrong view, a second person and a camera that turned left and right
// over, and against two peers on real data — s2mLab's own 3D keypoints of a trampoline routine
// (8 cameras) and Pose2Sim's triangulation of its balancing trial (4 cameras, OpenPose).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/capture/trial_io.h"
#include "acro/reconstruct/triangulation.h"
#include "acro/vision/camera.h"
#include "refdata.h"

namespace {

namespace fs = std::filesystem;
using acro::analysis::CameraView;
using acro::analysis::TriangulateKeypoints;
using acro::analysis::Triangulation;
using acro::analysis::TriangulationOptions;
using acro::vision::Camera;

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

fs::path S2m(const std::string& rel) {
  return acro::testing::RefdataFile("s2mLab-EKF_multicamera-trampoline/inputs/" + rel);
}

// A camera at `centre` looking at `target`, z up in the world, 1920 × 1080, f = 1400 px, with a
// little distortion.
Camera LookAt(const std::string& name,
              const Eigen::Vector3d& centre,
              const Eigen::Vector3d& target) {
  Camera c;
  c.name = name;
  c.width_px = 1920;
  c.height_px = 1080;
  c.K << 1400, 0, 960, 0, 1400, 540, 0, 0, 1;
  c.distortion = {-0.08, 0.02, 0.0005, -0.0003};
  acro::vision::AimCamera(&c, centre, target);
  return c;
}

std::vector<Camera> FourCameras() {
  const Eigen::Vector3d target(0, 0, 1.5);
  return {LookAt("north", {0, 7, 2.0}, target),
          LookAt("east", {7, 0.5, 1.8}, target),
          LookAt("south", {0.5, -7, 2.2}, target),
          LookAt("west", {-7, -0.3, 1.6}, target)};
}

TEST(Triangulation, RecoversAPointFromItsExactProjections) {
  const std::vector<Camera> cameras = FourCameras();
  const Eigen::Vector3d truth(0.31, -0.42, 2.73);
  std::vector<const Camera*> pointers;
  std::vector<Eigen::Vector2d> pixels;
  for (const Camera& c : cameras) {
    pointers.push_back(&c);
    pixels.push_back(*c.Project(truth));
  }
  const Eigen::Vector3d X = acro::analysis::TriangulatePoint(pointers, pixels, {1, 0.5, 0.8, 0.9});
  EXPECT_LT((X - truth).norm(), 1e-8);
  // Two views are enough; one is not.
  EXPECT_LT((acro::analysis::TriangulatePoint(
                 {pointers[0], pointers[1]}, {pixels[0], pixels[1]}, {1, 1}) -
             truth)
                .norm(),
            1e-8);
  EXPECT_FALSE(acro::analysis::TriangulatePoint({pointers[0]}, {pixels[0]}, {1}).allFinite());
}

TEST(Triangulation, NamesItsLeftRightPairs) {
  const std::vector<std::string> names = {"Nose",
                                          "LShoulder",
                                          "RShoulder",
                                          "L Hip",
                                          "R Hip",
                                          "left_knee",
                                          "right_knee",
                                          "Neck",
                                          "LBigToe",
                                          "RBigToe"};
  const auto pairs = acro::analysis::LeftRightPairsOfNames(names);
  ASSERT_EQ(pairs.size(), 4u);
  EXPECT_EQ(pairs[0], std::make_pair(1, 2));
  EXPECT_EQ(pairs[1], std::make_pair(3, 4));
  EXPECT_EQ(pairs[2], std::make_pair(5, 6));
  EXPECT_EQ(pairs[3], std::make_pair(8, 9));
}

// s2mLab's whole routine (17 COCO keypoints, 1261 frames at 120 Hz) projected exactly into its 8
// cameras: the detections a perfect detector would give.
struct ProjectedRoutine {
  std::vector<Camera> cameras;
  acro::capture::Trial truth;
  std::vector<CameraView> views;
};

ProjectedRoutine ProjectRoutine(int frames) {
  ProjectedRoutine r;
  r.cameras = acro::vision::ReadPose2SimToml(S2m("calibration/Calib.toml"));
  r.truth = acro::capture::ReadTrial(S2m("trc/1_partie_0429_002.trc"));
  std::vector<std::string> names;
  for (const auto& p : r.truth.points) names.push_back(p.label);
  for (const Camera& c : r.cameras) {
    CameraView view;
    view.camera = c;
    view.detections.names = names;
    view.detections.frames.resize(frames);
    for (int k = 0; k < frames; ++k) {
      acro::capture::DetectedPerson person = acro::capture::DetectedPerson::Zero(3, names.size());
      for (int j = 0; j < static_cast<int>(names.size()); ++j) {
        if (!r.truth.valid(k, j)) continue;
        const auto uv = c.Project(r.truth.position(k, j));
        if (!uv) continue;
        person.col(j) << *uv, 0.9;
      }
      view.detections.frames[k].push_back(person);
    }
    r.views.push_back(std::move(view));
  }
  return r;
}

TEST(Triangulation, ExactDetectionsOfARoutineGiveItsPointsBack) {
  ACRO_REQUIRE_REFDATA_FILE(S2m("trc/1_partie_0429_002.trc"));
  const int frames = 240;
  const ProjectedRoutine r = ProjectRoutine(frames);
  const Triangulation t = TriangulateKeypoints(r.views);
  ASSERT_EQ(t.num_frames, frames);
  double worst = 0;
  int compared = 0;
  for (int k = 0; k < frames; ++k)
    for (int j = 0; j < t.num_points(); ++j) {
      if (!r.truth.valid(k, j)) continue;
      ASSERT_TRUE(t.position(k, j).allFinite()) << k << " " << j;
      worst = std::max(worst, (t.position(k, j) - r.truth.position(k, j)).norm());
      ++compared;
    }
  EXPECT_GT(compared, frames * 15);
  EXPECT_LT(worst, 1e-6);
  for (const auto& c : t.cameras) {
    EXPECT_EQ(c.rejected, 0) << c.name;
    EXPECT_EQ(c.left_right_repairs, 0) << c.name;
    EXPECT_LT(c.median_reprojection_px, 1e-6) << c.name;
  }
}

TEST(Triangulation, OutvotesAWrongViewPicksTheAthleteAndPutsASwappedCameraRight) {
  ACRO_REQUIRE_REFDATA_FILE(S2m("trc/1_partie_0429_002.trc"));
  const int frames = 120;
  ProjectedRoutine r = ProjectRoutine(frames);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.5);
  for (CameraView& v : r.views)
    for (auto& people : v.detections.frames)
      for (auto& p : people)
        for (int j = 0; j < p.cols(); ++j)
          if (p(2, j) > 0) p.block<2, 1>(0, j) += Eigen::Vector2d(noise(rng), noise(rng));
  const std::vector<std::string>& names = r.views[0].detections.names;
  const auto pairs = acro::analysis::LeftRightPairsOfNames(names);
  ASSERT_EQ(pairs.size(), 8u);  // eyes, ears, shoulders, elbows, wrists, hips, knees, ankles
  // Camera 2: left and right exchanged (the whole body) over frames 30–39.
  for (int k = 30; k < 40; ++k)
    for (const auto& [a, b] : pairs) {
      auto& p = r.views[2].detections.frames[k][0];
      p.col(a).swap(p.col(b));
    }
  // Camera 5: the left wrist 200 px off over frames 50–59 (a hand mistaken for something else).
  const int l_wrist = 9;
  ASSERT_EQ(names[l_wrist], "L Wrist");
  for (int k = 50; k < 60; ++k) r.views[5].detections.frames[k][0](0, l_wrist) += 200;
  // Camera 0: a second person (a coach beside the bed) listed first, more confident, in every
  // frame.
  for (auto& people : r.views[0].detections.frames) {
    acro::capture::DetectedPerson coach = people[0];
    coach.row(0).array() += 450;
    coach.row(2).setConstant(1.0);
    people.insert(people.begin(), coach);
  }
  const Triangulation t = TriangulateKeypoints(r.views);
  std::vector<double> d;
  double worst = 0;
  for (int k = 0; k < frames; ++k)
    for (int j = 0; j < t.num_points(); ++j) {
      if (!r.truth.valid(k, j) || !t.position(k, j).allFinite()) continue;
      const double e = (t.position(k, j) - r.truth.position(k, j)).norm();
      d.push_back(e);
      worst = std::max(worst, e);
    }
  // 1.5 px of noise at 5–8 m with f ≈ 1700 px and 8 views: a few millimetres.
  EXPECT_LT(Median(d), 0.005);
  // The standard error the fits predict against the errors made: the median length of a 3D
  // Gaussian error is 1.54 σ per coordinate.
  const double sigma = Median(d) / 1.54;
  std::printf(
      "standard error predicted %.2f mm, measured %.2f mm\n", 1000 * t.NoiseRmsM(), 1000 * sigma);
  EXPECT_GT(t.NoiseRmsM(), 0.5 * sigma);
  EXPECT_LT(t.NoiseRmsM(), 2.0 * sigma);
  EXPECT_LT(worst, 0.05);
  EXPECT_EQ(t.cameras[0].frames_chosen_among_several, frames);
  EXPECT_EQ(t.cameras[0].rejected, 0) << "the coach was taken for the athlete";
  // Every exchanged pair whose sides camera 2 sees apart (more than twice the agreement threshold
  // between them: closer, the exchange is within the noise and does no harm) was put right, and
  // nothing in the other cameras.
  int exchanged = 0, distinguishable = 0;
  for (int k = 30; k < 40; ++k)
    for (const auto& [a, b] : pairs) {
      const auto& p = r.views[2].detections.frames[k][0];
      if (!(p(2, a) > 0 && p(2, b) > 0)) continue;
      ++exchanged;
      distinguishable += (p.col(a).head<2>() - p.col(b).head<2>()).norm() > 30;
    }
  EXPECT_GE(distinguishable, 20);  // camera 2 sees the body partly edge-on
  EXPECT_GE(t.cameras[2].left_right_repairs, distinguishable);
  EXPECT_LE(t.cameras[2].left_right_repairs, exchanged);
  for (int k = 30; k < 40; ++k)
    for (const auto& [a, b] : pairs)
      if (r.truth.valid(k, a) && r.truth.valid(k, b)) {
        EXPECT_LT((t.position(k, a) - r.truth.position(k, a)).norm(), 0.02) << k << " " << names[a];
        EXPECT_LT((t.position(k, b) - r.truth.position(k, b)).norm(), 0.02) << k << " " << names[b];
      }
  for (int v : {0, 1, 3, 4, 5, 6, 7}) EXPECT_EQ(t.cameras[v].left_right_repairs, 0) << v;
  EXPECT_GE(t.cameras[5].rejected, 10);
  // The wrist through those frames is where it was.
  for (int k = 50; k < 60; ++k)
    EXPECT_LT((t.position(k, l_wrist) - r.truth.position(k, l_wrist)).norm(), 0.02) << k;
}

TEST(Triangulation, RefusesWhatCannotBeTriangulatedAndSaysWhatItLeftOut) {
  const std::vector<Camera> cameras = FourCameras();
  CameraView a{cameras[0], {}}, b{cameras[1], {}};
  a.detections.names = {"Nose", "Neck"};
  b.detections.names = {"Nose", "Neck"};
  a.detections.frames.resize(10);
  b.detections.frames.resize(6);
  try {
    TriangulateKeypoints({a});
    FAIL() << "one camera was triangulated";
  } catch (const acro::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 2"), std::string::npos) << e.what();
  }
  CameraView twin = b;
  twin.camera.name = a.camera.name;
  try {
    TriangulateKeypoints({a, twin});
    FAIL() << "two cameras with one name";
  } catch (const acro::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("two cameras named 'north'"), std::string::npos)
        << e.what();
  }
  CameraView other = b;
  other.detections.names = {"Nose", "Neck", "MidHip"};
  EXPECT_THROW(TriangulateKeypoints({a, other}), acro::InputError);
  // Nobody seen anywhere: every sample a gap, and both warnings.
  const Triangulation t = TriangulateKeypoints({a, b});
  EXPECT_EQ(t.num_frames, 10);
  EXPECT_FALSE(t.positions.allFinite());
  EXPECT_EQ((t.views > 0).count(), 0);
  ASSERT_EQ(t.warnings.size(), 3u);
  EXPECT_NE(t.warnings[0].find("6 frames, the longest view has 10"), std::string::npos)
      << t.warnings[0];
  EXPECT_NE(t.warnings[1].find("nobody detected"), std::string::npos) << t.warnings[1];
}

// The real detections of s2mLab's first 15 frames (17 COCO keypoints from 8 cameras) against the
// TRC its authors made from them.
TEST(Triangulation, S2mLabsFirstFramesAgreeWithTheirOwnTriangulation) {
  ACRO_REQUIRE_REFDATA_FILE(S2m("keypoints/1_partie_0429_15f_keypoints.json"));
  const std::vector<Camera> cameras = acro::vision::ReadPose2SimToml(S2m("calibration/Calib.toml"));
  const acro::capture::Trial theirs =
      acro::capture::ReadTrial(S2m("trc/1_partie_0429_first15.trc"));
  std::ifstream in(S2m("keypoints/1_partie_0429_15f_keypoints.json"));
  const nlohmann::json json = nlohmann::json::parse(in);
  std::vector<std::string> names;
  for (const auto& p : theirs.points) names.push_back(p.label);
  std::vector<CameraView> views;
  for (const auto& [key, value] : json.items()) {
    CameraView view;
    const std::string serial = key.substr(key.find('_') + 1);
    for (const Camera& c : cameras)
      if (c.name == serial) view.camera = c;
    ASSERT_EQ(view.camera.name, serial);
    view.detections.names = names;
    for (size_t k = 0; k < value["frames"].size(); ++k) {
      acro::capture::DetectedPerson p(3, names.size());
      for (size_t j = 0; j < names.size(); ++j)
        p.col(static_cast<long>(j)) << value["keypoints"][k][j][0].get<double>(),
            value["keypoints"][k][j][1].get<double>(), value["scores"][k][j].get<double>();
      view.detections.frames.push_back({p});
    }
    views.push_back(std::move(view));
  }
  ASSERT_EQ(views.size(), 8u);
  auto distance = [&](const Triangulation& t, std::vector<double>* per_point = nullptr) {
    std::vector<double> d;
    for (int k = 0; k < 15; ++k)
      for (int j = 0; j < t.num_points(); ++j)
        if (theirs.valid(k, j) && t.position(k, j).allFinite()) {
          d.push_back((t.position(k, j) - theirs.position(k, j)).norm());
          if (per_point) per_point->push_back(d.back());
        }
    EXPECT_EQ(d.size(), 15u * 17u);
    return Median(d);
  };
  // Their TRC is a Pose2Sim-style triangulation that leaves the lenses' distortion in (k1 ≈ −0.13
  // in every camera) and keeps the linear point: the same choices here give their points back.
  TriangulationOptions as_theirs;
  as_theirs.model_distortion = false;
  as_theirs.refine = false;
  as_theirs.repair_left_right = false;
  as_theirs.max_view_error_factor = 1e6;
  const double same_choices = distance(TriangulateKeypoints(views, as_theirs));
  // Ours models the distortion, refines, and puts right a camera that exchanged left and right.
  const Triangulation ours = TriangulateKeypoints(views);
  const double ours_median = distance(ours);
  std::printf(
      "s2mLab first 15 frames: median distance to their TRC %.1f mm with their choices, "
      "%.1f mm with ours\n",
      1000 * same_choices,
      1000 * ours_median);
  std::printf("%s", ours.BriefReport().c_str());
  EXPECT_LE(same_choices, 0.010);
  // Who is right where the two differ: the reprojection into every camera's detections (the
  // calibrated distortion applied): ours no worse than theirs overall, nor by more than 1 px in any
  // camera (the two consensus rules keep different views of a few points).
  std::vector<double> all_ours, all_theirs;
  std::printf("camera    ours (px)  theirs (px)\n");
  for (const CameraView& v : views) {
    std::vector<double> eo, et;
    for (int k = 0; k < 15; ++k)
      for (int j = 0; j < ours.num_points(); ++j) {
        const auto& p = v.detections.frames[k][0];
        if (!(p(2, j) > 0.3) || !theirs.valid(k, j) || !ours.position(k, j).allFinite()) continue;
        eo.push_back((*v.camera.Project(ours.position(k, j)) - p.col(j).head<2>()).norm());
        et.push_back((*v.camera.Project(theirs.position(k, j)) - p.col(j).head<2>()).norm());
      }
    all_ours.insert(all_ours.end(), eo.begin(), eo.end());
    all_theirs.insert(all_theirs.end(), et.begin(), et.end());
    EXPECT_LE(Median(eo), Median(et) + 1.0) << v.camera.name;
    std::printf("%-8s %8.1f %12.1f\n", v.camera.name.c_str(), Median(eo), Median(et));
  }
  std::printf("all      %8.1f %12.1f\n", Median(all_ours), Median(all_theirs));
  EXPECT_LE(Median(all_ours), Median(all_theirs));
  // Their right shoulder sits on the left one in frames 1, 6, 8 and 14 (one camera's detector
  // exchanged the sides and their triangulation kept it); ours stays a shoulder width away.
  const int l_shoulder = 5, r_shoulder = 6;
  for (int k : {1, 6, 8, 14}) {
    EXPECT_LT((theirs.position(k, r_shoulder) - theirs.position(k, l_shoulder)).norm(), 0.12) << k;
    EXPECT_GT((ours.position(k, r_shoulder) - ours.position(k, l_shoulder)).norm(), 0.25) << k;
  }
}

// Pose2Sim's balancing trial: its OpenPose detections (BODY_25B, 4 cameras, sometimes two people)
// triangulated by us against the TRC Pose2Sim made from the same detections.
TEST(Triangulation, Pose2SimsDetectionsGivePose2SimsPoints) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(root / "balancing-trial");
  const std::vector<Camera> cameras =
      acro::vision::ReadPose2SimToml(root / "calibration/Calib_qualisys.toml");
  ASSERT_EQ(cameras.size(), 4u);
  std::vector<CameraView> views;
  for (int c = 0; c < 4; ++c) {
    CameraView view;
    view.camera = cameras[c];
    view.detections = acro::capture::ReadOpenPoseJson(
        root / "balancing-trial/pose" / ("cam0" + std::to_string(c + 1) + "_json"), "body25b");
    views.push_back(std::move(view));
  }
  const Triangulation ours = TriangulateKeypoints(views);
  const acro::capture::Trial theirs = acro::capture::ReadTrial(
      root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  ASSERT_EQ(ours.num_frames, 100);
  ASSERT_EQ(theirs.num_frames, 100);
  // Their TRC is Y up: world (Z, X, Y) of the file's (X, Y, Z) (README.md).
  auto world = [&](int k, int j) {
    const Eigen::Vector3d p = theirs.position(k, j);
    return Eigen::Vector3d(p.z(), p.x(), p.y());
  };
  std::vector<double> all;
  std::map<std::string, std::vector<double>> per_joint;
  // Reprojection of both into the detections of the person each chose (the median over every
  // camera's confident keypoints).
  std::vector<double> our_error, their_error;
  for (int j = 0; j < theirs.num_points(); ++j) {
    const std::string& name = theirs.points[j].label;
    const auto it = std::find(ours.names.begin(), ours.names.end(), name);
    ASSERT_NE(it, ours.names.end()) << name;
    const int o = static_cast<int>(it - ours.names.begin());
    for (int k = 0; k < 100; ++k) {
      if (!theirs.valid(k, j) || !ours.position(k, o).allFinite()) continue;
      const double e = (ours.position(k, o) - world(k, j)).norm();
      all.push_back(e);
      per_joint[name].push_back(e);
      for (const CameraView& v : views) {
        if (k >= v.detections.num_frames()) continue;
        double best_ours = INFINITY, best_theirs = INFINITY;
        for (const auto& person : v.detections.frames[k]) {
          if (!(person(2, o) > 0.5)) continue;
          const auto a = v.camera.Project(ours.position(k, o));
          const auto b = v.camera.Project(world(k, j));
          if (a) best_ours = std::min(best_ours, (*a - person.col(o).head<2>()).norm());
          if (b) best_theirs = std::min(best_theirs, (*b - person.col(o).head<2>()).norm());
        }
        if (std::isfinite(best_ours) && std::isfinite(best_theirs)) {
          our_error.push_back(best_ours);
          their_error.push_back(best_theirs);
        }
      }
    }
  }
  std::printf("Pose2Sim balancing trial, OpenPose detections: median %.1f mm over %zu points\n",
              1000 * Median(all),
              all.size());
  for (const auto& [name, d] : per_joint)
    std::printf("  %-10s %6.1f mm\n", name.c_str(), 1000 * Median(d));
  std::printf("reprojection into the detections: ours median %.2f px, theirs %.2f px (%zu)\n",
              Median(our_error),
              Median(their_error),
              our_error.size());
  std::printf("%s", ours.BriefReport().c_str());
  EXPECT_GT(all.size(), 1500u);
  EXPECT_LE(Median(all), 0.010);
  EXPECT_LE(Median(our_error), Median(their_error));
}

}  // namespace
