#pragma once

// The athlete's body as the project's standard 15-segment human in the reference pose (standing,
// arms by the sides): per segment the proximal joint centre, the distal end and the mass
// properties, all in the body frame H (origin on the midline at hip-joint level, x anterior, y to
// the athlete's left, z up; docs/athlete-model.md). Built either from Yeadon's geometric model
// (measurements) or from de Leva's regression (height, mass, sex; de_leva.h), and posable for
// whole-body inertia in tucked, piked or any other shape.

#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/inertial_properties.h"
#include "acro/athlete/yeadon_human.h"

namespace acro::analysis {

/// Segment names and order of the standard human: the one list of them (MakeStandardHumanModel).
inline constexpr std::array<std::string_view, 15> kStandardSegmentNames = {"pelvis",
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

/// Parent of each standard segment (index into kStandardSegmentNames, −1 for the pelvis).
inline constexpr std::array<int, 15> kStandardSegmentParents = {
    -1, 0, 1, 1, 3, 4, 1, 6, 7, 0, 9, 10, 0, 12, 13};

struct BodySegment {
  std::string name;
  int parent = -1;
  /// Proximal joint centre (the pelvis: H's origin), in H.
  Eigen::Vector3d p_HoJ_H = Eigen::Vector3d::Zero();
  /// Distal end in H: the child's joint centre, or the tip (head vertex, hand or foot end).
  Eigen::Vector3d p_HoE_H = Eigen::Vector3d::Zero();
  /// Orientation relative to the reference pose (identity there; set by PoseAthleteBody).
  Eigen::Matrix3d R_pose = Eigen::Matrix3d::Identity();
  InertialProperties in_H;
};

struct AthleteBody {
  /// "Yeadon 1990 (dempster densities)", "de Leva 1996 (female)".
  std::string model;
  double height_m = 0.0;
  /// Segments in kStandardSegmentNames order.
  std::vector<BodySegment> segments;
  /// Whole body, inertia about its centre of mass.
  InertialProperties total;

  /// Index of a segment by name, or −1.
  int Find(std::string_view name) const;
};

/// The standard segment (index into kStandardSegmentNames) a Yeadon solid ("j5") belongs to, or −1.
int StandardSegmentOfYeadonSolid(std::string_view solid_label);

/// Groups a Yeadon human's 40 solids into the 15 standard segments (pelvis = s0–s1, thorax =
/// s2–s4 up to the acromion, head = s5–s7, hand = a4–a6, foot = j5–j8, …). The human should be in
/// the zero configuration for the result to be a reference pose.
AthleteBody MakeAthleteBodyFromYeadon(const YeadonHuman& human);

/// A shape of the body: named angles in radians (see kBodyPoseAngleNames). Unset angles are zero.
struct BodyPose {
  std::map<std::string, double> angles_rad;
};

/// Pose angle names. Without a side prefix an angle applies to both sides; "l_"/"r_" prefixed
/// ones ("l_hip_flexion") to one side and take precedence. Signs: flexion brings the limb forward
/// (the knee: the heel backward), abduction moves it away from the midline; somersault is a
/// forward rotation about the lateral axis, tilt about the antero-posterior and twist about the
/// longitudinal axis (whole body, R = R_y(somersault) R_x(tilt) R_z(twist)).
inline constexpr std::array<std::string_view, 11> kBodyPoseAngleNames = {"somersault",
                                                                         "tilt",
                                                                         "twist",
                                                                         "trunk_flexion",
                                                                         "neck_flexion",
                                                                         "shoulder_flexion",
                                                                         "shoulder_abduction",
                                                                         "elbow_flexion",
                                                                         "hip_flexion",
                                                                         "hip_abduction",
                                                                         "knee_flexion"};

/// True when `name` is a pose angle (with or without an "l_"/"r_" prefix where sided).
bool IsBodyPoseAngle(std::string_view name);

/// The named shapes a coach uses: "straight" (all zero), "pike" (hips flexed 130°, arms forward
/// 80° towards the shins), "tuck" (hips 140°, knees 145°, upper arms down and elbows flexed 100°
/// so that the hands reach the shins). False for another name.
bool MakeNamedPose(std::string_view name, BodyPose* pose);

/// Rotates each segment about its proximal joint (children follow their parents). Throws
/// acro::InputError for an unknown angle name (the `where` of the message is "pose").
AthleteBody PoseAthleteBody(const AthleteBody& body, const BodyPose& pose);

/// Whole-body inertia about the somersault axis: the lateral (H's y) axis through the centre of
/// mass, kg·m².
double SomersaultInertia(const AthleteBody& body);

/// Somersault-axis inertia (lateral axis through the centre of mass, kg·m²) of the three shapes a
/// coach names, and of the pose being reported.
struct ShapeInertias {
  double straight_kgm2 = 0.0;
  double pike_kgm2 = 0.0;
  double tuck_kgm2 = 0.0;
  double pose_kgm2 = 0.0;
};

/// `rest` is the reference-pose body, `posed` the reported one.
ShapeInertias CalcShapeInertias(const AthleteBody& rest, const AthleteBody& posed);

/// Parses "tuck", "pike", "straight", "NAME=DEG" entries separated by commas, in order (later
/// entries override earlier ones): "tuck,knee_flexion=120". Angles in degrees. Throws
/// acro::InputError (where "--pose") naming the entry at fault.
BodyPose ParseBodyPose(std::string_view spec);

}  // namespace acro::analysis
