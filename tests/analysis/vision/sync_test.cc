// Sync between a trial and a video: from 2D detections on the real balancing trial with its TRC
// shifted by a known number of frames, and from image motion alone on a video drawn from the
// sample routine's markers that starts a known time after the trial.

#include "acro/vision/sync.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "refdata.h"

namespace acro::vision {
namespace {

namespace fs = std::filesystem;

TEST(VideoSync, EventAndNearestSample) {
  const VideoSync s = SyncFromEvent(2.0, 2.5);
  EXPECT_DOUBLE_EQ(s.offset_s, 0.5);
  EXPECT_DOUBLE_EQ(s.VideoTime(1.0), 1.5);
  EXPECT_DOUBLE_EQ(s.TrialTime(1.5), 1.0);
  const VideoSync slow = SyncFromEvent(1.0, 5.0, 4.0);  // 4× slow motion
  EXPECT_DOUBLE_EQ(slow.offset_s, 1.0);
  EXPECT_DOUBLE_EQ(slow.TrialTime(9.0), 2.0);
  capture::Trial trial;
  trial.point_rate_hz = 100;
  trial.num_frames = 10;
  EXPECT_EQ(s.NearestSample(trial, 0.5), 0);
  EXPECT_EQ(s.NearestSample(trial, 0.5 + 0.0449), 4);
  EXPECT_EQ(s.NearestSample(trial, 0.49), -1);
  EXPECT_EQ(s.NearestSample(trial, 0.5 + 0.0951), -1);
}

// Writes the balancing TRC without its first `drop` rows, renumbered from 1: its first sample is
// then video frame `drop`, so the sync must find offset = drop / 60 s.
fs::path ShiftedTrc(const fs::path& trc, int drop, const fs::path& dir) {
  std::ifstream in(trc);
  std::ostringstream out;
  std::string line;
  for (int i = 0; i < 5 && std::getline(in, line); ++i) {
    if (i == 2) {
      // DataRate CameraRate NumFrames …: one less frame per row dropped.
      std::istringstream f(line);
      std::string rate, camera_rate, frames;
      f >> rate >> camera_rate >> frames;
      std::string rest;
      std::getline(f, rest);
      line = rate + "\t" + camera_rate + "\t" + std::to_string(std::stoi(frames) - drop) + rest;
    }
    out << line << "\n";
  }
  int row = 0, kept = 0;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (row++ < drop) continue;
    ++kept;
    const size_t a = line.find('\t'), b = line.find('\t', a + 1);
    out << kept << "\t" << kept / 60.0 << line.substr(b) << "\n";
  }
  const fs::path path = dir / "shifted.trc";
  std::ofstream(path) << out.str();
  return path;
}

struct Balancing {
  std::vector<Camera> cameras;
  std::vector<capture::KeypointDetections> detections;
  std::vector<CameraDetections> per_camera;
};

Balancing LoadBalancing() {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  Balancing b;
  b.cameras = ReadPose2SimToml(root / "calibration/Calib_qualisys.toml");
  for (int cam = 1; cam <= 4; ++cam) {
    const std::string name = "cam0" + std::to_string(cam);
    b.detections.push_back(
        capture::ReadOpenPoseJson(root / "balancing-trial/pose" / (name + "_json"), "body25b"));
  }
  for (int cam = 0; cam < 4; ++cam) {
    CameraDetections c;
    c.camera = &b.cameras[size_t(cam)];
    c.detections = &b.detections[size_t(cam)];
    c.frame_times_s =
        capture::VideoReader(root / "videos" / ("cam0" + std::to_string(cam + 1) + ".mp4"))
            .frame_times_s();
    b.per_camera.push_back(std::move(c));
  }
  return b;
}

// The balancing trial's axes (README: z x y) and offsets searched within ±0.5 s.
AutoSyncOptions BalancingSyncOptions() {
  AutoSyncOptions options;
  options.axes = ParseAxisMapping("zxy");
  options.min_offset_s = -0.5;
  options.max_offset_s = 0.5;
  return options;
}

fs::path BalancingTrc(const fs::path& root) {
  return root / "balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc";
}

TEST(AutoSync, DetectionsRecoverASevenFrameShiftWithinAThirdOfAFrame) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(root / "balancing-trial");
  const Balancing b = LoadBalancing();
  ASSERT_EQ(b.detections[0].num_frames(), 100);
  ASSERT_GE(b.detections[0].frames[0].size(), 1u);
  const AutoSyncOptions options = BalancingSyncOptions();
  const fs::path trc = BalancingTrc(root);
  // As recorded, first sample ↔ first frame.
  const AutoSyncResult as_is = SyncFromDetections(capture::ReadTrial(trc), b.per_camera, options);
  RecordProperty("unshifted_offset_frames", std::to_string(as_is.sync.offset_s * 60));
  EXPECT_NEAR(as_is.sync.offset_s * 60.0, 0.0, 1.0 / 3.0);
  const fs::path dir = acro::testing::ScratchDir("sync_shift");
  const capture::Trial shifted = capture::ReadTrial(ShiftedTrc(trc, 7, dir));
  ASSERT_EQ(shifted.num_frames, 93);
  const AutoSyncResult r = SyncFromDetections(shifted, b.per_camera, options);
  RecordProperty("shifted_offset_frames", std::to_string(r.sync.offset_s * 60));
  RecordProperty("cost_px", std::to_string(r.cost));
  RecordProperty("runner_up_cost_px", std::to_string(r.runner_up_cost));
  EXPECT_NEAR(r.sync.offset_s * 60.0, 7.0, 1.0 / 3.0);
  EXPECT_EQ(r.method, "detections");
  // The minimum is distinct: two frames away the cost is clearly higher.
  EXPECT_GT(r.runner_up_cost, r.cost + 0.5);
  EXPECT_LT(r.cost, 20.0);
  fs::remove_all(dir);
}

