#pragma once

// Keyframe timing optimisation (Model 2) and trajectory optimisation (Model 1) of a skill, and the
// driver that runs Model 2 and then, when asked, Model 1 from its optimum (DESIGN.md, "Keyframe
// timing and trajectory optimisation"; docs/skill-design.md). The objective
//   J = T⁻¹ ∫₀ᵀ |n_Scm(t)|² dt
// (skill_design.h) is integrated by Simpson's rule on a fixed grid; derivatives come from
// automatic differentiation (ceres::Jet) through the motion and the inverse dynamics. Model 2
// lives in src/timing_optimization.*, Model 1 in src/trajectory_optimization.*; each depends on
// skill_design.h and on the option types here, not on each other.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/design/skill_design.h"

namespace acro::analysis {

/// The optimisation variables x of Model (m) about a base trajectory:
///   Model 2: the n − 1 gaps (s), t_i = T Σ_{j<i} g_j / Σ g_j;
///   Model 1 (base with knots, MakeKnotTrajectory): the gaps, then per knot k, contiguous, the
///   offsets of its joint angles (num_joint_dofs), of its orientation δ_k (3: Q_k = Q̄_k ⊗
///   exp(δ_k/2), |δ_k| the geodesic distance), of its joint rates and accelerations (y' then y'',
///   2 num_joint_dofs) and of its body angular velocity and acceleration (6).
int NumSkillParameters(const SkillDesign& design, SkillModel model, int knots_per_interval = 2);
/// x for the base trajectory itself (its gaps, zero offsets).
Eigen::VectorXd InitialSkillParameters(const SkillDesign& design,
                                       const SkillTrajectory& base,
                                       SkillModel model);
/// The trajectory that x describes.
SkillTrajectory SkillTrajectoryFromParameters(const SkillDesign& design,
                                              const SkillTrajectory& base,
                                              SkillModel model,
                                              const Eigen::VectorXd& x);
/// J(x) by Simpson's rule, and ∂J/∂x by automatic differentiation when gradient != nullptr.
/// Model 2: `intervals` (even) uniform intervals over [0, T]. Model 1: `intervals` (even) equal
/// intervals in every knot interval (the grid moves with the knots), evaluated by the same
/// per-sample residual blocks the solver uses.
double CalcSkillObjective(const SkillDesign& design,
                          const SkillTrajectory& base,
                          SkillModel model,
                          const Eigen::VectorXd& x,
                          int intervals,
                          Eigen::VectorXd* gradient = nullptr);

struct SkillOptimizationOptions {
  SkillModel model = SkillModel::kTiming;
  /// Simpson's rule on this many intervals over [0, T] (even): 40 gives samples 40 ms apart at
  /// T = 1.6 s, about four per keyframe interval.
  int quadrature_intervals = 40;
  /// Smallest gap between keyframes, as a fraction of the even gap T/(n − 1).
  double min_gap_fraction = 0.15;
  int max_iterations = 200;
  /// Ceres' convergence tests: stop when the relative decrease of the cost falls below
  /// function_tolerance (J then has about six stable digits), and so on.
  double function_tolerance = 1e-5;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  /// Model 1 varies the joint angles at the keyframes (true) or keeps them as given and varies only
  /// the times and the root orientation knots (false).
  bool model1_vary_joints = true;
  /// Model 1's local form: knots per keyframe interval (1: the keyframes only; each carries its
  /// values, rates and accelerations, so the motion between keyframes is already free).
  int model1_knots_per_interval = 1;
  /// Model 1's quadrature: Simpson's rule on this many (even) equal intervals in every knot
  /// interval. Fewer lets the quintic pieces bend between the samples: on the paper's example 4
  /// gives a solver J 70 times below the same motion's J on a fine grid, 8 agrees within 0.2 %.
  int model1_samples_per_knot_interval = 8;
  /// Model 1 stops when an iteration lowers J by less than this fraction of it. Its quadrature
  /// agrees with the 8 times finer check grid to about 0.2 %, so steps below 0.1 % refine digits
  /// that J does not have: on the paper's example 43 iterations instead of 54 with 1e-5, for a J
  /// 0.2 % higher and the same keyframe times within 1 ms (docs/performance.md).
  double model1_function_tolerance = 1e-3;
  /// Model 1 starts from the Model 2 optimum (true) or from the initial times.
  bool model1_from_model2 = true;
  /// Threads that evaluate Model 1's residual blocks (0: the hardware's concurrency).
  int num_threads = 0;
  /// Progress lines (iteration, objective) are handed here when set; the library prints nothing.
  std::function<void(const std::string&)> progress;
  /// Asked after every solver iteration when set: true stops the optimisation, and OptimizeSkill
  /// throws acro::Cancelled ("optimisation: cancelled").
  std::function<bool()> cancelled;

  bool IsValid(std::string* why) const;
};

struct SkillOptimizationSummary {
  bool success = false;
  std::string message;
  int iterations = 0;
  double initial_cost = 0.0;  ///< the solver's cost ½‖r‖² at the start
  double final_cost = 0.0;
  double time_s = 0.0;
  std::string BriefReport() const;
};

struct SkillOptimizationResult {
  SkillModel model = SkillModel::kTiming;
  Eigen::VectorXd times_initial_s;  ///< the even (or guessed) timing the optimisation starts from
  SkillTrajectory initial;          ///< keyframes at the initial times
  SkillTrajectory optimized;
  /// J with the initial timing and after optimisation, on a check grid 8 times finer than the
  /// optimisation's (the solver's own figures are in `stages`).
  double objective_initial = 0.0;
  double objective = 0.0;
  double angular_momentum_variation_initial = 0.0;
  double angular_momentum_variation = 0.0;
  /// Model 1: the largest keyframe deviation of any joint angle and of the root orientation
  /// (geodesic angle), rad; zero for Model 2.
  double max_joint_deviation_rad = 0.0;
  double max_orientation_deviation_rad = 0.0;
  std::vector<SkillOptimizationSummary> stages;  ///< Model 2, then Model 1 when asked
  SkillOptimizationSummary summary;              ///< the last stage
};

/// Optimises the skill's timing (Model 2) or timing and trajectory (Model 1, after Model 2).
SkillOptimizationResult OptimizeSkill(const SkillDesign& design,
                                      const SkillOptimizationOptions& options);

}  // namespace acro::analysis
