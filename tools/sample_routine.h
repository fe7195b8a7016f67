#pragma once

// The sample trampoline routine (samples/trials/trampoline_routine/): a routine of six skills
// made by the project's own tools for one athlete. Flights are simulated by the dynamics engine
// (dynamics::SimulateFlight: prescribed joint angles, free root under gravity, so the COM follows
// the ballistic parabola and the angular momentum about it is conserved); the take-off angular
// momentum of each skill is found by shooting so that it lands with its nominal rotation. Contacts
// are on a spring-damper bed: m z̈ = −m g + max(0, k d + c ḋ), d the bed depression under the
// feet, with orientation and joint angles blended (cubic Hermite) from the landing state to the
// next take-off state and a knee-and-hip "push" that gives the athlete the energy of the next
// flight. Markers of the "trampoline" marker set by forward kinematics, 1 mm Gaussian noise (a
// fixed seed and our own Box–Muller, so the file is the same on every run) and a few gaps; four
// static markers at the corners of the woven bed.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/trial.h"
#include "acro/dynamics/model.h"

namespace acro::samples {

struct SampleRoutineOptions {
  double point_rate_hz = 120.0;
  /// Integration steps per frame, for flights (RK4) and contacts.
  int substeps_per_frame = 20;
  /// Bed: effective vertical stiffness and damping of the woven bed and its springs at the centre.
  double bed_stiffness_N_per_m = 6500.0;
  double bed_damping_N_s_per_m = 25.0;
  /// The bed's centre cross at rest (Z up, the bed's long axis along X).
  Eigen::Vector3d bed_centre_m = Eigen::Vector3d(0.4, -0.2, 1.155);
  double bed_length_m = 4.28;
  double bed_width_m = 2.14;
  double noise_sd_m = 0.001;
  unsigned noise_seed = 20261122;
  /// Variations of the routine (a season of them, tests/library): every flight time scaled (a
  /// higher or lower routine; 0.9–1.1 keeps every skill within reach), every landing target moved
  /// on the bed (m, along and across it), and only the first `num_skills` skills (1–6).
  double flight_time_scale = 1.0;
  Eigen::Vector2d landing_offset_m = Eigen::Vector2d::Zero();
  int num_skills = 6;
};

/// One flight (one skill) as simulated: times are exact (sub-frame).
struct SampleFlightTruth {
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
struct SampleContactTruth {
  double start_s = 0.0;
  double end_s = 0.0;
  double peak_force_body_weights = 0.0;
  double max_depression_m = 0.0;
};

struct SampleRoutine {
  dynamics::Model<double> model;
  double mass_kg = 0.0;
  double gravity_m_per_s2 = 9.81;
  SampleRoutineOptions options;
  std::string athlete_file;
  capture::Trial trial;
  std::vector<SampleFlightTruth> flights;
  std::vector<SampleContactTruth> contacts;
  /// Noise-free generalised coordinates and velocities per frame (columns), as the markers were
  /// placed from them.
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

  /// truth.json: the flights, contacts, bed and athlete.
  std::string TruthJson() const;
};

/// Simulates the routine for the athlete profile at `athlete_path` (docs/formats/athlete.md).
/// `athlete_label` is the path written into truth.json. Throws acro::InputError for a bad profile.
SampleRoutine MakeSampleRoutine(const std::filesystem::path& athlete_path,
                                const std::string& athlete_label,
                                const SampleRoutineOptions& options = {});

/// Physics of one flight on the noise-free frames strictly between take-off and landing.
struct SampleFlightPhysics {
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

SampleFlightPhysics CheckSampleFlight(const SampleRoutine& routine, int flight);

}  // namespace acro::samples
