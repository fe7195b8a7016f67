#pragma once

// Keyframe timing optimisation (Model 2) and trajectory optimisation (Model 1) for a skill, and
// the flight simulation of a designed skill (DESIGN.md, "Keyframe timing and trajectory
// optimisation"; docs/skill-design.md).
//
// Motion between keyframes: natural C² cubic splines for the joint angles (keyframe_spline.h) and
// the cumulative C² quaternion spline for the root orientation (quaternion_spline.h). The root
// translation is not interpolated: at every instant it is the one that puts the whole-body centre
// of mass on the ballistic parabola of the take-off velocity (DESIGN.md's reduction), so the
// three force components of the root residual vanish identically and
//   J = T⁻¹ ∫₀ᵀ |n_Scm(t)|² dt,   n_Scm = moment residual about the COM / (m g height) = L̇_Scm / (m
//   g h),
// the rate of change of the angular momentum about the centre of mass, dimensionless. The
// integral is Simpson's rule on a fixed grid of N intervals over [0, T]. Derivatives come from
// automatic differentiation (ceres::Jet) through the splines and the inverse dynamics.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/design/skill_file.h"
#include "acro/dynamics/flight_simulation.h"
#include "acro/dynamics/model.h"

namespace acro::analysis {

/// A skill made ready for optimisation: the athlete's standard human model and the keyframes.
class SkillDesign {
 public:
  explicit SkillDesign(const Skill& skill);

  const Skill& skill() const { return skill_; }
  const dynamics::Model<double>& model() const { return model_; }
  int num_keyframes() const { return static_cast<int>(skill_.keyframes.size()); }
  int num_joint_dofs() const { return model_.num_joint_dofs(); }
  double flight_time_s() const { return skill_.flight_time_s; }
  double height_m() const { return skill_.athlete.height_m; }
  /// Keyframe orientations R_WB (somersault, tilt, twist).
  const std::vector<Eigen::Quaterniond>& keyframe_orientations() const { return orientations_; }
  /// Keyframe joint angles, num_joint_dofs × num_keyframes.
  const Eigen::MatrixXd& keyframe_joint_angles_rad() const { return joint_angles_; }
  /// Times spread evenly over [0, T].
  Eigen::VectorXd EvenTimes() const;
  /// The file's time guesses where given, the even times elsewhere (interpolated between guesses).
  Eigen::VectorXd InitialTimes() const;

 private:
  Skill skill_;
  dynamics::Model<double> model_;
  std::vector<Eigen::Quaterniond> orientations_;
  Eigen::MatrixXd joint_angles_;
};

/// A designed motion: keyframe times, the joint angles at the keyframes and the orientation knots.
/// Model 2's motion is the natural cubic splines and the cumulative quaternion spline through the
/// keyframes; Model 1's is the local (Hermite) form through the knot data below when those are set
/// (docs/skill-design.md, "Model (1): local form").
struct SkillTrajectory {
  Eigen::VectorXd times_s;                                ///< num_keyframes, t_0 = 0, t_n = T
  Eigen::MatrixXd joint_angles_rad;                       ///< num_joint_dofs × num_keyframes
  std::vector<Eigen::Quaterniond> keyframe_orientations;  ///< num_keyframes
  /// Model 1's local form: knots per keyframe interval (0: not used, the splines above are the
  /// motion). Knot k = i·P + j sits at t_i + (j/P)(t_{i+1} − t_i).
  int knots_per_interval = 0;
  Eigen::MatrixXd knot_joint_angles_rad;              ///< num_joint_dofs × num_knots: y
  Eigen::MatrixXd knot_joint_rates;                   ///< y' (rad/s)
  Eigen::MatrixXd knot_joint_accelerations;           ///< y'' (rad/s²)
  std::vector<Eigen::Quaterniond> knot_orientations;  ///< R_WB at the knots
  Eigen::Matrix3Xd knot_angular_velocities_B;         ///< w_WB_B at the knots (rad/s)
  Eigen::Matrix3Xd knot_angular_accelerations_B;      ///< its derivative (rad/s²)

