#include "acro/athlete/athlete_body.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/base/yaml.h"

namespace acro::analysis {

int AthleteBody::Find(std::string_view name) const {
  for (size_t i = 0; i < segments.size(); ++i)
    if (segments[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

// Solids of each standard segment, in kStandardSegmentNames order.
const std::array<std::vector<std::string_view>, 15> kSolids = {{
    {"s0", "s1"},
    {"s2", "s3", "s4"},
    {"s5", "s6", "s7"},
    {"b0", "b1"},
    {"b2", "b3"},
    {"b4", "b5", "b6"},
    {"a0", "a1"},
    {"a2", "a3"},
    {"a4", "a5", "a6"},
    {"k0", "k1", "k2"},
    {"k3", "k4"},
    {"k5", "k6", "k7", "k8"},
    {"j0", "j1", "j2"},
    {"j3", "j4"},
    {"j5", "j6", "j7", "j8"},
}};

}  // namespace

int StandardSegmentOfYeadonSolid(std::string_view solid_label) {
  for (size_t i = 0; i < kSolids.size(); ++i)
    for (std::string_view label : kSolids[i])
      if (label == solid_label) return static_cast<int>(i);
  return -1;
}

AthleteBody MakeAthleteBodyFromYeadon(const YeadonHuman& human) {
  auto solid = [&](std::string_view label) -> const YeadonSolid& {
    const int i = human.FindSolid(label);
    ACRO_DEMAND(i >= 0);
    return human.solids()[static_cast<size_t>(i)];
  };
  // The two ends of a solid: stadium 0 (S's origin) and stadium 1 (at S's z = height).
  auto base = [&](std::string_view label) { return solid(label).p_HoSo_H; };
  auto top = [&](std::string_view label) {
    const YeadonSolid& s = solid(label);
    return Eigen::Vector3d(s.p_HoSo_H + s.height_m * s.R_HS.col(2));
  };
  // Proximal joint and distal end of each segment. Limb solids run distal (stadium 0) to proximal.
  const std::array<std::pair<Eigen::Vector3d, Eigen::Vector3d>, 15> ends = {{
      {base("s0"), top("s1")},  // pelvis: Ls0 → Ls2
      {base("s2"), top("s4")},  // thorax: Ls2 → Ls5 (acromion)
      {base("s5"), top("s7")},  // head: neck base → vertex
      {top("b0"), base("b1")},  // upper arm: shoulder → elbow
      {top("b2"), base("b3")},  // forearm: elbow → wrist
      {top("b4"), base("b6")},  // hand: wrist → fingernails
      {top("a0"), base("a1")},
      {top("a2"), base("a3")},
      {top("a4"), base("a6")},
      {top("k0"), base("k2")},  // thigh: hip → knee
      {top("k3"), base("k4")},  // shank: knee → ankle
      {top("k5"), base("k8")},  // foot: ankle → toe nails (pointed)
      {top("j0"), base("j2")},
      {top("j3"), base("j4")},
      {top("j5"), base("j8")},
  }};
  AthleteBody body;
  body.model =
      "Yeadon 1990 (" + std::string(DensitySetName(human.options().density)) + " densities)";
  std::vector<InertialProperties> all;
  for (size_t i = 0; i < kSolids.size(); ++i) {
    BodySegment seg;
    seg.name = std::string(kStandardSegmentNames[i]);
    seg.parent = kStandardSegmentParents[i];
    seg.p_HoJ_H = ends[i].first;
    seg.p_HoE_H = ends[i].second;
    std::vector<InertialProperties> parts;
    for (std::string_view label : kSolids[i]) parts.push_back(solid(label).in_H);
    seg.in_H = CombineInertia(parts);
    all.push_back(seg.in_H);
    body.segments.push_back(seg);
  }
  // The pelvis joint is H's origin exactly.
  body.segments[0].p_HoJ_H.setZero();
  body.total = CombineInertia(all);
  // Stature: Yeadon's feet are pointed, so the sole is not measured; the vertex-to-ankle distance
  // is taken as (1 − 0.039) of the stature (ankle height 0.039 H, Drillis & Contini 1966).
  body.height_m = (top("s7").z() - base("j4").z()) / (1.0 - 0.039);
  return body;
}

namespace {

// Angle of `base` for a side ("l" or "r"): the sided name wins over the shared one.
double Angle(const BodyPose& pose, std::string_view base, const char* side) {
  if (side != nullptr) {
    const auto sided = pose.angles_rad.find(std::string(side) + "_" + std::string(base));
    if (sided != pose.angles_rad.end()) return sided->second;
  }
  const auto shared = pose.angles_rad.find(std::string(base));
  return shared == pose.angles_rad.end() ? 0.0 : shared->second;
}

Eigen::Matrix3d Ry(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
}
Eigen::Matrix3d Rx(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d Rz(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

bool IsBodyPoseAngle(std::string_view name) {
  std::string_view base = name;
  const bool sided = name.rfind("l_", 0) == 0 || name.rfind("r_", 0) == 0;
  if (sided) base = name.substr(2);
  for (std::string_view n : kBodyPoseAngleNames) {
    if (n != base) continue;
    const bool limb = n.find("shoulder") == 0 || n.find("elbow") == 0 || n.find("hip") == 0 ||
                      n.find("knee") == 0;
    return !sided || limb;
  }
  return false;
}

bool MakeNamedPose(std::string_view name, BodyPose* pose) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  pose->angles_rad.clear();
  if (name == "straight") return true;
  if (name == "pike") {
    pose->angles_rad = {{"hip_flexion", 130 * kDeg}, {"shoulder_flexion", 80 * kDeg}};
    return true;
  }
  if (name == "tuck") {
    pose->angles_rad = {
        {"hip_flexion", 140 * kDeg}, {"knee_flexion", 145 * kDeg}, {"elbow_flexion", 100 * kDeg}};
    return true;
  }
  return false;
}

AthleteBody PoseAthleteBody(const AthleteBody& body, const BodyPose& pose) {
  for (const auto& [name, value] : pose.angles_rad) {
    if (!IsBodyPoseAngle(name)) throw InputError("", "pose", "unknown angle '" + name + "'");
  }
  // Rotation of each segment relative to its parent, in the reference pose's axes (H).
  std::array<Eigen::Matrix3d, 15> R_rel;
  R_rel.fill(Eigen::Matrix3d::Identity());
  R_rel[0] = Ry(Angle(pose, "somersault", nullptr)) * Rx(Angle(pose, "tilt", nullptr)) *
             Rz(Angle(pose, "twist", nullptr));
  R_rel[1] = Ry(Angle(pose, "trunk_flexion", nullptr));
  R_rel[2] = Ry(Angle(pose, "neck_flexion", nullptr));
  // Limbs hang down (−z): flexion (forward) is a negative rotation about y, abduction a positive
  // rotation about x on the left (+y) and a negative one on the right; knee flexion is positive.
  for (const char* side : {"r", "l"}) {
    const bool left = side[0] == 'l';
    const double sigma = left ? 1.0 : -1.0;
    const size_t arm = left ? 6 : 3;
    const size_t leg = left ? 12 : 9;
    R_rel[arm] = Ry(-Angle(pose, "shoulder_flexion", side)) *
                 Rx(sigma * Angle(pose, "shoulder_abduction", side));
    R_rel[arm + 1] = Ry(-Angle(pose, "elbow_flexion", side));
    R_rel[leg] =
        Ry(-Angle(pose, "hip_flexion", side)) * Rx(sigma * Angle(pose, "hip_abduction", side));
    R_rel[leg + 1] = Ry(Angle(pose, "knee_flexion", side));
  }
  // Forward kinematics from the pelvis outwards (parents come first in the standard order):
  // R_i = R_parent R_rel_i, joint_i = joint_parent' + R_parent (joint_i − joint_parent).
  AthleteBody out = body;
  std::vector<Eigen::Matrix3d> R(body.segments.size());
  std::vector<InertialProperties> all;
  for (size_t i = 0; i < body.segments.size(); ++i) {
    const BodySegment& rest = body.segments[i];
    BodySegment& seg = out.segments[i];
    Eigen::Vector3d joint = rest.p_HoJ_H;
    if (rest.parent < 0) {
      R[i] = R_rel[i];
      joint = R[i] * rest.p_HoJ_H;
    } else {
      const size_t p = static_cast<size_t>(rest.parent);
      R[i] = R[p] * R_rel[i];
      joint = out.segments[p].p_HoJ_H + R[p] * (rest.p_HoJ_H - body.segments[p].p_HoJ_H);
    }
    seg.p_HoJ_H = joint;
    seg.R_pose = R[i] * rest.R_pose;
    seg.p_HoE_H = joint + R[i] * (rest.p_HoE_H - rest.p_HoJ_H);
    seg.in_H.p_HoCm_H = joint + R[i] * (rest.in_H.p_HoCm_H - rest.p_HoJ_H);
    seg.in_H.I_Cm_H = R[i] * rest.in_H.I_Cm_H * R[i].transpose();
    all.push_back(seg.in_H);
  }
  out.total = CombineInertia(all);
  return out;
}

double SomersaultInertia(const AthleteBody& body) {
  return body.total.I_Cm_H(1, 1);
}

ShapeInertias CalcShapeInertias(const AthleteBody& rest, const AthleteBody& posed) {
  ShapeInertias out;
  BodyPose pose;
  MakeNamedPose("straight", &pose);
  out.straight_kgm2 = SomersaultInertia(PoseAthleteBody(rest, pose));
  MakeNamedPose("pike", &pose);
  out.pike_kgm2 = SomersaultInertia(PoseAthleteBody(rest, pose));
  MakeNamedPose("tuck", &pose);
  out.tuck_kgm2 = SomersaultInertia(PoseAthleteBody(rest, pose));
  out.pose_kgm2 = SomersaultInertia(posed);
  return out;
}

BodyPose ParseBodyPose(std::string_view spec) {
  BodyPose pose;
  size_t start = 0;
  while (start <= spec.size()) {
    size_t end = spec.find(',', start);
    if (end == std::string_view::npos) end = spec.size();
    const std::string entry(spec.substr(start, end - start));
    start = end + 1;
    if (entry.empty()) throw InputError("", "--pose", "empty entry in '" + std::string(spec) + "'");
    const size_t eq = entry.find('=');
    if (eq == std::string::npos) {
      // A named shape replaces everything set so far.
      BodyPose named;
      if (!MakeNamedPose(entry, &named))
        throw InputError(
            "", "--pose", "'" + entry + "' is not a shape (straight, pike, tuck) nor NAME=DEG");
      pose = named;
      continue;
    }
    const std::string name = entry.substr(0, eq);
    double degrees = 0.0;
    if (!ParseYamlNumber(entry.substr(eq + 1), &degrees) || !std::isfinite(degrees))
      throw InputError("", "--pose", "'" + entry + "': the angle is not a number of degrees");
    if (!IsBodyPoseAngle(name)) {
      std::string names;
      for (std::string_view n : kBodyPoseAngleNames)
        names += (names.empty() ? "" : ", ") + std::string(n);
      throw InputError(
          "",
          "--pose",
          "'" + name + "' is not a pose angle (" + names + ", with l_/r_ for one side)");
    }
    pose.angles_rad[name] = degrees * std::numbers::pi / 180.0;
    if (end == spec.size()) break;
  }
  return pose;
}

}  // namespace acro::analysis