// The same detections as one CSV of all four cameras (the rows `project --csv` writes, with a
// confidence column): the CSV reader feeds the same search.
TEST(AutoSync, DetectionsFromACsvFindTheSameShift) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(root / "balancing-trial");
  Balancing b = LoadBalancing();
  const fs::path dir = acro::testing::ScratchDir("sync_csv");
  std::ofstream csv(dir / "detections.csv");
  csv << "camera,frame,time_s,marker,u_px,v_px,confidence\n";
  for (size_t cam = 0; cam < 4; ++cam) {
    const capture::KeypointDetections& d = b.detections[cam];
    for (int k = 0; k < d.num_frames(); ++k) {
      if (d.frames[size_t(k)].empty()) continue;
      const capture::DetectedPerson& person = d.frames[size_t(k)].front();  // the first person
      for (Eigen::Index j = 0; j < person.cols(); ++j)
        if (person(2, j) > 0.5)
          csv << b.cameras[cam].name << "," << k << "," << k / 60.0 << "," << d.names[size_t(j)]
              << "," << person(0, j) << "," << person(1, j) << "," << person(2, j) << "\n";
    }
  }
  csv.close();
  std::vector<capture::KeypointDetections> from_csv;
  for (size_t cam = 0; cam < 4; ++cam)
    from_csv.push_back(
        capture::ReadDetections(dir / "detections.csv", "body25b", b.cameras[cam].name));
  EXPECT_EQ(from_csv[0].names.front(), "Nose");
  for (size_t cam = 0; cam < 4; ++cam) b.per_camera[cam].detections = &from_csv[cam];
  const AutoSyncOptions options = BalancingSyncOptions();
  const fs::path trc = BalancingTrc(root);
  const AutoSyncResult r =
      SyncFromDetections(capture::ReadTrial(ShiftedTrc(trc, 7, dir)), b.per_camera, options);
  RecordProperty("csv_shifted_offset_frames", std::to_string(r.sync.offset_s * 60));
  EXPECT_NEAR(r.sync.offset_s * 60.0, 7.0, 1.0 / 3.0);
  // A broken row names its line.
  std::ofstream(dir / "bad.csv") << "frame,marker,u_px,v_px\n0,Nose,1,2\n1,Nose,x,2\n";
  std::string e;
  try {
    capture::ReadDetections(dir / "bad.csv", "body25b");
  } catch (const InputError& error) {
    e = error.what();
  }
  EXPECT_NE(e.find("bad.csv: line 3: 'x' is not a number"), std::string::npos) << e;
  fs::remove_all(dir);
}

