// Real motion through a virtual camera (docs/one-camera.md, the acceptance): s2mLab's
// trampoline routine — their 3D keypoints (17 COCO points at 120 Hz, triangulated from 8 cameras) —
// projected into one camera with 3 px of noise and written as OpenPose JSON, then `acrolab analyze
// --detections` as one camera's detections, against `acrolab analyze` of the 3D keypoints: every
// complete flight and its take-off within 2 frames (asserted); its landing within 2 frames and each
// skill's somersaults and twists as the 3D analysis reads them — the acceptance — counted
// and printed: not met (docs/one-camera.md: twisting doubles and triples seen from one side). Two
// cameras: a virtual phone 8 m to the side of the routine, 1.2 m above the floor (tilted up to keep
// the routine in its picture), and the one of s2mLab's own eight that looks at the routine most
// squarely from its side.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "acro/capture/trial_io.h"
#include "acro/vision/camera.h"
#include "refdata.h"
#include "run_command.h"

namespace {

namespace fs = std::filesystem;
using acro::testing::Execute;
using acro::testing::ProcessResult;
using acro::testing::Quote;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path S2m(const std::string& rel) {
  return acro::testing::RefdataFile("s2mLab-EKF_multicamera-trampoline/inputs/" + rel);
}

struct Routine {
  acro::capture::Trial trial;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();      // the hips' mean
  Eigen::Vector3d long_axis = Eigen::Vector3d::UnitX();  // the hips' main horizontal travel
};

Routine ReadRoutine() {
  Routine r;
  r.trial = acro::capture::ReadTrial(S2m("trc/1_partie_0429_002.trc"));
  int left = -1, right = -1;
  for (int j = 0; j < static_cast<int>(r.trial.points.size()); ++j) {
    if (r.trial.points[j].label == "L Hip") left = j;
    if (r.trial.points[j].label == "R Hip") right = j;
  }
  EXPECT_GE(left, 0);
  EXPECT_GE(right, 0);
  std::vector<Eigen::Vector3d> hips;
  for (int k = 0; k < r.trial.num_frames; ++k)
    if (r.trial.valid(k, left) && r.trial.valid(k, right))
      hips.push_back(0.5 * (r.trial.position(k, left) + r.trial.position(k, right)));
  for (const auto& h : hips) r.centre += h / double(hips.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& h : hips) {
    const Eigen::Vector2d d = (h - r.centre).head<2>();
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  r.long_axis << eig.eigenvectors().col(1), 0;
  return r;
}

// The bed's height at rest as the 3D analysis found it ("bed at rest 1.234 m …").
double BedHeight(const nlohmann::json& jumps) {
  for (const auto& j : jumps) {
    const std::string s = j["surface"].get<std::string>();
    const size_t at = s.find("at rest ");
    if (at != std::string::npos) return std::stod(s.substr(at + 8));
  }
  ADD_FAILURE() << "no bed height in the 3D analysis";
  return 0;
}

// The routine projected into `camera` with 3 px of noise as OpenPose JSON (COCO-17 order, the
// TRC's), one file per frame; returns the bed's rest line (y0, slope) in its picture: the bed's
// plane at `bed_z` under the routine, along its long axis.
std::pair<double, double> WriteDetections(const Routine& r,
                                          const acro::vision::Camera& camera,
                                          double bed_z,
                                          const fs::path& dir) {
  fs::create_directories(dir);
  std::mt19937 rng(17);
  std::normal_distribution<double> noise(0.0, 3.0);
  const int P = static_cast<int>(r.trial.points.size());
  for (int k = 0; k < r.trial.num_frames; ++k) {
    std::vector<double> flat;
    for (int j = 0; j < P; ++j) {
      const auto uv = r.trial.valid(k, j) ? camera.Project(r.trial.position(k, j)) : std::nullopt;
      if (!uv) {
        flat.insert(flat.end(), {0.0, 0.0, 0.0});
        continue;
      }
      flat.insert(flat.end(), {uv->x() + noise(rng), uv->y() + noise(rng), 0.9});
    }
    nlohmann::json j;
    j["version"] = 1.3;
    j["people"] = nlohmann::json::array({{{"pose_keypoints_2d", flat}}});
    std::ofstream(dir / fmt::format("routine_{:012d}_keypoints.json", k)) << j.dump();
  }
  Eigen::Vector3d a = r.centre, b = r.centre + r.long_axis;
  a.z() = b.z() = bed_z;
  const Eigen::Vector2d pa = *camera.Project(a), pb = *camera.Project(b);
  const double slope = (pb.y() - pa.y()) / (pb.x() - pa.x());
  return {pa.y() - slope * pa.x(), slope};
}

// Every complete flight found and its take-off within 2 frames (asserted); its landing within 2
// frames, its somersaults and its twists as the 3D analysis reads them (counted and printed: not
// met yet, docs/one-camera.md).
void CompareWithTheThreeDimensionalAnalysis(const nlohmann::json& mono,
                                            const nlohmann::json& three_d,
                                            const std::string& camera) {
  std::vector<nlohmann::json> a, b;
  for (const auto& j : mono)
    if (!j["partial"].get<bool>()) a.push_back(j);
  for (const auto& j : three_d)
    if (!j["partial"].get<bool>()) b.push_back(j);
  EXPECT_EQ(a.size(), b.size()) << camera;
  ASSERT_FALSE(b.empty());
  const double two_frames = 2.0 / 120.0;
  int landings = 0, somersaults = 0, twists = 0;
  for (const auto& j : a) {
    const auto* m = &b[0];
    for (const auto& k : b)
      if (std::abs(k["takeoff_s"].get<double>() - j["takeoff_s"].get<double>()) <
          std::abs((*m)["takeoff_s"].get<double>() - j["takeoff_s"].get<double>()))
        m = &k;
    std::printf(
        "%s: %s / %s, take-off %+.1f ms, landing %+.1f ms, somersault %+.0f deg, twist "
        "%+.0f deg\n",
        camera.c_str(),
        j["fig_code"].dump().c_str(),
        (*m)["fig_code"].dump().c_str(),
        1e3 * (j["takeoff_s"].get<double>() - (*m)["takeoff_s"].get<double>()),
        1e3 * (j["landing_s"].get<double>() - (*m)["landing_s"].get<double>()),
        j["measured_somersault_deg"].get<double>() - (*m)["measured_somersault_deg"].get<double>(),
        j["measured_twist_deg"].get<double>() - (*m)["measured_twist_deg"].get<double>());
    EXPECT_NEAR(j["takeoff_s"].get<double>(), (*m)["takeoff_s"].get<double>(), two_frames)
        << camera;
    landings +=
        std::abs(j["landing_s"].get<double>() - (*m)["landing_s"].get<double>()) <= two_frames;
    somersaults += j["somersault_quarters"] == (*m)["somersault_quarters"];
    twists += j["twist_halves"] == (*m)["twist_halves"];
  }
  std::printf("%s: landings within 2 frames %d of %zu, somersaults %d, twists %d\n",
              camera.c_str(),
              landings,
              a.size(),
              somersaults,
              twists);
}

TEST(OneCamera, S2mLabsRoutineThroughOneCameraFindsEveryFlightAndTakeOff) {
  ACRO_REQUIRE_REFDATA_FILE(S2m("trc/1_partie_0429_002.trc"));
  const fs::path dir = acro::testing::ScratchDir("one_camera_s2mlab");
  const ProcessResult three_d =
      Execute(std::string(ACROLAB_EXE) + " analyze " + Quote(S2m("trc/1_partie_0429_002.trc")) +
              " --quiet --no-images -o " + Quote(dir / "3d"));
  ASSERT_EQ(three_d.status, 0) << three_d.err;
  const nlohmann::json jumps_3d = nlohmann::json::parse(Slurp(dir / "3d/jumps.json"));
  const Routine r = ReadRoutine();
  const double bed_z = BedHeight(jumps_3d);

  // The virtual phone: 8 m to the side of the routine, 1.2 m high, a phone's lens (f = 1400 px for
  // 1920 × 1080, 69° across), tilted up to the routine's middle height (3.2 m) to keep the whole
  // routine — 5.7 m high at its top — in the picture.
  std::vector<acro::vision::Camera> cameras;
  acro::vision::Camera phone;
  phone.name = "phone";
  phone.width_px = 1920;
  phone.height_px = 1080;
  phone.K << 1400, 0, 960, 0, 1400, 540, 0, 0, 1;
  phone.distortion = {0, 0, 0, 0};
  const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(r.long_axis).normalized();
  Eigen::Vector3d at = r.centre + 8.0 * side;
  at.z() = 1.2;
  acro::vision::AimCamera(&phone, at, Eigen::Vector3d(r.centre.x(), r.centre.y(), 3.2));
  cameras.push_back(phone);
  // s2mLab's camera most square to the routine's long axis, level within 60°.
  const std::vector<acro::vision::Camera> theirs =
      acro::vision::ReadPose2SimToml(S2m("calibration/Calib.toml"));
  const acro::vision::Camera* best = nullptr;
  double best_cos = 1;
  for (const auto& c : theirs) {
    const Eigen::Vector3d axis = c.R_KW.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d down = c.R_KW.transpose() * Eigen::Vector3d::UnitY();
    if (!(down.z() < -0.5)) continue;
    const double cos =
        std::abs(Eigen::Vector3d(axis.x(), axis.y(), 0).normalized().dot(r.long_axis));
    if (cos < best_cos) {
      best_cos = cos;
      best = &c;
    }
  }
  ASSERT_NE(best, nullptr);
  cameras.push_back(*best);
  acro::vision::WritePose2SimToml(cameras, dir / "cameras.toml");

  for (const auto& camera : cameras) {
    const auto [y0, slope] = WriteDetections(r, camera, bed_z, dir / camera.name);
    const ProcessResult mono =
        Execute(std::string(ACROLAB_EXE) + " analyze --detections " + Quote(dir / camera.name) +
                " --keypoints coco17 --fps 120 --calib " + Quote(dir / "cameras.toml") +
                " --camera " + camera.name + fmt::format(" --bed-line {},{}", y0, slope) +
                " --no-images -o " + Quote(dir / ("mono_" + camera.name)));
    ASSERT_EQ(mono.status, 0) << camera.name << ": " << mono.err;
    const size_t line = mono.err.find("one camera");
    if (line != std::string::npos)
      std::printf("%s\n", mono.err.substr(line, mono.err.find('\n', line) - line).c_str());
    CompareWithTheThreeDimensionalAnalysis(
        nlohmann::json::parse(Slurp(dir / ("mono_" + camera.name) / "jumps.json")),
        jumps_3d,
        camera.name);
  }
}

}  // namespace
