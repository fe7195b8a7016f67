#pragma once

// The project's standard 15-segment human: pelvis (root, free joint), thorax-abdomen, head-neck,
// upper arms, forearms, hands, thighs, shanks, feet; 32 joint angles + 6 root = 38 DoF. A fixture
// for tests and benchmarks and a default athlete; personalised bodies come from anthropometry in
// analysis/. Segment parameters default to de Leva 1996 (Table 4, male) fractions of stature and
// body mass, with the upper and middle trunk merged by the parallel-axis theorem.
//
// Frames: in the reference pose (all angles zero, identity root) the athlete stands upright with
// the arms by the sides; every segment frame is parallel to W: x anterior, y to the athlete's left,
// z up. Each segment's origin is its proximal joint centre (the pelvis': the hip-joint midpoint).

#include <array>
#include <string>

#include "acro/dynamics/model.h"

namespace acro::dynamics {

/// One segment's parameters as fractions (de Leva 1996 style).
struct HumanSegmentParameters {
  double mass_fraction = 0.0;    ///< of body mass
  double length_fraction = 0.0;  ///< proximal joint to distal end (or next joint), of stature
  double com_fraction = 0.0;     ///< centre of mass along the segment's long axis, of its length
  /// Radii of gyration about the centre of mass along the segment's x, y, z axes, of its length.
  Eigen::Vector3d gyration_fraction = Eigen::Vector3d::Zero();
};

/// Segment order of the reference human (also the model's segment order).
inline constexpr std::array<const char*, 15> kReferenceHumanSegments = {"pelvis",
                                                                        "thorax",
                                                                        "head",
                                                                        "r_upper_arm",
                                                                        "r_forearm",
                                                                        "r_hand",
                                                                        "l_upper_arm",
                                                                        "l_forearm",
                                                                        "l_hand",
                                                                        "r_thigh",
                                                                        "r_shank",
                                                                        "r_foot",
                                                                        "l_thigh",
                                                                        "l_shank",
                                                                        "l_foot"};

struct ReferenceHumanParameters {
  double height_m = 1.75;
  double mass_kg = 70.0;
  /// Per segment, in kReferenceHumanSegments order; left and right share the values of a side.
  std::array<HumanSegmentParameters, 15> segments = DeLevaMale();
  /// Gravity in W.
  Eigen::Vector3d gravity_W = Eigen::Vector3d(0.0, 0.0, -9.81);

  /// de Leva 1996 (male, Table 4) fractions.
  static std::array<HumanSegmentParameters, 15> DeLevaMale();
  /// True when height and mass are positive, mass fractions positive summing to 1 (to 1e-9) and
  /// every length, centre-of-mass and gyration fraction positive; else the reason in *why.
  bool IsValid(std::string* why) const;
};

/// Builds the reference human. Throws acro::InputError naming the parameter at fault when
/// `params` is not valid. Joint axis sequences (anatomical: y flexion/extension, x ab/adduction,
/// z axial rotation): lumbar, neck, shoulders, hips "yxz"; elbows "yz" (flexion, pronation);
/// wrists "yx"; knees "y"; ankles "yx". Named points: every joint centre ("r_knee_jc", …) and the
/// landmarks "head_vertex", "c7", "r_asis", "l_asis", "r_fingertip", "l_fingertip", "r_heel",
/// "l_heel", "r_toe", "l_toe".
Model<double> MakeReferenceHuman(const ReferenceHumanParameters& params = {});

}  // namespace acro::dynamics
