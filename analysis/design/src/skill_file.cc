#include "acro/design/skill_file.h"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <utility>

#include <yaml-cpp/yaml.h>

#include "acro/athlete/standard_human.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/text_format.h"

namespace acro::analysis {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Segments that exist on both sides: an unsided key ("thigh") sets both, mirrored.
constexpr std::string_view kSidedSegments[] = {
    "upper_arm", "forearm", "hand", "thigh", "shank", "foot"};

// Writes a joint's angles (degrees) for `segment`; `mirror` negates the angles about x and z
// (the mirror image in the sagittal plane keeps rotations about y and reverses the others).
void SetJoint(const YamlNode& node, std::string_view segment, bool mirror, Eigen::VectorXd& q) {
  const std::vector<double> deg = node.AsDoubleList();
  int count = 0;
  for (const StandardJoint& j : kStandardJoints) {
    if (j.segment != segment) continue;
    if (deg.size() > j.axis_sequence.size())
      node.Fail("joint " + std::string(segment) + " has " + std::to_string(j.axis_sequence.size()) +
                " axes (" + std::string(j.axis_sequence) + "), got " + std::to_string(deg.size()) +
                " angles");
    for (size_t k = 0; k < deg.size(); ++k) {
      if (!std::isfinite(deg[k])) node.Fail("angle is not finite");
      // A joint turns less than a turn from the reference pose (the widest human ranges are
      // about 180°); beyond ±360° the number is a mistake, never a pose.
      if (std::abs(deg[k]) > 360.0)
        node.Fail("joint " + std::string(segment) + ": " + FormatFixed(deg[k], 1) +
                  "° is outside ±360°");
      const bool flip = mirror && j.axis_sequence[k] != 'y';
      q[StandardJointDofIndex(segment, static_cast<int>(k))] =
          (flip ? -deg[k] : deg[k]) * kDegToRad;
    }
    ++count;
  }
  if (count == 0) node.Fail("unknown joint (a standard segment name such as r_thigh or thigh)");
}

// Limits of a skill file (docs/limits.md): an aerial skill's flight time (a 4 s flight rises
// 19.6 m; the longest trampoline flights are about 2.2 s), keyframes (a skill has 5–15; the timing
// problem grows with their cube), root angles (ten turns), tolerances.
constexpr double kMinFlightTimeS = 0.2, kMaxFlightTimeS = 4.0;
constexpr double kMaxHorizontalSpeedMps = 10.0;
constexpr std::size_t kMaxKeyframes = 100;
constexpr double kMaxRootAngleDeg = 3600.0;
constexpr double kMaxStepDeg = 170.0;

double AngleDeg(const YamlNode& map, std::string_view key) {
  const YamlNode* n = map.Find(key);
  if (n == nullptr) return 0.0;
  const double v = n->AsDouble();
  if (!std::isfinite(v)) n->Fail("angle is not finite");
  if (std::abs(v) > kMaxRootAngleDeg)
    n->Fail(FormatFixed(v, 1) + "° is outside ±" + FormatFixed(kMaxRootAngleDeg, 0) +
            "° (ten turns)");
  return v * kDegToRad;
}

// The flight time as the reader checks it: finite and within [kMinFlightTimeS, kMaxFlightTimeS].
void CheckFlightTime(const YamlNode& node, const std::string& what, double T) {
  if (!(T >= kMinFlightTimeS && T <= kMaxFlightTimeS))
    node.Fail((what.empty() ? "a flight time of " : what + " gives a flight time of ") +
              FormatFixed(T, 3) + " s, outside " + FormatFixed(kMinFlightTimeS, 1) + "–" +
              FormatFixed(kMaxFlightTimeS, 1) + " s (a 4 s flight rises 19.6 m)");
}

}  // namespace

int StandardJointDofCount() {
  int n = 0;
  for (const StandardJoint& j : kStandardJoints) n += static_cast<int>(j.axis_sequence.size());
  return n;
}

int StandardJointDofIndex(std::string_view segment, int axis) {
  int first = 0;
  for (const StandardJoint& j : kStandardJoints) {
    const int n = static_cast<int>(j.axis_sequence.size());
    if (j.segment == segment) return axis >= 0 && axis < n ? first + axis : -1;
    first += n;
  }
  return -1;
}

