// The skill-optimisation driver: Model 2, then Model 1 from its optimum when asked; the reports
// on a check grid finer than the solvers'.

#include "acro/design/skill_optimization.h"

#include <algorithm>
#include <sstream>

#include "acro/base/demand.h"
#include "acro/base/progress.h"
#include "acro/base/input_error.h"
#include "timing_optimization.h"
#include "trajectory_optimization.h"

namespace acro::analysis {
namespace {

double MaxJointDeviation(const SkillDesign& design, const SkillTrajectory& t) {
  return (t.joint_angles_rad - design.keyframe_joint_angles_rad()).cwiseAbs().maxCoeff();
}

double MaxOrientationDeviation(const SkillDesign& design, const SkillTrajectory& t) {
  double worst = 0.0;
  for (size_t i = 0; i < t.keyframe_orientations.size(); ++i)
    worst = std::max(worst,
                     t.keyframe_orientations[i].angularDistance(design.keyframe_orientations()[i]));
  return worst;
}

}  // namespace

int NumSkillParameters(const SkillDesign& design, SkillModel model, int knots_per_interval) {
  if (model == SkillModel::kTrajectory)
    return internal::NumModel1Parameters(design, knots_per_interval);
  return internal::NumModel2Parameters(design);
}

Eigen::VectorXd InitialSkillParameters(const SkillDesign& design,
                                       const SkillTrajectory& base,
                                       SkillModel model) {
  ACRO_DEMAND(model == SkillModel::kTiming || base.has_knots());
  Eigen::VectorXd x =
      Eigen::VectorXd::Zero(NumSkillParameters(design, model, base.knots_per_interval));
  for (int j = 0; j + 1 < design.num_keyframes(); ++j) x[j] = base.times_s[j + 1] - base.times_s[j];
  return x;
}

SkillTrajectory SkillTrajectoryFromParameters(const SkillDesign& design,
                                              const SkillTrajectory& base,
                                              SkillModel model,
                                              const Eigen::VectorXd& x) {
  if (model == SkillModel::kTrajectory)
    return internal::Model1TrajectoryFromParameters(design, base, x);
  return internal::Model2TrajectoryFromParameters(design, base, x);
}

double CalcSkillObjective(const SkillDesign& design,
                          const SkillTrajectory& base,
                          SkillModel model,
                          const Eigen::VectorXd& x,
                          int intervals,
                          Eigen::VectorXd* gradient) {
  if (model == SkillModel::kTrajectory)
    return internal::CalcModel1Objective(design, base, x, intervals, gradient);
  return internal::CalcModel2Objective(design, base, x, intervals, gradient);
}

bool SkillOptimizationOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (model != SkillModel::kTiming && model != SkillModel::kTrajectory)
    return fail("model must be 1 or 2");
  if (quadrature_intervals < 2 || quadrature_intervals > 2000 || quadrature_intervals % 2 != 0)
    return fail("quadrature_intervals must be even, 2–2000");
  if (!(min_gap_fraction > 0.0 && min_gap_fraction < 1.0))
    return fail("min_gap_fraction must lie in (0, 1)");
  if (max_iterations < 0) return fail("max_iterations must be non-negative");
  if (!(model1_function_tolerance > 0.0 && model1_function_tolerance < 1.0))
    return fail("model1_function_tolerance must lie in (0, 1)");
  if (model1_samples_per_knot_interval < 2 || model1_samples_per_knot_interval % 2 != 0)
    return fail("model1_samples_per_knot_interval must be even and at least 2");
  if (model1_knots_per_interval < 1) return fail("model1_knots_per_interval must be positive");
  if (num_threads < 0) return fail("num_threads must be non-negative");
  return true;
}

std::string SkillOptimizationSummary::BriefReport() const {
  std::ostringstream s;
  s << (success ? "converged" : "not converged") << " after " << iterations << " iterations, cost "
    << initial_cost << " -> " << final_cost << ", " << time_s << " s: " << message;
  return s.str();
}

SkillOptimizationResult OptimizeSkill(const SkillDesign& design,
                                      const SkillOptimizationOptions& options) {
  DemandValidOptions(options, "skill optimisation options");
  SkillOptimizationResult result;
  result.model = options.model;
  result.times_initial_s = design.InitialTimes();
  result.initial = MakeKeyframeTrajectory(design, result.times_initial_s);
  const int N = options.quadrature_intervals;
  // Model 1's grid: model1_samples_per_knot_interval intervals in each of its knot intervals.
  const int n = design.num_keyframes();
  const int N1 =
      options.model1_samples_per_knot_interval * options.model1_knots_per_interval * (n - 1);
  // J and the momentum variation are reported on a check grid 8 times finer than the
  // optimisation's (Simpson's rule as well).
  const int check = 8 * std::max(N, options.model == SkillModel::kTrajectory ? N1 : N);
  const SkillMotionProfile p0 = CalcSkillMotionProfile(design, result.initial, check);
  result.objective_initial = p0.objective;
  result.angular_momentum_variation_initial = p0.angular_momentum_variation;

  // Model 2: times only.
  SkillOptimizationSummary s2;
  const Eigen::VectorXd x2 = internal::SolveModel2(design, result.initial, N, options, &s2);
  result.stages.push_back(s2);
  const auto stop_if_cancelled = [&options] {
    if (options.cancelled && options.cancelled()) throw Cancelled("optimisation: cancelled");
  };
  stop_if_cancelled();
  result.optimized = SkillTrajectoryFromParameters(design, result.initial, SkillModel::kTiming, x2);

  // Model 1: times and trajectory coefficients, from the Model 2 optimum (or the initial times).
  if (options.model == SkillModel::kTrajectory) {
    const SkillTrajectory base1 =
        MakeKnotTrajectory(options.model1_from_model2 ? result.optimized : result.initial,
                           options.model1_knots_per_interval);
    SkillOptimizationSummary s1;
    const Eigen::VectorXd x1 = internal::SolveModel1(design, base1, options, &s1);
    result.stages.push_back(s1);
    stop_if_cancelled();
    result.optimized = SkillTrajectoryFromParameters(design, base1, SkillModel::kTrajectory, x1);
  }
  result.summary = result.stages.back();
  const SkillMotionProfile p = CalcSkillMotionProfile(design, result.optimized, check);
  result.objective = p.objective;
  result.angular_momentum_variation = p.angular_momentum_variation;
  result.max_joint_deviation_rad = MaxJointDeviation(design, result.optimized);
  result.max_orientation_deviation_rad = MaxOrientationDeviation(design, result.optimized);
  return result;
}

}  // namespace acro::analysis
