// Per-frame inverse kinematics: 39 Plug-in Gait markers on the standard human (de Leva, 1.75 m),
// warm-started from the previous frame's solution, 1 mm marker noise, a periodic motion at 200 Hz
// (one somersault per 1.2 s, every joint angle oscillating), so that the benchmark loop can run
// frame after frame indefinitely. Run: build/bench/reconstruct_bench (docs/performance.md).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"

namespace {

using acro::analysis::InverseKinematics;
using acro::analysis::InverseKinematicsOptions;

struct Scene {
  acro::dynamics::Model<double> model;
  std::vector<acro::analysis::ModelMarker> markers;
  std::vector<Eigen::Matrix3Xd> frames;
  Eigen::VectorXd q0;
};

const Scene& GetScene() {
  static const Scene scene = [] {
    const acro::analysis::AthleteBody body =
        acro::analysis::MakeDeLevaBody(1.75, 65.0, acro::analysis::Sex::kFemale);
    Scene s{acro::analysis::MakeStandardHumanModel(body), {}, {}, {}};
    s.markers = acro::analysis::PlaceMarkers(
        acro::analysis::BuiltinMarkerSet("plug_in_gait"), s.model, body.height_m);
    const int N = 240;  // 1.2 s at 200 Hz: one somersault, one period of every joint
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 1e-3);
    acro::dynamics::Workspace<double> ws(s.model);
    for (int k = 0; k < N; ++k) {
      const double phase = 2.0 * std::numbers::pi * k / N;
      Eigen::VectorXd q = acro::dynamics::MakeNeutralConfiguration(s.model);
      q.head<3>() << 0.1 * std::sin(phase), 0.0, 3.0 + 0.5 * std::cos(phase);
      const Eigen::Quaterniond r(
          Eigen::AngleAxisd(phase, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.3 * std::sin(phase), Eigen::Vector3d::UnitZ()));
      q.segment<4>(3) << r.w(), r.x(), r.y(), r.z();
      for (int j = 7; j < q.size(); ++j) q[j] = 0.3 * std::sin(phase * (1 + j % 2) + j);
      if (k == 0) s.q0 = q;
      acro::dynamics::CalcForwardKinematics(s.model, ws, q);
      Eigen::Matrix3Xd obs(3, static_cast<Eigen::Index>(s.markers.size()));
      for (size_t m = 0; m < s.markers.size(); ++m)
        obs.col(Eigen::Index(m)) = ws.X_WB[size_t(s.markers[m].segment)] * s.markers[m].p_BoM_B +
                                   Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      s.frames.push_back(obs);
    }
    return s;
  }();
  return scene;
}

/// Arguments: maximum iterations per frame, 1 = dense normal Cholesky / 0 = dense QR,
/// 1 = structured Levenberg–Marquardt for warm starts / 0 = ceres::Problem.
void BM_IkPerFrameWarmStarted(benchmark::State& state) {
  const Scene& s = GetScene();
  InverseKinematicsOptions options;
  options.max_iterations = static_cast<int>(state.range(0));
  options.normal_cholesky = state.range(1) != 0;
  options.structured_warm_start = state.range(2) != 0;
  InverseKinematics ik(s.model, s.markers, acro::analysis::StandardJointLimits(s.model), options);
  Eigen::VectorXd q = s.q0;
  // Settle on the first frame, then one frame per benchmark iteration.
  ik.Solve(s.frames[0], q, true);
  size_t f = 1;
  double iterations = 0, rms = 0;
  for (auto _ : state) {
    const acro::analysis::IkFrameResult r = ik.Solve(s.frames[f], q, false);
    benchmark::DoNotOptimize(q.data());
    iterations += r.iterations;
    rms += r.rms_m;
    f = (f + 1) % s.frames.size();
  }
  state.counters["iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
  state.counters["rms_mm"] = benchmark::Counter(rms * 1e3, benchmark::Counter::kAvgIterations);
  state.counters["markers"] = static_cast<double>(s.markers.size());
}
BENCHMARK(BM_IkPerFrameWarmStarted)
    ->Args({10, 1, 0})
    ->Args({3, 1, 0})
    ->Args({2, 1, 0})
    ->Args({10, 0, 0})
    ->Args({10, 1, 1})
    ->Args({3, 1, 1})
    ->Unit(benchmark::kMicrosecond);

/// The forward kinematics and 39 point Jacobians of one evaluation (the analytic Jacobian's cost).
void BM_MarkerJacobians(benchmark::State& state) {
  const Scene& s = GetScene();
  acro::dynamics::Workspace<double> ws(s.model);
  Eigen::Matrix3Xd J = Eigen::Matrix3Xd::Zero(3, s.model.nv());
  for (auto _ : state) {
    acro::dynamics::CalcForwardKinematics(s.model, ws, s.q0);
    for (const auto& m : s.markers) {
      acro::dynamics::CalcPointJacobian(s.model, ws, m.segment, m.p_BoM_B, J);
      benchmark::DoNotOptimize(J.data());
    }
  }
}
BENCHMARK(BM_MarkerJacobians)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