// The same detections as Sports2D's 2D TRC files, one per camera, in both of its conventions
// (pixels, y down; before 0.5: pixels ÷ 1000, y up), one of them trimmed to start at frame 10: they
// read back to the JSON's pixels and give the same shift.
TEST(AutoSync, DetectionsFromSports2DTrcFilesFindTheSameShift) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(root / "balancing-trial");
  Balancing b = LoadBalancing();
  const fs::path dir = acro::testing::ScratchDir("sync_trc2d");
  std::vector<capture::KeypointDetections> from_trc;
  for (size_t cam = 0; cam < 4; ++cam) {
    const capture::KeypointDetections& d = b.detections[cam];
    const bool legacy = cam >= 2;
    const int first = cam == 3 ? 10 : 0;
    const fs::path path = dir / (b.cameras[cam].name + "_px_person00.trc");
    std::ofstream trc(path);
    const size_t K = d.names.size();
    trc << "PathFileType\t4\t(X/Y/Z)\t" << path.string() << "\n"
        << "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\t"
           "OrigDataStartFrame\tOrigNumFrames\n"
        << "60\t60\t" << d.num_frames() - first << "\t" << K << "\tm\t60\t0\t"
        << d.num_frames() - first << "\nFrame#\tTime";
    for (const std::string& n : d.names) trc << "\t" << n << "\t\t";
    trc << "\n\t";
    for (size_t j = 0; j < K; ++j) trc << "\tX" << j + 1 << "\tY" << j + 1 << "\tZ" << j + 1;
    trc << "\n";
    trc.precision(10);
    for (int k = first; k < d.num_frames(); ++k) {
      trc << k - first << "\t" << k / 60.0;
      for (size_t j = 0; j < K; ++j) {
        const bool seen =
            !d.frames[size_t(k)].empty() && d.frames[size_t(k)].front()(2, Eigen::Index(j)) > 0.5;
        if (!seen) {
          trc << (legacy ? "\t\t\t" : "\t0\t0\t0");  // a gap, or Sports2D's zeros
          continue;
        }
        const Eigen::Vector3d x = d.frames[size_t(k)].front().col(Eigen::Index(j));
        if (legacy)
          trc << "\t" << x(0) / 1000 << "\t" << -x(1) / 1000 << "\t0";
        else
          trc << "\t" << x(0) << "\t" << x(1) << "\t0";
      }
      trc << "\n";
    }
    trc.close();
    from_trc.push_back(capture::ReadDetections(path, "body25b"));
    const capture::KeypointDetections& r = from_trc.back();
    ASSERT_EQ(r.num_frames(), d.num_frames());
    EXPECT_NE(r.warnings.back().find(legacy ? "before 0.5" : "pixels, x right and y down"),
              std::string::npos)
        << r.warnings.back();
    // Every detection read back where the JSON has it, to the digits written.
    int compared = 0;
    for (int k = 0; k < d.num_frames(); ++k) {
      if (k < first) {
        EXPECT_TRUE(r.frames[size_t(k)].empty()) << k;
        continue;
      }
      ASSERT_EQ(r.frames[size_t(k)].size(), 1u) << k;
      for (size_t j = 0; j < K; ++j) {
        const bool seen =
            !d.frames[size_t(k)].empty() && d.frames[size_t(k)].front()(2, Eigen::Index(j)) > 0.5;
        const Eigen::Vector3d got = r.frames[size_t(k)].front().col(Eigen::Index(j));
        if (!seen) {
          EXPECT_EQ(got(2), 0.0);
          continue;
        }
        const Eigen::Vector3d want = d.frames[size_t(k)].front().col(Eigen::Index(j));
        EXPECT_NEAR(got(0), want(0), 1e-4);
        EXPECT_NEAR(got(1), want(1), 1e-4);
        EXPECT_EQ(got(2), 1.0);
        ++compared;
      }
    }
    EXPECT_GT(compared, 1000);
  }
  for (size_t cam = 0; cam < 4; ++cam) b.per_camera[cam].detections = &from_trc[cam];
  const AutoSyncOptions options = BalancingSyncOptions();
  const fs::path trc = BalancingTrc(root);
  const AutoSyncResult r =
      SyncFromDetections(capture::ReadTrial(ShiftedTrc(trc, 7, dir)), b.per_camera, options);
  RecordProperty("trc2d_shifted_offset_frames", std::to_string(r.sync.offset_s * 60));
  EXPECT_NEAR(r.sync.offset_s * 60.0, 7.0, 1.0 / 3.0);
  // A 3D file given as detections is refused, naming the marker and the frame.
  std::string e;
  try {
    capture::ReadDetections(trc, "body25b");
  } catch (const InputError& error) {
    e = error.what();
  }
  EXPECT_NE(e.find("is not 0: a 3D file, not 2D detections"), std::string::npos) << e;
  fs::remove_all(dir);
}

