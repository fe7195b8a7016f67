#pragma once

// A skill made ready for design (DESIGN.md, "Keyframe timing and trajectory optimisation";
// docs/skill-design.md): the athlete's standard human and the keyframes, and the two forms a
// designed motion takes between them —
//   the keyframe form: natural C² cubic splines for the joint angles (keyframe_spline.h) and the
//     cumulative C² quaternion spline for the root orientation (quaternion_spline.h), through the
//     keyframes at given times (Model 2 moves the times);
//   the local form: quintic Hermite pieces through knots that carry values, rates and
//     accelerations (Model 1 moves the times and the knot data).
// In both, the root translation is not interpolated: at every instant it is the one that puts the
// whole-body centre of mass on the ballistic parabola of the take-off velocity, so the three force
// components of the root residual vanish identically and what is left is the moment residual
// about the COM, n_Scm = L̇_Scm / (m g h), the integrand of the objective J.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/athlete/motion.h"
#include "acro/design/skill_file.h"
#include "acro/dynamics/model.h"

namespace acro::analysis {

/// Which optimisation a design goes through (DESIGN.md): Model 2 moves the keyframe times only;
/// Model 1 moves the times and the trajectory within the keyframe tolerances (after Model 2).
enum class SkillModel { kTrajectory = 1, kTiming = 2 };

/// 1 or 2, as the paper and the command line number the models.
inline int SkillModelNumber(SkillModel model) {
  return static_cast<int>(model);
}

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
/// Builds the motion's splines (or reads its knots) for this one call: to sample many times, use
/// CalcSkillMotionProfile.
SkillMotionState CalcSkillMotion(const SkillDesign& design,
                                 const SkillTrajectory& trajectory,
                                 double t_s,
                                 const Eigen::Vector3d& com_start_W = Eigen::Vector3d(0, 0, 1));

/// The designed motion sampled evenly over [0, T] at about `rate_hz` (the last sample at T), as the
/// motion of the design's standard human: for drawing it (filmstrips, ghosts).
Motion SampleSkillMotion(const SkillDesign& design,
                         const SkillTrajectory& trajectory,
                         double rate_hz = 100.0);

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

}  // namespace acro::analysis
