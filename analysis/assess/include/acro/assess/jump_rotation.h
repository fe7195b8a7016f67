#pragma once

// Somersault, twist and shape of one flight from the root orientation and the hip and knee angles:
// what the FIG numeric code counts.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/fig/skill.h"

namespace acro::analysis {

/// Somersault, tilt and twist angles of a body relative to a somersault frame S whose y axis is the
/// horizontal somersault axis and z is up (Yeadon 1990, J. Biomech. 23(1):59–66: orientation as
/// somersault about a fixed lateral axis, then tilt, then twist about the body's long axis):
/// R_SB = R_y(somersault) · R_x(tilt) · R_z(twist), unwrapped over time. Body axes as in the
/// standard human's reference pose: x forward, y left, z up the trunk. Positive somersault is
/// forward (the head moves to the front).
struct RotationAngles {
  Eigen::VectorXd somersault_rad;
  Eigen::VectorXd tilt_rad;
  Eigen::VectorXd twist_rad;
};

/// Angles for the orientations R_WB (one per frame) about the somersault axis `lateral_W`
/// (projected onto the horizontal plane).
RotationAngles CalcRotationAngles(const std::vector<Eigen::Quaterniond>& q_WB,
                                  const Eigen::Vector3d& lateral_W);

struct JumpRotationOptions {
  /// A body whose long axis leans less than this from vertical is upright (feet or seat).
  double upright_max_lean_deg = 55.0;
  /// Somersault done on the bed (take-off plus landing) between upright positions, in quarters: the
  /// in-air rotation of a feet-to-feet skill falls short of the nominal by about this (a double
  /// shows ~1¾ turns in the air, a single ¾–⅞; DESIGN.md, "Trampoline facts").
  double bed_rotation_quarters = 1.0;
  /// Shape by the FIG Code of Points (trampoline, body positions), held, not at one instant: the
  /// hips are closed when the angle between trunk and thighs (180° − the anatomical hip flexion) is
  /// at or below this, the knees when the angle between thigh and shank (180° − knee flexion) is.
  /// Tuck: both closed; pike: the hips closed, the knees straight; straight: the hips open.
  double closed_angle_deg = 135.0;
  /// A tuck or pike counts when the hips stay closed without a break over at least this fraction
  /// of the flight (between the opening of the take-off and the kick-out); within that hold, tuck
  /// when the knees are closed over at least half of it.
  double min_shape_hold_fraction = 0.15;
  /// The hip and knee angles are median-filtered over this many frames first (odd; 1: none), so
  /// that keypoint noise and one frame of left/right swap do not break or fake a hold.
  int shape_median_frames = 5;
  /// A held median this close to the 135° line makes the shape a close call (the measurement's
  /// angle uncertainty for motion capture: docs/scoring.md): said, with the other reading.
  double shape_uncertainty_deg = 5.0;

  bool IsValid(std::string* why) const;
};

/// What one flight's rotation amounts to.
struct JumpRotation {
  fig::FigSkill skill;  ///< quarters, half twists per somersault, shape, direction
  double measured_somersault_rad =
      0;                          ///< in the air, take-off to landing (signed, forward positive)
  double measured_twist_rad = 0;  ///< in the air (signed)
  fig::BodyPosition takeoff_position = fig::BodyPosition::kFeet;
  fig::BodyPosition landing_position = fig::BodyPosition::kFeet;
  double max_hip_flexion_deg = 0;  ///< anatomical, mean of both sides, at the most flexed instant
  double knee_flexion_at_max_hip_deg = 0;
  /// Why the shape: the fraction of the flight the hips were held closed (the longest hold; 0 when
  /// never), the median trunk–thigh and thigh–shank angles over it (deg), and the fraction of it
  /// with the knees closed.
  double shape_hold_fraction = 0;
  double shape_hip_angle_deg = 180;
  double shape_knee_angle_deg = 180;
  double shape_knees_closed_fraction = 0;
  /// The same in words: "tuck: trunk–thigh 62°, thigh–shank 55° (medians) held over 48 % of the
  /// flight (FIG: both at or below 135°)".
  std::string shape_reason;
  /// The other reading of a close call ("pike" for a tuck whose knees' median lies within the
  /// uncertainty of 135°, "tuck" for such a pike, "straight" for a tuck or pike whose hips' does);
  /// empty when the shape is clear.
  std::string shape_alternative;
};

/// Counts the rotation of a flight between `takeoff_frame` and `landing_frame` (inclusive). The
/// somersault axis is the normal of the plane the root's long axis sweeps (twist does not move it),
/// made horizontal; for jumps, the root's lateral axis at take-off. The nominal quarter
/// count is resolved against the take-off and landing positions: the nearest count congruent to the
/// position change (mod 4) to the in-air rotation plus the rotation done on the bed. Twists are
/// assigned to somersaults by the nominal somersault angle (half the bed rotation before take-off);
/// the twist of a last, incomplete somersault belongs to it. `hip_flexion_rad` and
/// `knee_flexion_rad` are anatomical flexion (positive when flexed) per frame, either may be empty
/// (shape then straight).
JumpRotation CountJumpRotation(const std::vector<Eigen::Quaterniond>& q_WB,
                               int takeoff_frame,
                               int landing_frame,
                               const Eigen::VectorXd& hip_flexion_rad,
                               const Eigen::VectorXd& knee_flexion_rad,
                               const JumpRotationOptions& options = {});

fig::TwistDirection TwistDirectionOf(const JumpRotation& rotation);
/// The same for a flight of `half_twists` counted half twists that twisted `twist_rad` (signed,
/// about the body's long axis): a designed one.
fig::TwistDirection TwistDirectionOf(int half_twists, double twist_rad);

/// "left", "right" or "none".
const char* TwistDirectionName(fig::TwistDirection direction);

}  // namespace acro::analysis
