// Skill design benchmarks on the paper's example, samples/skills/front_1_3_4_half_twist.yaml, and
// skills and a routine designed from their FIG codes (docs/performance.md, "Skill design").
// Run: build-opt/bench/optimize_bench --benchmark_repetitions=9
// --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>

#include "acro/design/routine_design.h"
#include "acro/design/skill_from_code.h"
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

std::filesystem::path SampleAthlete() {
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() /
         "samples/athletes/sample_athlete.yaml";
}

// A skill from its FIG code as `acrolab design` makes it: the shooting of its keyframes, then
// Model 2 and Model 1 (the goal for a double somersault with a twist: <= 3 s). The
// argument picks the code.
const char* const kCodes[] = {"801o", "801<", "811o", "821o"};
void BM_DesignFromCode(benchmark::State& state) {
  const char* code = kCodes[state.range(0)];
  state.SetLabel(code);
  SkillOptimizationOptions o;
  o.model = SkillModel::kTrajectory;
  double shooting_s = 0, variation = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const SkillFromCodeResult d = DesignSkillFromCode(code, SampleAthlete());
    shooting_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const SkillOptimizationResult r = OptimizeSkill(SkillDesign(d.skill), o);
    variation = r.angular_momentum_variation;
  }
  state.counters["shooting_s"] = shooting_s;
  state.counters["variation"] = variation;
}
BENCHMARK(BM_DesignFromCode)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->Iterations(1);

// The ten-skill routine (`acrolab routine --codes …` without its files): every skill
// designed (two at a time), the composition checked, the routine flown through the bed (goal:
// <= 30 s).
void BM_Routine(benchmark::State& state) {
  const RoutineSpec spec =
      RoutineSpecFromCodes("40o 41/ 42/ 43/ 800o 800< 801< 811o 821o 831<", SampleAthlete());
  double tof = 0;
  for (auto _ : state) {
    const RoutineDesignResult r = DesignRoutine(spec, {});
    tof = r.time_of_flight_s;
  }
  state.counters["time_of_flight_s"] = tof;
}
BENCHMARK(BM_Routine)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace acro::analysis

BENCHMARK_MAIN();