Eigen::Quaterniond KeyframeOrientation(const SkillKeyframe& k) {
  return Eigen::AngleAxisd(k.somersault_rad, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(k.tilt_rad, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(k.twist_rad, Eigen::Vector3d::UnitZ());
}

namespace {

// The take-off: the COM velocity, or the flight time (then the take-off is vertical).
void ReadTakeoff(const YamlNode& takeoff, Skill* skill) {
  takeoff.RequireKnownKeys({"com_velocity_mps", "flight_time_s"});
  const YamlNode* vel = takeoff.Find("com_velocity_mps");
  const YamlNode* tof = takeoff.Find("flight_time_s");
  if ((vel == nullptr) == (tof == nullptr))
    takeoff.Fail("give exactly one of com_velocity_mps and flight_time_s");
  if (vel != nullptr) {
    const std::vector<double> v = vel->AsDoubleList();
    if (v.size() != 3) vel->Fail("expected [vx, vy, vz]");
    skill->takeoff_com_velocity_mps = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!skill->takeoff_com_velocity_mps.allFinite() || !(v[2] > 0.0))
      vel->Fail("the vertical take-off velocity must be positive and finite");
    if (std::hypot(v[0], v[1]) > kMaxHorizontalSpeedMps)
      vel->Fail("a horizontal take-off speed of " + FormatFixed(std::hypot(v[0], v[1]), 2) +
                " m/s is above " + FormatFixed(kMaxHorizontalSpeedMps, 0) + " m/s");
    CheckFlightTime(*vel, "the vertical velocity", 2.0 * v[2] / skill->gravity_mps2);
  } else {
    const double T = tof->AsDouble();
    CheckFlightTime(*tof, "", T);
    skill->takeoff_com_velocity_mps = Eigen::Vector3d(0.0, 0.0, 0.5 * skill->gravity_mps2 * T);
  }
  skill->flight_time_s = 2.0 * skill->takeoff_com_velocity_mps.z() / skill->gravity_mps2;
}

struct Tolerances {
  double position_m = 0.05;
  double angle_rad = 5.0 * kDegToRad;
};

bool TolerancesInRange(double position_m, double angle_rad) {
  return position_m >= 0.0 && position_m <= 1.0 && angle_rad >= 0.0 &&
         angle_rad <= std::numbers::pi;
}

// The skill's default tolerances (the file's, or 5 cm and 5°).
Tolerances ReadTolerances(const YamlNode* t) {
  Tolerances out;
  if (t == nullptr) return out;
  t->RequireKnownKeys({"position_m", "angle_deg"});
  if (const YamlNode* n = t->Find("position_m")) out.position_m = n->AsDouble();
  if (const YamlNode* n = t->Find("angle_deg")) out.angle_rad = n->AsDouble() * kDegToRad;
  if (!TolerancesInRange(out.position_m, out.angle_rad)) t->Fail("must be within 0–1 m and 0–180°");
  return out;
}

SkillKeyframe ReadKeyframe(const YamlNode& item, const Tolerances& defaults) {
  if (!item.IsMap()) item.Fail("a keyframe is a map");
  item.RequireKnownKeys({"name",
                         "time_s",
                         "somersault_deg",
                         "tilt_deg",
                         "twist_deg",
                         "joints_deg",
                         "tolerance_position_m",
                         "tolerance_angle_deg"});
  SkillKeyframe k;
  k.line = item.line();
  k.name = item.At("name").AsString();
  k.somersault_rad = AngleDeg(item, "somersault_deg");
  k.tilt_rad = AngleDeg(item, "tilt_deg");
  k.twist_rad = AngleDeg(item, "twist_deg");
  k.joint_angles_rad = Eigen::VectorXd::Zero(StandardJointDofCount());
  if (const YamlNode* joints = item.Find("joints_deg")) {
    if (!joints->IsMap()) joints->Fail("expected a map of joint names to angle lists");
    for (const auto& [key, value] : joints->entries()) {
      bool sided = false;
      for (std::string_view s : kSidedSegments) sided = sided || key == s;
      if (sided) {
        SetJoint(value, "r_" + key, false, k.joint_angles_rad);
        SetJoint(value, "l_" + key, true, k.joint_angles_rad);
      } else {
        SetJoint(value, key, false, k.joint_angles_rad);
      }
    }
  }
  if (const YamlNode* n = item.Find("time_s")) {
    k.time_s = n->AsDouble();
    if (!std::isfinite(*k.time_s)) n->Fail("not finite");
  }
  k.tolerance_position_m = defaults.position_m;
  k.tolerance_angle_rad = defaults.angle_rad;
  if (const YamlNode* n = item.Find("tolerance_position_m")) k.tolerance_position_m = n->AsDouble();
  if (const YamlNode* n = item.Find("tolerance_angle_deg"))
    k.tolerance_angle_rad = n->AsDouble() * kDegToRad;
  if (!TolerancesInRange(k.tolerance_position_m, k.tolerance_angle_rad))
    item.Fail("tolerances must be within 0–1 m and 0–180°");
  return k;
}

// Times, when given, must run from 0 to T in increasing order.
void CheckKeyframeTimes(const Skill& skill) {
  const size_t n = skill.keyframes.size();
  for (size_t i = 0; i < n; ++i) {
    const SkillKeyframe& k = skill.keyframes[i];
    if (!k.time_s) continue;
    const std::string where = "line " + std::to_string(k.line);
    if (i == 0 && std::abs(*k.time_s) > 1e-9)
      throw InputError(skill.source, where, "time_s: the first keyframe is at take-off, 0 s");
    if (i + 1 == n && std::abs(*k.time_s - skill.flight_time_s) > 1e-3)
      throw InputError(
          skill.source,
          where,
          "time_s: the last keyframe is at landing, " + std::to_string(skill.flight_time_s) + " s");
    if (i > 0 && skill.keyframes[i - 1].time_s && !(*k.time_s > *skill.keyframes[i - 1].time_s))
      throw InputError(skill.source, where, "time_s: keyframe times must increase");
    if (*k.time_s < 0.0 || *k.time_s > skill.flight_time_s + 1e-3)  // the landing's tolerance
      throw InputError(skill.source,
                       where,
                       "time_s " + FormatFixed(*k.time_s, 3) + " is outside the flight, 0–" +
                           FormatFixed(skill.flight_time_s, 3) + " s");
  }
}

// Consecutive keyframes less than 170° apart in each root angle as written (so that −40 then
// −250 is not read as the 150° turn the other way) and as orientations (the quaternion
// spline's log branch).
void CheckKeyframeSteps(const Skill& skill) {
  const size_t n = skill.keyframes.size();
  for (size_t i = 1; i < n; ++i) {
    const SkillKeyframe& a = skill.keyframes[i - 1];
    const SkillKeyframe& b = skill.keyframes[i];
    const std::pair<const char*, double> steps[] = {
        {"somersault_deg", b.somersault_rad - a.somersault_rad},
        {"tilt_deg", b.tilt_rad - a.tilt_rad},
        {"twist_deg", b.twist_rad - a.twist_rad}};
    for (const auto& [key, step] : steps)
      if (std::abs(step) > kMaxStepDeg * kDegToRad)
        throw InputError(skill.source,
                         "line " + std::to_string(b.line),
                         std::string(key) + " changes by " + FormatFixed(step / kDegToRad, 1) +
                             "° from the previous keyframe; insert a keyframe (at most " +
                             FormatFixed(kMaxStepDeg, 0) + "° apart)");
  }
  for (size_t i = 1; i < n; ++i) {
    const double angle = KeyframeOrientation(skill.keyframes[i - 1])
                             .angularDistance(KeyframeOrientation(skill.keyframes[i]));
    if (angle > 170.0 * kDegToRad)
      throw InputError(skill.source,
                       "line " + std::to_string(skill.keyframes[i].line),
                       "orientation turns " + FormatFixed(angle / kDegToRad, 1) +
                           "° from the previous keyframe; insert a keyframe (at most 170° apart)");
  }
}

}  // namespace

Skill SkillFromYaml(const YamlNode& root, const std::filesystem::path& base_dir) {
  Skill skill;
  skill.source = root.file();
  if (!root.IsMap()) throw InputError(root.file(), root.Where(), "a skill file is a map");
  root.RequireKnownKeys({"name", "fig_code", "athlete", "takeoff", "tolerances", "keyframes"});
  skill.name = root.At("name").AsString();
  if (const YamlNode* n = root.Find("fig_code")) skill.fig_code = n->AsString();

  // Athlete profile, relative to the skill's folder.
  const YamlNode& athlete = root.At("athlete");
  skill.athlete_path = athlete.AsString();
  if (skill.athlete_path.is_relative()) skill.athlete_path = base_dir / skill.athlete_path;
  // A profile that cannot be read is the skill file's line too: which file named it.
  try {
    skill.athlete = ReadAthleteProfile(skill.athlete_path);
  } catch (const InputError& e) {
    athlete.Fail(e.what());
  }

  ReadTakeoff(root.At("takeoff"), &skill);
  const Tolerances tolerances = ReadTolerances(root.Find("tolerances"));

  const YamlNode& keyframes = root.At("keyframes");
  if (!keyframes.IsSequence() || keyframes.items().size() < 3)
    keyframes.Fail("expected a sequence of at least 3 keyframes");
  if (keyframes.items().size() > kMaxKeyframes)
    keyframes.Fail(std::to_string(keyframes.items().size()) + " keyframes; at most " +
                   std::to_string(kMaxKeyframes) + " (a skill has 5–15)");
  for (const YamlNode& item : keyframes.items())
    skill.keyframes.push_back(ReadKeyframe(item, tolerances));
  CheckKeyframeTimes(skill);
  CheckKeyframeSteps(skill);
  return skill;
}

Skill ReadSkill(const std::filesystem::path& path) {
  return SkillFromYaml(ReadYamlFile(path), path.parent_path());
}

std::string FormatSkillYaml(const Skill& skill, const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  constexpr double kRadToDeg = 180.0 / std::numbers::pi;
  YAML::Emitter out;
  // 12 significant digits: -30 stays -30 after the degrees' round trip, and 1e-12 of an angle is
  // far below anything a body does.
  out.SetDoublePrecision(12);
  out << YAML::Comment("Written by Acrolab from " + skill.source +
                       ". Format: docs/formats/skill.md.");
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << skill.name;
  if (!skill.fig_code.empty())
    out << YAML::Key << "fig_code" << YAML::Value << YAML::DoubleQuoted << skill.fig_code;
  // The athlete relative to the new file's folder when both are on one tree.
  std::string athlete = skill.athlete_path.string();
  if (!athlete.empty()) {
    const fs::path from = fs::weakly_canonical(fs::absolute(dir));
    const fs::path to = fs::weakly_canonical(fs::absolute(skill.athlete_path));
    const fs::path rel = to.lexically_relative(from);
    int up = 0;
    for (const fs::path& part : rel) up += part == ".." ? 1 : 0;
    athlete = rel.empty() || up > 2 ? to.string() : rel.string();
  }
  out << YAML::Key << "athlete" << YAML::Value << athlete;
  const Eigen::Vector3d& v = skill.takeoff_com_velocity_mps;
  out << YAML::Key << "takeoff" << YAML::Value << YAML::BeginMap << YAML::Key << "com_velocity_mps"
      << YAML::Value << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z() << YAML::EndSeq
      << YAML::EndMap;
  out << YAML::Key << "keyframes" << YAML::Value << YAML::BeginSeq;
  for (const SkillKeyframe& k : skill.keyframes) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << k.name;
    out << YAML::Key << "somersault_deg" << YAML::Value << k.somersault_rad * kRadToDeg;
    if (k.tilt_rad != 0) out << YAML::Key << "tilt_deg" << YAML::Value << k.tilt_rad * kRadToDeg;
    if (k.twist_rad != 0) out << YAML::Key << "twist_deg" << YAML::Value << k.twist_rad * kRadToDeg;
    if (k.time_s) out << YAML::Key << "time_s" << YAML::Value << *k.time_s;
    out << YAML::Key << "tolerance_position_m" << YAML::Value << k.tolerance_position_m;
    out << YAML::Key << "tolerance_angle_deg" << YAML::Value << k.tolerance_angle_rad * kRadToDeg;
    out << YAML::Key << "joints_deg" << YAML::Value << YAML::BeginMap;
    for (const StandardJoint& j : kStandardJoints) {
      const int first = StandardJointDofIndex(j.segment, 0);
      const int n = static_cast<int>(j.axis_sequence.size());
      // Up to the last angle that is not zero (the rest are the reference pose).
      int last = -1;
      for (int a = 0; a < n; ++a)
        if (first + a < k.joint_angles_rad.size() && k.joint_angles_rad(first + a) != 0) last = a;
      if (last < 0) continue;
      out << YAML::Key << std::string(j.segment) << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (int a = 0; a <= last; ++a) out << k.joint_angles_rad(first + a) * kRadToDeg;
      out << YAML::EndSeq;
    }
    out << YAML::EndMap << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

void WriteSkill(const std::filesystem::path& path, const Skill& skill) {
  WriteFileAtomically(
      path, FormatSkillYaml(skill, path.parent_path().empty() ? "." : path.parent_path()));
}

}  // namespace acro::analysis
