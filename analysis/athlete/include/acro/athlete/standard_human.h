#pragma once

// The project's standard human as a dynamics model: the 15 segments of an AthleteBody (Yeadon or
// de Leva route) joined by Euler-angle joints chosen for acrobatics, with named joint centres and
// landmarks. The pelvis is the root (free joint: position + unit quaternion, no Euler angles, so
// any number of somersaults and twists is singularity-free).
//
// Axis sequences (intrinsic; x anterior, y left, z along the segment in the reference pose) and
// where each keeps its gimbal lock — a 3-axis sequence locks when its middle angle reaches ±90°:
//   thorax (lumbar) "yxz", head (neck) "yxz": flexion, lateral bending (middle, ±40° range), axial
//     rotation — lock at ±90° of lateral bending, beyond any spine.
//   upper arms (shoulders) "yzx": flexion, axial rotation (middle), abduction — flexion (up to
//     180°, arms overhead) and abduction (up to 180°) both exceed 90° in acrobatics, so neither
//     may be the middle angle; humeral axial rotation stays within about ±70° in flight shapes, so
//     the lock at ±90° sits at the end of the anatomical range, not inside it.
//   thighs (hips) "yzx": flexion (up to 150° in a tuck or pike), axial rotation (middle, ±45°),
//     abduction (straddles reach 90°) — lock at ±90° of hip rotation, outside its range.
//   forearms (elbows) "yz": flexion, pronation; hands (wrists) "yx": flexion, deviation; feet
//     (ankles) "yx": plantar/dorsiflexion, inversion; shanks (knees) "y" — two perpendicular axes
//     or one: no lock.
// A zero angle is the reference pose (standing, arms by the sides); positive flexion about y of a
// limb hanging down moves it backwards, so anatomical flexion of the hip, shoulder and elbow is a
// negative first angle, and of the knee a positive one (the same convention as PoseAthleteBody).

#include <array>
#include <string_view>

#include "acro/athlete/athlete_body.h"
#include "acro/dynamics/model.h"

namespace acro::analysis {

struct StandardJoint {
  std::string_view segment;        ///< the child segment
  std::string_view axis_sequence;  ///< "" for the root
  std::string_view joint_centre;   ///< named point at the joint centre ("" for the root)
};

/// In kStandardSegmentNames order; the segment names are that one list's.
inline constexpr std::array<StandardJoint, 15> kStandardJoints = {{
    {kStandardSegmentNames[0], "", ""},
    {kStandardSegmentNames[1], "yxz", "lumbar_jc"},
    {kStandardSegmentNames[2], "yxz", "neck_jc"},
    {kStandardSegmentNames[3], "yzx", "r_shoulder_jc"},
    {kStandardSegmentNames[4], "yz", "r_elbow_jc"},
    {kStandardSegmentNames[5], "yx", "r_wrist_jc"},
    {kStandardSegmentNames[6], "yzx", "l_shoulder_jc"},
    {kStandardSegmentNames[7], "yz", "l_elbow_jc"},
    {kStandardSegmentNames[8], "yx", "l_wrist_jc"},
    {kStandardSegmentNames[9], "yzx", "r_hip_jc"},
    {kStandardSegmentNames[10], "y", "r_knee_jc"},
    {kStandardSegmentNames[11], "yx", "r_ankle_jc"},
    {kStandardSegmentNames[12], "yzx", "l_hip_jc"},
    {kStandardSegmentNames[13], "y", "l_knee_jc"},
    {kStandardSegmentNames[14], "yx", "l_ankle_jc"},
}};

/// Builds the model from a body in its reference pose: each segment's frame is parallel to H with
/// its origin at the proximal joint centre (the pelvis: the hip-joint midpoint). Named points: the
/// joint centres of kStandardJoints, "midhip" (pelvis origin), "head_vertex", "r_hand_end" /
/// "l_hand_end" (third metacarpal head for de Leva, fingernails for Yeadon), "r_toe" / "l_toe"
/// (toe tip), and each segment's centre of mass "<segment>_com". Throws acro::InputError when a
/// segment's mass properties are not physical.
dynamics::Model<double> MakeStandardHumanModel(const AthleteBody& body);

}  // namespace acro::analysis
