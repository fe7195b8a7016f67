// Cameras: the Pose2Sim/Anipose TOML read and written back, projection against OpenCV's
// projectPoints (an independent implementation), and the real balancing trial's 3D keypoints
// projected into its four videos against the OpenPose detections of the same frames
// (../shared/refdata/pose2sim-demo/expected.md).

#include "acro/vision/camera.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>

#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "body25b.h"
#include "refdata.h"

namespace acro::vision {
namespace {

namespace fs = std::filesystem;

fs::path Calibration() {
  return acro::testing::RefdataFile("pose2sim-demo/calibration/Calib_qualisys.toml");
}

TEST(Camera, ReadsThePose2SimCalibration) {
  ACRO_REQUIRE_REFDATA_FILE(Calibration());
  const std::vector<Camera> cameras = ReadPose2SimToml(Calibration());
  ASSERT_EQ(cameras.size(), 4u);
  EXPECT_EQ(cameras[0].name, "cam_01");
  EXPECT_EQ(cameras[3].name, "cam_04");
  EXPECT_EQ(cameras[0].width_px, 1088);
  EXPECT_EQ(cameras[0].height_px, 1920);
  EXPECT_DOUBLE_EQ(cameras[0].K(0, 0), 1681.244873046875);
  EXPECT_DOUBLE_EQ(cameras[0].K(1, 2), 948.137390140625);
  EXPECT_EQ(cameras[0].distortion.size(), 4u);
  // The cameras stand about 3–4.5 m from the lab's origin, above the floor (Z up).
  for (const Camera& c : cameras) {
    const Eigen::Vector3d centre = c.CentreInWorld();
    EXPECT_GT(centre.norm(), 2.0) << c.name;
    EXPECT_LT(centre.norm(), 6.0) << c.name;
    EXPECT_GT(centre.z(), 0.0) << c.name;
  }
}

TEST(Camera, ProjectionEqualsOpenCvsProjectPoints) {
  ACRO_REQUIRE_REFDATA_FILE(Calibration());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (Camera c : ReadPose2SimToml(Calibration())) {
    // Stronger distortion than the file's, so that every term shows.
    c.distortion = {-0.12, 0.05, 0.001, -0.002, 0.01};
    const Eigen::Vector3d r = RodriguesFromRotation(c.R_KW);
    const cv::Mat rvec = (cv::Mat_<double>(3, 1) << r.x(), r.y(), r.z());
    const cv::Mat tvec = (cv::Mat_<double>(3, 1) << c.t_KW.x(), c.t_KW.y(), c.t_KW.z());
    cv::Mat K(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) K.at<double>(i, j) = c.K(i, j);
    const cv::Mat d(c.distortion, true);
    std::vector<cv::Point3d> points;
    for (int k = 0; k < 50; ++k) points.emplace_back(u(rng), u(rng), 1.0 + 0.5 * u(rng));
    std::vector<cv::Point2d> expected;
    cv::projectPoints(points, rvec, tvec, K, d, expected);
    for (size_t k = 0; k < points.size(); ++k) {
      const auto ours = c.Project(Eigen::Vector3d(points[k].x, points[k].y, points[k].z));
      ASSERT_TRUE(ours.has_value());
      EXPECT_NEAR(ours->x(), expected[k].x, 1e-6) << c.name;
      EXPECT_NEAR(ours->y(), expected[k].y, 1e-6) << c.name;
    }
  }
}

// Undistortion against OpenCV's undistortPoints (iterated to convergence), and the ray through a
// pixel projecting back onto it.
TEST(Camera, UndistortionEqualsOpenCvsAndRaysProjectBack) {
  ACRO_REQUIRE_REFDATA_FILE(Calibration());
  std::mt19937 rng(4);
  for (Camera c : ReadPose2SimToml(Calibration())) {
    c.distortion = {-0.12, 0.05, 0.001, -0.002, 0.01};
    cv::Mat K(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) K.at<double>(i, j) = c.K(i, j);
    std::uniform_real_distribution<double> u(0.0, c.width_px), v(0.0, c.height_px);
    std::vector<cv::Point2d> pixels, expected;
    for (int k = 0; k < 50; ++k) pixels.emplace_back(u(rng), v(rng));
    cv::undistortPoints(
        pixels,
        expected,
        K,
        cv::Mat(c.distortion, true),
        cv::noArray(),
        K,
        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-14));
    for (size_t k = 0; k < pixels.size(); ++k) {
      const Eigen::Vector2d ours = c.Undistort({pixels[k].x, pixels[k].y});
      EXPECT_NEAR(ours.x(), expected[k].x, 1e-6) << c.name;
      EXPECT_NEAR(ours.y(), expected[k].y, 1e-6) << c.name;
      // A point 4 m along the ray lands on the pixel again.
      const Eigen::Vector3d p = c.CentreInWorld() + 4.0 * c.RayInWorld({pixels[k].x, pixels[k].y});
      const auto back = c.Project(p);
      ASSERT_TRUE(back.has_value());
      EXPECT_NEAR(back->x(), pixels[k].x, 1e-6);
      EXPECT_NEAR(back->y(), pixels[k].y, 1e-6);
    }
  }
}

// The balancing trial projected into each camera: median distance to the OpenPose detections
// (confidence > 0.5; of two people, the one nearer the projection), one per camera.
std::vector<double> MedianDistancesToDetections(const std::vector<Camera>& cameras) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  const fs::path trc = root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
  const capture::Trial trial = capture::ReadTrial(trc);
  std::vector<double> medians;
  for (int cam = 0; cam < 4; ++cam) {
    std::vector<double> errors;
    for (int frame = 0; frame < 100; ++frame) {
      char name[64];
      std::snprintf(name, sizeof name, "cam%02d_json/cam%02d.%04d.json", cam + 1, cam + 1, frame);
      std::ifstream in(root / "balancing-trial/pose" / name);
      EXPECT_TRUE(in) << name;
      const nlohmann::json people = nlohmann::json::parse(in)["people"];
      for (int p = 0; p < trial.num_points(); ++p) {
        const auto index =
            acro::testing::Body25bIndex().find(trial.points[static_cast<size_t>(p)].label);
        if (index == acro::testing::Body25bIndex().end() || !trial.valid(frame, p)) continue;
        // TRC (X, Y, Z), Y up, is the lab's (Z, X, Y).
        const Eigen::Vector3d v = trial.position(frame, p);
        const auto uv =
            cameras[static_cast<size_t>(cam)].Project(Eigen::Vector3d(v.z(), v.x(), v.y()));
        if (!uv) continue;
        double best = std::numeric_limits<double>::infinity();
        for (const nlohmann::json& person : people) {
          const nlohmann::json& k = person["pose_keypoints_2d"];
          const size_t i = 3 * static_cast<size_t>(index->second);
          if (k[i + 2].get<double>() <= 0.5) continue;
          best = std::min(
              best, (Eigen::Vector2d(k[i].get<double>(), k[i + 1].get<double>()) - *uv).norm());
        }
        if (std::isfinite(best)) errors.push_back(best);
      }
    }
    EXPECT_GT(errors.size(), 1000u);
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    medians.push_back(errors[errors.size() / 2]);
  }
  return medians;
}

