// Skill design benchmarks on the paper's example, samples/skills/front_1_3_4_half_twist.yaml
// (docs/performance.md, "Skill design").
// Run: build-opt/bench/optimize_bench --benchmark_repetitions=9
// --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <filesystem>

#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"

namespace acro::analysis {
namespace {

const SkillDesign& Example() {
  // The sample relative to this file (tests/bench/ → repository root).
  static const SkillDesign design(
      ReadSkill(std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() /
                "samples/skills" / "front_1_3_4_half_twist.yaml"));
  return design;
}

// Model 2 from even timing: the whole OptimizeSkill call (initial and final profiles
// included).
void BM_Model2(benchmark::State& state) {
  SkillOptimizationOptions o;
  o.model = SkillModel::kTiming;
  double ratio = 0.0;
  for (auto _ : state) {
    const SkillOptimizationResult r = OptimizeSkill(Example(), o);
    ratio = r.objective_initial / r.objective;
    benchmark::DoNotOptimize(ratio);
  }
  state.counters["J_ratio"] = ratio;
}
BENCHMARK(BM_Model2)->Unit(benchmark::kMillisecond);

// One objective and gradient of Model 2 on the default 40 quadrature intervals (what each solver
// iteration costs).
void BM_Model2Gradient(benchmark::State& state) {
  const SkillTrajectory t = MakeKeyframeTrajectory(Example(), Example().EvenTimes());
  const Eigen::VectorXd x = InitialSkillParameters(Example(), t, SkillModel::kTiming);
  Eigen::VectorXd g;
  for (auto _ : state)
    benchmark::DoNotOptimize(CalcSkillObjective(Example(), t, SkillModel::kTiming, x, 40, &g));
}
BENCHMARK(BM_Model2Gradient)->Unit(benchmark::kMillisecond);

// One objective and gradient of Model 1 in its local form on the default grid (one knot per
// keyframe interval, 8 Simpson intervals in each: 89 samples, 1271 variables), on one thread:
// the Jacobian work of one solver iteration.
void BM_Model1Gradient(benchmark::State& state) {
  const SkillTrajectory t =
      MakeKnotTrajectory(MakeKeyframeTrajectory(Example(), Example().EvenTimes()), 1);
  const Eigen::VectorXd x = InitialSkillParameters(Example(), t, SkillModel::kTrajectory);
  Eigen::VectorXd g;
  for (auto _ : state)
    benchmark::DoNotOptimize(CalcSkillObjective(Example(), t, SkillModel::kTrajectory, x, 8, &g));
}
BENCHMARK(BM_Model1Gradient)->Unit(benchmark::kMillisecond);

// Model 1 (after Model 2).
void BM_Model1(benchmark::State& state) {
  SkillOptimizationOptions o;
  o.model = SkillModel::kTrajectory;
  double ratio = 0.0, model1_s = 0.0, iterations = 0.0;
  for (auto _ : state) {
    const SkillOptimizationResult r = OptimizeSkill(Example(), o);
    ratio = r.objective_initial / r.objective;
    model1_s = r.stages.back().time_s;
    iterations = r.stages.back().iterations;
    benchmark::DoNotOptimize(ratio);
  }
  state.counters["J_ratio"] = ratio;
  state.counters["model1_stage_s"] = model1_s;  // the Model 1 solve alone
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_Model1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace acro::analysis

BENCHMARK_MAIN();
