#pragma once

// A trampoline routine simulated from its skills (docs/skill-design.md, "Routines"): flights by the
// dynamics engine (dynamics::SimulateFlight: prescribed joint angles, free root under gravity, so
// the COM follows the ballistic parabola and the angular momentum about it is conserved), the
// take-off angular momentum of each skill found by shooting so that it lands with its nominal
// rotation, and contacts on a spring-damper bed: m z̈ = −m g + max(0, k d + c ḋ), d the bed's
// depression under the feet, with orientation and joint angles blended (cubic Hermite) from the
// landing state to the next take-off state and a knee-and-hip "push" that gives the athlete the
// energy of the next flight. What the sample routine (tools/sample_routine.h) and `acrolab routine`
// are made of.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/athlete_profile.h"
#include "acro/design/posture_track.h"
#include "acro/dynamics/model.h"
#include "acro/fig/trampoline.h"

namespace acro::analysis {

/// One skill of a routine, as designed: its flight, its rotation and the joints' schedule.
struct RoutineSkillPlan {
  std::string name;
  std::string fig_code;
  double flight_s = 1.4;         ///< design flight time: take-off vertical velocity g·T/2
  int direction = 0;             ///< +1 forward, −1 backward, 0 none
  double nominal_rad = 0;        ///< nominal somersault (magnitude)
  int twist_halves = 0;          ///< nominal twist in half turns, signed (its direction)
  double takeoff_lean_rad = 0;   ///< somersault already done on the bed at take-off
  double landing_short_rad = 0;  ///< somersault still to do on the bed after landing
  Eigen::Vector2d landing_target_m = Eigen::Vector2d::Zero();  ///< feet at landing, from the centre
  PostureTrack track;  ///< the joints over the flight, t = 0 at take-off
  /// A first guess of the take-off momentum's somersault component (along the heading's lateral
  /// axis) and twist component (along the body's long axis), kg·m²/s; none: from a mean inertia.
  std::optional<Eigen::Vector2d> momentum_guess;
};

struct RoutineSimulationOptions {
  double point_rate_hz = 120.0;
  /// Integration steps per frame, for flights (RK4) and contacts.
  int substeps_per_frame = 20;
  /// Bed: effective vertical stiffness and damping of the woven bed and its springs at the centre.
  double bed_stiffness_N_per_m = 6500.0;
  double bed_damping_N_s_per_m = 25.0;
  /// The bed's centre cross at rest (Z up, the bed's long axis along X).
  Eigen::Vector3d bed_centre_m = Eigen::Vector3d(0.4, -0.2, 1.155);
  double bed_length_m = fig::kBedLength_m;
  double bed_width_m = fig::kBedWidth_m;
  /// How a contact takes energy (a lower flight after a higher one): the athlete bends late in
  /// the contact, against the bed's largest force (true, docs/skill-design.md "Routines"), or the
  /// push's squat is reversed (false: knees and hips extended past straight by the push — the
  /// sample routine's first version, kept so that its committed files stay as they are; its
  /// largest such push is 1.8°).
  bool absorb_by_late_squat = true;
};

/// One flight (one skill) as simulated: times are exact (sub-frame).
struct RoutineFlightTruth {
  std::string name;
  std::string fig_code;
  double takeoff_s = 0.0;  ///< the bed force falls to zero: the feet leave the bed
  double landing_s = 0.0;  ///< the feet reach the bed's rest level
  double takeoff_vertical_velocity_m_per_s = 0.0;
  double apex_com_z_m = 0.0;
  Eigen::Vector3d takeoff_com_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d landing_com_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d landing_feet_m = Eigen::Vector3d::Zero();  ///< midpoint of the soles
  /// Rotation in the air (take-off to landing), signed (forward positive), and twist.
  double air_somersault_rad = 0.0;
  double air_twist_rad = 0.0;
  double takeoff_lean_rad = 0.0;  ///< signed somersault angle of the pelvis at take-off
  /// Angular momentum about the COM at take-off, in W (N·m·s).
  Eigen::Vector3d H_Scm_W = Eigen::Vector3d::Zero();
};

/// One contact with the bed (the first starts at the bottom of a bounce, the last ends at the
/// bottom after the last landing).
struct RoutineContactTruth {
  double start_s = 0.0;
  double end_s = 0.0;
  double peak_force_body_weights = 0.0;
  double max_depression_m = 0.0;
  /// The push the athlete gives (rad of hip flexion of the squat; 0 for the first and last
  /// contacts) and how far the solved take-off missed its vertical velocity (m/s).
  double push_rad = 0.0;
  double takeoff_velocity_error_m_per_s = 0.0;
};

struct SimulatedRoutine {
  dynamics::Model<double> model;
  double mass_kg = 0.0;
  double gravity_m_per_s2 = 9.81;
  RoutineSimulationOptions options;
  std::vector<RoutineFlightTruth> flights;
  std::vector<RoutineContactTruth> contacts;
  /// Noise-free generalised coordinates and velocities per frame (columns).
  Eigen::MatrixXd q;
  Eigen::MatrixXd v;
  /// Largest mismatch of the COM position (m) and velocity (m/s), the orientation (rad), the root
  /// angular velocity (rad/s) and the joint angles (rad) between the end of one phase and the start
  /// of the next (C¹ continuity), over all take-offs and landings.
  double max_boundary_position_jump_m = 0.0;
  double max_boundary_velocity_jump_m_per_s = 0.0;
  double max_boundary_orientation_jump_rad = 0.0;
  double max_boundary_angular_velocity_jump_rad_per_s = 0.0;
  double max_boundary_joint_jump_rad = 0.0;
  double max_boundary_joint_rate_jump_rad_per_s = 0.0;

  int num_frames() const { return static_cast<int>(q.cols()); }
};

/// Simulates the routine of `plans` (at least one) for the athlete: the first contact from the
/// bottom of a bounce, standing, then per skill the flight and the contact after it, the last to
/// the bottom, standing. Every skill turns the heading by its half twists.
SimulatedRoutine SimulateRoutine(const AthleteProfile& athlete,
                                 const std::vector<RoutineSkillPlan>& plans,
                                 const RoutineSimulationOptions& options = {});

/// Physics of one flight on the noise-free frames strictly between take-off and landing.
struct RoutineFlightPhysics {
  int num_frames = 0;
  /// max |H(t) − H(t₀)| / |H(t₀)| of the angular momentum about the COM (for a flight with no
  /// rotation, |H| < 1 N·m·s, divided by 1 N·m·s instead).
  double max_relative_momentum_drift = 0.0;
  double momentum_norm_N_m_s = 0.0;
  /// The vertical COM acceleration of a least-squares parabola through the COM heights, and the
  /// largest |z(t) − parabola|.
  double fitted_vertical_acceleration_m_per_s2 = 0.0;
  double parabola_max_error_m = 0.0;
  /// max |horizontal COM velocity change| over the flight (m/s).
  double max_horizontal_velocity_change_m_per_s = 0.0;
};

/// The frames of `q`, `v` (columns, at `rate_hz` from t = 0) within `flight`.
RoutineFlightPhysics CheckRoutineFlight(const dynamics::Model<double>& model,
                                        const Eigen::MatrixXd& q,
                                        const Eigen::MatrixXd& v,
                                        double rate_hz,
                                        const RoutineFlightTruth& flight);

}  // namespace acro::analysis