// expected.md's figures come from an independent projection of the same data with the same file.
TEST(Camera, BalancingTrialProjectsOntoItsDetectionsAsExpected) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("pose2sim-demo/balancing-trial"));
  const std::vector<double> medians = MedianDistancesToDetections(ReadPose2SimToml(Calibration()));
  const double expected_median[4] = {11.3, 7.7, 17.2, 8.5};
  for (int cam = 0; cam < 4; ++cam) {
    RecordProperty("median_px_cam" + std::to_string(cam + 1), std::to_string(medians[cam]));
    EXPECT_NEAR(medians[cam], expected_median[cam], 0.5) << "cam " << cam + 1;
  }
  // With Qualisys' own distortion (64 times Pose2Sim's): 11.37, 7.93, 17.27, 8.78 px, a little
  // worse in three cameras, but these keypoints were triangulated with Pose2Sim's file, so this
  // does not settle which is right (docs/formats/calibration.md): recorded, not asserted.
  const fs::path qca = acro::testing::RefdataFile("pose2sim-demo/calibration/Calib.qca.txt");
  const std::vector<double> qualisys = MedianDistancesToDetections(ReadQualisysQca(qca));
  for (int cam = 0; cam < 4; ++cam)
    RecordProperty("qca_median_px_cam" + std::to_string(cam + 1), std::to_string(qualisys[cam]));
}