TEST(AutoSync, DetectionsWithNoSharedNameAreRefused) {
  const fs::path root = acro::testing::RefdataFile("pose2sim-demo");
  ACRO_REQUIRE_REFDATA_FILE(root / "balancing-trial");
  const Balancing b = LoadBalancing();
  capture::Trial trial;
  trial.point_rate_hz = 60;
  trial.num_frames = 2;
  trial.points.push_back({"C7", "", capture::PointType::kMarker, "m"});
  trial.positions = Eigen::Matrix3Xd::Zero(3, 2);
  std::string e;
  try {
    SyncFromDetections(trial, b.per_camera);
  } catch (const InputError& error) {
    e = error.what();
  }
  EXPECT_NE(e.find("sync: no point of the trial is named like a keypoint"), std::string::npos) << e;
}

// A virtual camera 10 m beside the trampoline films the sample routine's markers, drawn as white
// discs on a noisy grey background; the video starts 0.37 s after the trial.
TEST(AutoSync, ImageMotionFindsAVideoStarting037sLateWithinAFrame) {
  const fs::path c3d =
      acro::testing::SourceDir() / "samples/trials/trampoline_routine/trampoline_routine.c3d";
  const capture::Trial trial = capture::ReadTrial(c3d);
  // The bed's centre from its corner markers.
  Eigen::Vector3d bed = Eigen::Vector3d::Zero();
  int corners = 0;
  for (int p = 0; p < trial.num_points(); ++p)
    if (trial.points[size_t(p)].label.rfind("BED_C", 0) == 0 && trial.valid(0, p)) {
      bed += trial.position(0, p);
      ++corners;
    }
  ASSERT_EQ(corners, 4);
  bed /= corners;
  Camera camera;
  camera.name = "side";
  camera.width_px = 480;
  camera.height_px = 360;
  camera.K << 300, 0, 240, 0, 300, 180, 0, 0, 1;
  // Looking along +y at the point 3.5 m above the bed from 10 m away: x right = world x, y down =
  // world −z.
  const Eigen::Vector3d centre = bed + Eigen::Vector3d(0, -10, 3.5);
  camera.R_KW << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  camera.t_KW = -camera.R_KW * centre;
  std::string why;
  ASSERT_TRUE(camera.IsValid(&why)) << why;

  const double fps = 30.0, late_s = 0.37;
  const fs::path dir = acro::testing::ScratchDir("sync_motion");
  const fs::path video_path = dir / "side.mp4";
  {
    capture::VideoWriterOptions w;
    w.fps = fps;
    w.preset = "ultrafast";
    capture::VideoWriter writer(video_path, camera.width_px, camera.height_px, w);
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 6.0);
    std::vector<std::uint8_t> rgb(size_t(camera.width_px) * camera.height_px * 3);
    const VideoSync truth{-late_s, 1.0};
    for (int k = 0;; ++k) {
      const int f = truth.NearestSample(trial, k / fps);
      if (f < 0) break;
      for (auto& v : rgb) v = static_cast<std::uint8_t>(std::clamp(110.0 + noise(rng), 0.0, 255.0));
      for (int p = 0; p < trial.num_points(); ++p) {
        if (!trial.valid(f, p)) continue;
        const auto uv = camera.Project(trial.position(f, p));
        if (!uv) continue;
        for (int dy = -3; dy <= 3; ++dy)
          for (int dx = -3; dx <= 3; ++dx) {
            const int x = int(std::lround(uv->x())) + dx, y = int(std::lround(uv->y())) + dy;
            if (dx * dx + dy * dy > 9 || x < 0 || y < 0 || x >= camera.width_px ||
                y >= camera.height_px)
              continue;
            std::uint8_t* px = &rgb[(size_t(y) * camera.width_px + x) * 3];
            px[0] = px[1] = px[2] = 250;
          }
      }
      writer.Write(rgb);
    }
    writer.Finish();
  }
  capture::VideoReader video(video_path, {.pixels = capture::VideoPixels::kGrey});
  AutoSyncOptions options;
  options.min_offset_s = -2.0;
  options.max_offset_s = 2.0;
  const AutoSyncResult r = SyncFromImageMotion(trial, camera, video, options);
  RecordProperty("offset_s", std::to_string(r.sync.offset_s));
  RecordProperty("correlation", std::to_string(1.0 - r.cost));
  RecordProperty("runner_up_correlation", std::to_string(1.0 - r.runner_up_cost));
  EXPECT_NEAR(r.sync.offset_s, -late_s, 1.0 / fps);
  EXPECT_EQ(r.method, "image motion");
  EXPECT_GT(1.0 - r.cost, 0.8);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro::vision
