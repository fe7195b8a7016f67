#pragma once

// A skill file (YAML, docs/formats/skill.md): the athlete, the take-off, and the keyframe poses of
// a skill in order, with Model (1)'s tolerances. Joint angles refer to the standard human's
// joints (standard_human.h), named by their child segment; the root orientation is given as
// somersault, tilt and twist angles, R_WB = R_y(somersault) R_x(tilt) R_z(twist) (the convention
// of PoseAthleteBody).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/athlete/athlete_profile.h"

namespace acro::analysis {

struct SkillKeyframe {
  std::string name;
  double somersault_rad = 0.0;
  double tilt_rad = 0.0;
  double twist_rad = 0.0;
  /// All joint angles of the standard human in model order (num_joint_dofs entries; unnamed ones
  /// are zero, the reference pose).
  Eigen::VectorXd joint_angles_rad;
  /// A guess of the keyframe's time (s), when the file gives one.
  std::optional<double> time_s;
  /// Model (1)'s tolerances: e₁ on the root position (m), e₂ on every angle (rad).
  double tolerance_position_m = 0.05;
  double tolerance_angle_rad = 0.0872664625997164788;  // 5°
  int line = 0;                                        ///< line of the keyframe in its file
};

struct Skill {
  std::string name;
  std::string fig_code;  ///< e.g. "42/" (may be empty)
  std::string source;    ///< the file it was read from
  std::filesystem::path athlete_path;
  AthleteProfile athlete;
  /// Take-off velocity of the whole-body centre of mass in W (m/s, Z up).
  Eigen::Vector3d takeoff_com_velocity_mps = Eigen::Vector3d::Zero();
  /// Flight time T = 2 v_z / g (s).
  double flight_time_s = 0.0;
  /// |g| (m/s²): the standard human model's gravity.
  double gravity_mps2 = 9.81;
  std::vector<SkillKeyframe> keyframes;
};

/// The number of joint angles of the standard human (32).
int StandardJointDofCount();

/// The index among the joint angles (q[7 + index]) of `segment`'s axis `axis` (0-based in its
/// sequence), or −1 when the segment has no such axis.
int StandardJointDofIndex(std::string_view segment, int axis);

/// R_WB of a keyframe: R_y(somersault) R_x(tilt) R_z(twist).
Eigen::Quaterniond KeyframeOrientation(const SkillKeyframe& keyframe);

/// Reads a skill and its athlete profile (a relative athlete path is taken from the skill's
/// folder). Throws acro::InputError naming the file, the line and the key at fault.
Skill ReadSkill(const std::filesystem::path& path);

/// The same from parsed YAML; `base_dir` resolves the athlete path.
Skill SkillFromYaml(const YamlNode& root, const std::filesystem::path& base_dir);

/// The skill as a skill file's text for a file in `dir` (the athlete's path relative to `dir`
/// when it is at most two folders up): every keyframe with its orientation, its time guess and
/// tolerances, and each joint that is not at the reference pose by its sided name (r_thigh,
/// l_thigh), in degrees to 12 significant digits, so that ReadSkill gives back the same skill
/// within 1e-12 of every number. What the studio's designer saves after editing keyframes.
std::string FormatSkillYaml(const Skill& skill, const std::filesystem::path& dir);

/// Writes FormatSkillYaml to `path` atomically. Throws acro::InputError naming `path` when it
/// cannot be written.
void WriteSkill(const std::filesystem::path& path, const Skill& skill);

}  // namespace acro::analysis