// The same four cameras from Qualisys' own file and from Pose2Sim's conversion of it: the pose and
// K agree (the QCA reader's axis convention, diag(1, −1, −1), and its units, mm and 1/64 px, are
// what makes them agree). The distortion does not: Pose2Sim's file holds Qualisys' coefficients
// divided by 64 (see the balancing-trial test for what projection says about it).
TEST(Camera, QualisysFileAgreesWithItsPose2SimConversionButForTheDistortion) {
  const fs::path qca = acro::testing::RefdataFile("pose2sim-demo/calibration/Calib.qca.txt");
  ACRO_REQUIRE_REFDATA_FILE(qca);
  const std::vector<Camera> qualisys = ReadQualisysQca(qca);
  const std::vector<Camera> pose2sim = ReadPose2SimToml(Calibration());
  ASSERT_EQ(qualisys.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(qualisys[i].name);
    EXPECT_EQ(qualisys[i].width_px, 1088);
    EXPECT_EQ(qualisys[i].height_px, 1920);
    EXPECT_LT((qualisys[i].R_KW - pose2sim[i].R_KW).norm(), 1e-9);
    EXPECT_LT((qualisys[i].CentreInWorld() - pose2sim[i].CentreInWorld()).norm(), 1e-6);
    EXPECT_LT((qualisys[i].K - pose2sim[i].K).norm(), 1e-6);
    for (size_t k = 0; k < 4; ++k)
      EXPECT_NEAR(qualisys[i].distortion[k] / 64.0, pose2sim[i].distortion[k], 1e-9) << k;
  }
}

TEST(Camera, WritesWhatItReadsAndRefusesBrokenFiles) {
  ACRO_REQUIRE_REFDATA_FILE(Calibration());
  const fs::path dir = fs::temp_directory_path() / ("acro_calib_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::vector<Camera> cameras = ReadPose2SimToml(Calibration());
  WritePose2SimToml(cameras, dir / "back.toml");
  const std::vector<Camera> back = ReadPose2SimToml(dir / "back.toml");
  ASSERT_EQ(back.size(), cameras.size());
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].name, cameras[i].name);
    EXPECT_LT((back[i].K - cameras[i].K).norm(), 1e-9);
    EXPECT_LT((back[i].R_KW - cameras[i].R_KW).norm(), 1e-12);
    EXPECT_LT((back[i].t_KW - cameras[i].t_KW).norm(), 1e-12);
  }
  auto error_of = [&](const std::string& text) -> std::string {
    std::ofstream(dir / "bad.toml") << text;
    try {
      ReadPose2SimToml(dir / "bad.toml");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string camera =
      "[cam_a]\nname = \"cam_a\"\nsize = [ 640.0, 480.0]\n"
      "matrix = [ [ 500.0, 0.0, 320.0], [ 0.0, 500.0, 240.0], [ 0.0, 0.0, 1.0]]\n"
      "distortions = [ 0.0, 0.0, 0.0, 0.0]\n";
  EXPECT_NE(
      error_of(camera + "rotation = [ 0.1, 0.2, 0.3]\n").find("[cam_a]: translation: missing"),
      std::string::npos);
  EXPECT_NE(error_of(camera + "rotation = [ 1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 1.0]\n"
                              "translation = [ 0.0, 0.0, 1.0]\n")
                .find("not orthonormal"),
            std::string::npos);
  EXPECT_NE(error_of("[metadata]\nadjusted = false\n").find("no camera"), std::string::npos);
  EXPECT_NE(error_of("[cam_a\n").find("bad.toml: line 1"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro::vision
