// Replays the camera-side fuzz entry point (tests/fuzz/fuzz_camera.h) over the reference
// calibrations (Pose2Sim's Qualisys export and its TOML, the EKF trampoline's and Sports2D's TOML,
// the sample's camera), an OpenCV FileStorage file, OpenPose frames and a detections CSV, and their
// damaged copies: truncations, overwritten bytes, each number made hostile, lines deleted or
// doubled, nesting without end. Every input is accepted or rejected with acro::InputError; anything
// else fails (a crash fails the whole test binary). The originals must be accepted.
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../../fuzz/fuzz_camera.h"
#include "mutants.h"
#include "refdata.h"

namespace acro::vision {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> Bytes(const std::string& s) {
  return std::vector<std::uint8_t>(s.begin(), s.end());
}

TEST(CameraCorpus, EveryCalibrationDetectionAndMutationIsAcceptedOrRejectedCleanly) {
  const fs::path pose2sim = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(pose2sim);
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> seeds;
  for (const fs::path& p :
       {pose2sim / "calibration/Calib.qca.txt",
        pose2sim / "calibration/Calib_qualisys.toml",
        pose2sim / "balancing-trial/pose/cam01_json/cam01.0001.json",
        pose2sim / "balancing-trial/pose/cam03_json/cam03.0050.json",
        acro::testing::RefdataFile(
            "s2mLab-EKF_multicamera-trampoline/inputs/calibration/Calib.toml"),
        acro::testing::RefdataFile("sports2d-demo/Calib_demo.toml"),
        acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.toml"}) {
    ACRO_REQUIRE_REFDATA_FILE(p);
    seeds.emplace_back(p.filename().string(), acro::testing::Slurp(p));
  }
  // OpenCV's calibration sample writes this layout (one camera, YAML).
  seeds.emplace_back("opencv.yml",
                     Bytes("%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\n"
                           "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                           "   data: [ 1500., 0., 960., 0., 1500., 540., 0., 0., 1. ]\n"
                           "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n"
                           "   dt: d\n   data: [ -0.1, 0.01, 0., 0., 0. ]\n"
                           "rvec: [ 0.1, -0.2, 0.3 ]\ntvec: [ 0.5, 1.0, 4.0 ]\n"));
  seeds.emplace_back("detections.csv",
                     Bytes("camera,frame,time_s,marker,u_px,v_px\n"
                           "cam1,0,0,LHEE,512.25,700.5\ncam1,0,0,RHEE,530,702.75\n"
                           "cam1,1,0.0167,LHEE,513.5,699.25\ncam1,1,0.0167,RHEE,531,701\n"));
  std::mt19937 rng(13);
  int inputs = 0;
  for (const auto& [name, bytes] : seeds) {
    SCOPED_TRACE(name);
    std::vector<std::string> errors;
    const int accepted = fuzz::FeedCameraReaders(bytes.data(), bytes.size(), &errors);
    EXPECT_GE(accepted, 1) << acro::testing::JoinLines(errors);
    ++inputs;
    std::vector<acro::testing::Mutant> mutants = acro::testing::ByteMutants(bytes, rng);
    for (acro::testing::Mutant& m :
         acro::testing::TextMutants(std::string(bytes.begin(), bytes.end()), 30, 20))
      mutants.push_back(std::move(m));
    inputs += acro::testing::ReplayMutants(
        mutants, [](const auto& input) { fuzz::FeedCameraReaders(input.data(), input.size()); });
  }
  RecordProperty("inputs", inputs);
  std::printf("%d calibration and detection inputs replayed\n", inputs);
}

// Found by the fuzzer: an !!opencv-matrix of billions of rows made OpenCV allocate 48 GB before
// reading its data (OpenCV reads 3 000 000 000 as the int −1 294 967 296).
TEST(CameraCorpus, AHugeOpenCvMatrixIsRefusedBeforeItIsAllocated) {
  const std::string text =
      "%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\n"
      "camera_matrix: !!opencv-matrix\n   rows: 3000000000\n   cols: 3\n   dt: d\n"
      "   data: [ 1500., 0., 960., 0., 1500., 540., 0., 0., 1. ]\n";
  std::vector<std::string> errors;
  fuzz::FeedCameraReaders(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), &errors);
  EXPECT_NE(acro::testing::JoinLines(errors).find(
                "camera_matrix: -1294967296 × 3 is not a calibration matrix"),
            std::string::npos)
      << acro::testing::JoinLines(errors);
}

// Found by the camera fuzzer (10-minute run, after 28 669 inputs): a damaged OpenCV YAML made
// OpenCV's parser throw std::length_error, not cv::Exception, out of FileStorage::open.
TEST(CameraCorpus, OpenCvsOwnStandardExceptionsAreTheFilesFault) {
  const std::string text(
      "%YAML:1.0\n"
      "---\n"
      "image_width: 1920\n"
      "image_height: 1080\n"
      "camera[matri\177x: !!opencv-matrix\n"
      "   rows: 3\n"
      "   cols: 3\n"
      "   dt: d\n"
      "   :a tda[ 1500., 0., 960., 0., 1500., 540., 0., 0., 1. ]\n"
      "distortion_coefficients: !!opencv-matpix\n"
      "   rows: 1\n"
      "   cols: 5\n"
      "   \000dt: d\n"
      ", 4.0 ]\n",
      253);
  std::vector<std::string> errors;
  EXPECT_NO_THROW(fuzz::FeedCameraReaders(
      reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), &errors));
  EXPECT_NE(acro::testing::JoinLines(errors).find("calib.yml: not an OpenCV FileStorage file"),
            std::string::npos)
      << acro::testing::JoinLines(errors);
}

}  // namespace
}  // namespace acro::vision