  bool has_knots() const { return knots_per_interval > 0; }
  int num_knots() const {
    return has_knots() ? knots_per_interval * (static_cast<int>(times_s.size()) - 1) + 1 : 0;
  }
};

/// The keyframes as given at the given times.
SkillTrajectory MakeKeyframeTrajectory(const SkillDesign& design, const Eigen::VectorXd& times_s);

/// Model 1's base: the local form with `knots_per_interval` knots per keyframe interval, its knot
/// data (values, rates, accelerations; orientations, angular velocities and accelerations) read
/// from the keyframe splines of `trajectory` at the knot times. The joint angles are the same
/// curves (a cubic is its own quintic Hermite interpolant); the orientation agrees with the
/// cumulative spline to second order at every knot.
SkillTrajectory MakeKnotTrajectory(const SkillTrajectory& trajectory, int knots_per_interval = 2);

/// Configuration, velocity and acceleration of the designed motion at time t (root translation on
/// the COM parabola; the COM starts at `com_start_W`).
struct SkillMotionState {
  Eigen::VectorXd q, v, a;
};
SkillMotionState EvalSkillMotion(const SkillDesign& design,
                                 const SkillTrajectory& trajectory,
                                 double t_s,
                                 const Eigen::Vector3d& com_start_W = Eigen::Vector3d(0, 0, 1));

/// Per-sample diagnostics of a designed motion on a uniform grid.
struct SkillMotionProfile {
  Eigen::VectorXd t_s;
  Eigen::Matrix3Xd H_Scm_W;                   ///< angular momentum about the COM (kg m²/s)
  Eigen::Matrix3Xd moment_per_weight_height;  ///< L̇/(m g h), the integrand of J
  Eigen::Matrix3Xd force_per_weight;          ///< the force residual / (m g) (zero by construction)
  double objective = 0.0;                     ///< J on this grid (Simpson)
  /// (max − min) / mean of |H_Scm| over the grid.
  double angular_momentum_variation = 0.0;
};
SkillMotionProfile CalcSkillMotionProfile(const SkillDesign& design,
                                          const SkillTrajectory& trajectory,
                                          int intervals);

/// The optimisation variables x of Model (m) about a base trajectory:
///   Model 2: the n − 1 gaps (s), t_i = T Σ_{j<i} g_j / Σ g_j;
///   Model 1 (base with knots, MakeKnotTrajectory): the gaps, then per knot k, contiguous, the
///   offsets of its joint angles (num_joint_dofs), of its orientation δ_k (3: Q_k = Q̄_k ⊗
///   exp(δ_k/2), |δ_k| the geodesic distance), of its joint rates and accelerations (y' then y'',
///   2 num_joint_dofs) and of its body angular velocity and acceleration (6).
int NumSkillParameters(const SkillDesign& design, int model, int knots_per_interval = 2);
/// x for the base trajectory itself (its gaps, zero offsets).
Eigen::VectorXd InitialSkillParameters(const SkillDesign& design,
                                       const SkillTrajectory& base,
                                       int model);
/// The trajectory that x describes.
SkillTrajectory SkillTrajectoryFromParameters(const SkillDesign& design,
                                              const SkillTrajectory& base,
                                              int model,
                                              const Eigen::VectorXd& x);
/// J(x) by Simpson's rule, and ∂J/∂x by automatic differentiation when gradient != nullptr.
/// Model 2: `intervals` (even) uniform intervals over [0, T]. Model 1: `intervals` (even) equal
/// intervals in every knot interval (the grid moves with the knots), evaluated by the same
/// per-sample residual blocks the solver uses.
double CalcSkillObjective(const SkillDesign& design,
                          const SkillTrajectory& base,
                          int model,
                          const Eigen::VectorXd& x,
                          int intervals,
                          Eigen::VectorXd* gradient = nullptr);

struct TimingOptimizationOptions {
  int model = 2;  ///< 2: times only; 1: times and trajectory coefficients
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

  bool IsValid(std::string* why) const;
};

struct TimingOptimizationSummary {
  bool success = false;
  std::string message;
  int iterations = 0;
  double initial_cost = 0.0;  ///< the solver's cost ½‖r‖² at the start
  double final_cost = 0.0;
  double time_s = 0.0;
  std::string BriefReport() const;
};

struct TimingOptimizationResult {
  int model = 2;
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
  std::vector<TimingOptimizationSummary> stages;  ///< Model 2, then Model 1 when asked
  TimingOptimizationSummary summary;              ///< the last stage
};

/// Optimises the skill's timing (Model 2) or timing and trajectory (Model 1, after Model 2).
TimingOptimizationResult OptimizeSkillTiming(const SkillDesign& design,
                                             const TimingOptimizationOptions& options);

/// Flight simulation of a designed motion: the joints follow the trajectory, the root is
/// integrated under gravity from the take-off COM velocity and an angular momentum H0 about the
/// COM. H0 is the momentum the design needs: the one whose simulated orientation follows the
/// designed orientation best over the flight (least squares on the orientation error every 10 ms,
/// from the mean of the design's own H_Scm), or that mean itself when `fit_momentum` is false.
struct SkillSimulationResult {
  dynamics::FlightSimulationResult<double> flight;
  Eigen::Vector3d H_Scm_W = Eigen::Vector3d::Zero();   ///< the take-off momentum simulated
  Eigen::Vector3d H_mean_W = Eigen::Vector3d::Zero();  ///< the design's mean H_Scm
  Eigen::Quaterniond final_orientation = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond intended_final_orientation = Eigen::Quaterniond::Identity();
  /// Geodesic angle between the simulated and the intended final root orientation (rad).
  double final_orientation_error_rad = 0.0;
  /// RMS over the flight of the angle between the simulated and the designed orientation (rad).
  double rms_orientation_error_rad = 0.0;
  /// Somersault turns (rotation of the trunk's long axis about W's y axis, unwrapped) and
  /// the same for the designed motion.
  double somersault_turns = 0.0;
  double intended_somersault_turns = 0.0;
  /// Twist turns (the twist angle of R_WB = R_y(somersault) R_x(tilt) R_z(twist), unwrapped) of
  /// the simulated and the designed motion.
  double twist_turns = 0.0;
  double intended_twist_turns = 0.0;
  /// Where the simulated flight departs from the design, in plain words (empty when it follows
  /// it): see SkillSimulationWarnings.
  std::vector<std::string> warnings;
};

/// The warnings SimulateSkill attaches: the simulated landing or the flight's RMS orientation more
/// than 15° from the design's, the somersaults short or long by more than 15°, a twist the other
/// way or short or long by more than a quarter turn — each with its numbers and, for the rotations,
/// what in the keyframes usually causes it.
std::vector<std::string> SkillSimulationWarnings(const SkillSimulationResult& sim);

SkillSimulationResult SimulateSkill(const SkillDesign& design,
                                    const SkillTrajectory& trajectory,
                                    double step_s = 1e-3,
                                    bool fit_momentum = true);

}  // namespace acro::analysis
