// Dynamics benchmarks on the 15-segment, 38-DoF reference human (docs/performance.md).
// Run: build-dyn/bench/dynamics_bench --benchmark_repetitions=9
// --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <random>

#include "acro/dynamics/inverse_dynamics.h"
#include "standard_human_fixture.h"

namespace acro::dynamics {
namespace {

// A fixed random state: root anywhere, random orientation, joint angles in (−1, 1) rad, velocities
// in (−2, 2), accelerations in (−10, 10).
struct HumanState {
  Model<double> model = acro::dynamics::testing::MakeStandardHuman();
  Eigen::VectorXd q, v, a;
  HumanState() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    q = MakeNeutralConfiguration(model);
    for (int k = 0; k < model.nq(); ++k)
      if (k < 3 || k >= 7) q[k] = u(rng);
    Eigen::Quaterniond quat(u(rng), u(rng), u(rng), u(rng));
    quat.normalize();
    SetRootQuaternion(quat, q);
    v = 2.0 * Eigen::VectorXd::NullaryExpr(model.nv(), [&] { return u(rng); });
    a = 10.0 * Eigen::VectorXd::NullaryExpr(model.nv(), [&] { return u(rng); });
  }
};

void BM_InverseDynamics(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  for (auto _ : state) {
    benchmark::DoNotOptimize(CalcInverseDynamics(h.model, ws, h.q, h.v, h.a).data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_InverseDynamics);

void BM_MassMatrix(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  for (auto _ : state) {
    benchmark::DoNotOptimize(CalcMassMatrix(h.model, ws, h.q).data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_MassMatrix);

// Poses and spatial velocities of all segments.
void BM_ForwardKinematics(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  for (auto _ : state) {
    CalcForwardKinematics(h.model, ws, h.q, h.v);
    benchmark::DoNotOptimize(ws.V_WB_B.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ForwardKinematics);

// Poses only.
void BM_ForwardKinematicsPoses(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  for (auto _ : state) {
    CalcForwardKinematics(h.model, ws, h.q);
    benchmark::DoNotOptimize(ws.X_WB.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ForwardKinematicsPoses);

// One right-hand side of the flight simulation: inverse dynamics + whole-body inertia + 6×6 solve.
void BM_FlightRootAcceleration(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  Eigen::VectorXd a = h.a;
  for (auto _ : state) {
    CalcFlightRootAcceleration(h.model, ws, h.q, h.v, a);
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_FlightRootAcceleration);

// Inverse dynamics and the root residual at the centre of mass, as the physical check runs it.
void BM_InverseDynamicsWithRootResidual(benchmark::State& state) {
  HumanState h;
  Workspace<double> ws(h.model);
  for (auto _ : state) {
    CalcInverseDynamics(h.model, ws, h.q, h.v, h.a);
    const RootResidual<double> r = CalcRootResidual(h.model, ws, 1.75);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_InverseDynamicsWithRootResidual);

}  // namespace
}  // namespace acro::dynamics

BENCHMARK_MAIN();
