// Dynamics benchmarks on the 15-segment, 38-DoF reference human (docs/performance.md).
// Run: build-dyn/bench/dynamics_bench --benchmark_repetitions=9
// --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "acro/dynamics/flight_rotation.h"
#include "acro/dynamics/flight_simulation.h"
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

// A whole flight of a double somersault's length (1.8 s at the skill designer's 2 ms step), the
// joints moving (a tuck and open with an asymmetric arm swing): the Newton–Euler flight simulation
// against the rotation from the conserved momentum (flight_rotation.h), with and without sampling
// the joint motion — the shooting of a skill samples it once per joint motion and reuses it for
// every change of the take-off momentum.
constexpr double kFlight = 1.8;
constexpr int kSteps = 900;
JointTrajectory<double> MovingJoints(const Model<double>& model) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::VectorXd amplitude =
      Eigen::VectorXd::NullaryExpr(model.num_joint_dofs(), [&] { return u(rng); });
  return [amplitude](
             const double& t, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
    const double w = 2.0 * M_PI / kFlight;
    q = amplitude * (0.5 * (1.0 - std::cos(w * t)));
    v = amplitude * (0.5 * w * std::sin(w * t));
    a = amplitude * (0.5 * w * w * std::cos(w * t));
  };
}

void BM_FlightNewtonEuler(benchmark::State& state) {
  const Model<double> model = acro::dynamics::testing::MakeStandardHuman();
  const JointTrajectory<double> joints = MovingJoints(model);
  Eigen::Matrix<double, 7, 1> q_root;
  q_root << 0, 0, 1.1, 1, 0, 0, 0;
  Vector6<double> v_root;
  v_root << 0, 7.0, 1.0, 0, 0, 8.8;
  FlightSimulationOptions options;
  options.duration_s = kFlight;
  options.step_s = kFlight / kSteps;
  for (auto _ : state) {
    const FlightSimulationResult<double> r = SimulateFlight(model, options, q_root, v_root, joints);
    benchmark::DoNotOptimize(r.q.back().data());
  }
}
BENCHMARK(BM_FlightNewtonEuler)->Unit(benchmark::kMillisecond);

void BM_FlightRotation(benchmark::State& state) {
  const Model<double> model = acro::dynamics::testing::MakeStandardHuman();
  const JointTrajectory<double> joints = MovingJoints(model);
  const Eigen::Vector3d H(0.0, 55.0, 9.0);
  for (auto _ : state) {
    const JointMotionSamples samples = SampleJointMotion(model, kFlight, kSteps, joints);
    const std::vector<Eigen::Quaterniond> r =
        SimulateFlightRotation(samples, Eigen::Quaterniond::Identity(), H);
    benchmark::DoNotOptimize(r.back().coeffs().data());
  }
}
BENCHMARK(BM_FlightRotation)->Unit(benchmark::kMillisecond);

void BM_FlightRotationSameJoints(benchmark::State& state) {
  const Model<double> model = acro::dynamics::testing::MakeStandardHuman();
  const JointMotionSamples samples = SampleJointMotion(model, kFlight, kSteps, MovingJoints(model));
  const Eigen::Vector3d H(0.0, 55.0, 9.0);
  for (auto _ : state) {
    const std::vector<Eigen::Quaterniond> r =
        SimulateFlightRotation(samples, Eigen::Quaterniond::Identity(), H);
    benchmark::DoNotOptimize(r.back().coeffs().data());
  }
}
BENCHMARK(BM_FlightRotationSameJoints)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace acro::dynamics

BENCHMARK_MAIN();
