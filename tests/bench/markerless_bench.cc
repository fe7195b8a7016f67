// Reconstruction from several cameras' detections (#39, docs/markerless.md): the goal is ≥ 10×
// real time for 4 cameras at 60 fps, i.e. 600 frames of 4 views a second or better. A body of 25
// keypoints moving through a bounce, seen by 4 cameras around it, with 1.5 px noise and one wrong
// keypoint per camera and frame (so that the consensus has work to do).

#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/dynamics/configuration.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"
#include "acro/reconstruct/triangulation.h"
#include "acro/reconstruct/view_sync.h"

namespace {

using acro::analysis::CameraView;

acro::vision::Camera LookAt(const std::string& name, const Eigen::Vector3d& centre) {
  acro::vision::Camera c;
  c.name = name;
  c.width_px = 1920;
  c.height_px = 1080;
  c.K << 1400, 0, 960, 0, 1400, 540, 0, 0, 1;
  c.distortion = {-0.1, 0.05, 0, 0};
  acro::vision::AimCamera(&c, centre, Eigen::Vector3d(0, 0, 2));
  return c;
}

std::vector<CameraView> Views(int frames, int late_frames) {
  std::vector<CameraView> views;
  const std::vector<Eigen::Vector3d> centres = {
      {0, 8, 2}, {8, 0, 2.5}, {0, -8, 1.8}, {-8, 0.5, 2.2}};
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 1.5);
  std::uniform_int_distribution<int> wrong(0, 24);
  const int n = 25;
  for (size_t c = 0; c < centres.size(); ++c) {
    CameraView v;
    v.camera = LookAt("cam" + std::to_string(c), centres[c]);
    for (int j = 0; j < n; ++j) v.detections.names.push_back("k" + std::to_string(j));
    const int start = c == 1 ? late_frames : 0;
    for (int k = 0; k < frames; ++k) {
      const double t = (k + start) / 60.0;
      acro::capture::DetectedPerson p(3, n);
      const int bad = wrong(rng);
      for (int j = 0; j < n; ++j) {
        // Keypoints on a body 1.7 m tall that bounces 2 m and turns about the lateral axis.
        const double a = 2 * M_PI * 0.9 * t, h = 1.0 + 2.0 * std::abs(std::sin(M_PI * t / 1.8));
        const Eigen::Vector3d local(0.15 * std::sin(j), 0.2 * std::cos(3 * j), 0.07 * j - 0.85);
        const Eigen::Vector3d X =
            Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()) * local + Eigen::Vector3d(0.1 * t, 0, h);
        Eigen::Vector2d uv = *v.camera.Project(X) + Eigen::Vector2d(noise(rng), noise(rng));
        if (j == bad) uv.x() += 120;
        p.col(j) << uv, 0.8;
      }
      v.detections.frames.push_back({p});
    }
    views.push_back(std::move(v));
  }
  return views;
}

void BM_TriangulateFourCameras(benchmark::State& state) {
  const int frames = 600;  // 10 s at 60 fps
  const std::vector<CameraView> views = Views(frames, 0);
  for (auto _ : state) benchmark::DoNotOptimize(acro::analysis::TriangulateKeypoints(views));
  state.counters["frames_per_s"] =
      benchmark::Counter(frames, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["x_real_time"] =
      benchmark::Counter(frames / 60.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_TriangulateFourCameras)->Unit(benchmark::kMillisecond);

void BM_SyncFourCameras(benchmark::State& state) {
  const int frames = 600;
  const std::vector<CameraView> views = Views(frames, 7);
  const std::vector<double> rates(4, 60.0);
  acro::analysis::ViewSyncOptions options;
  options.max_offset_s = 2.0;
  for (auto _ : state) benchmark::DoNotOptimize(acro::analysis::SyncViews(views, rates, options));
  state.counters["x_real_time"] =
      benchmark::Counter(frames / 60.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SyncFourCameras)->Unit(benchmark::kMillisecond);

// One frame of the fit of the model to the views (view_fit.h) against the fit to triangulated
// points, both warm-started 3° and 2 cm off: BODY_25B keypoints, 4 cameras' rays. The goal is the
// same ≥ 10× real time at 60 fps (≤ 1.7 ms a frame); the ratio to the fit to the points is what
// the default `--fit views` adds to a reconstruction.
struct FrameFit {
  FrameFit()
      : body(acro::analysis::MakeDeLevaBody(1.75, 65.0, acro::analysis::Sex::kFemale)),
        model(acro::analysis::MakeStandardHumanModel(body)),
        ik(model,
           acro::analysis::PlaceMarkers(
               acro::analysis::BuiltinMarkerSet("body25b"), model, body.height_m),
           acro::analysis::StandardJointLimits(model)) {
    truth = acro::dynamics::MakeNeutralConfiguration(model);
    truth.head<3>() << 0.1, 0.2, 2.4;
    for (int j = 7; j < truth.size(); ++j) truth[j] = 0.3 * std::sin(1.7 * j);
    ik.CalcMarkerPositions(truth, points);
    for (int m = 0; m < points.cols(); ++m)
      for (const CameraView& v : Views(1, 0)) {
        acro::analysis::MarkerRay ray;
        ray.marker = m;
        ray.origin_W = v.camera.CentreInWorld();
        ray.direction_W = (points.col(m) - ray.origin_W).normalized();
        rays.push_back(ray);
      }
    start = truth;
    start.head<3>() += Eigen::Vector3d(0.02, -0.01, 0.01);
    for (int j = 7; j < start.size(); ++j) start[j] += 0.05 * ((j % 2) ? 1 : -1);
  }
  acro::analysis::AthleteBody body;
  acro::dynamics::Model<double> model;
  acro::analysis::InverseKinematics ik;
  Eigen::VectorXd truth, start;
  Eigen::Matrix3Xd points;
  std::vector<acro::analysis::MarkerRay> rays;
};

void BM_FitFrameToPoints(benchmark::State& state) {
  FrameFit f;
  for (auto _ : state) {
    Eigen::VectorXd q = f.start;
    benchmark::DoNotOptimize(f.ik.Solve(f.points, q));
  }
  state.counters["x_real_time_60fps"] =
      benchmark::Counter(1 / 60.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FitFrameToPoints)->Unit(benchmark::kMicrosecond);

void BM_FitFrameToFourViews(benchmark::State& state) {
  FrameFit f;
  for (auto _ : state) {
    Eigen::VectorXd q = f.start;
    benchmark::DoNotOptimize(f.ik.SolveRays(f.rays, q));
  }
  state.counters["x_real_time_60fps"] =
      benchmark::Counter(1 / 60.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FitFrameToFourViews)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
