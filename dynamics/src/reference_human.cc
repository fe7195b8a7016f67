#include "acro/dynamics/reference_human.h"

#include <cmath>

#include "acro/base/input_error.h"
#include "acro/dynamics/model_builder.h"

namespace acro::dynamics {
namespace {

// de Leva 1996 reference stature (mm) for the male tables.
constexpr double kDeLevaStatureMm = 1741.0;

HumanSegmentParameters Seg(
    double mass, double length_mm, double com, double rx, double ry, double rz) {
  HumanSegmentParameters p;
  p.mass_fraction = mass;
  p.length_fraction = length_mm / kDeLevaStatureMm;
  p.com_fraction = com;
  p.gyration_fraction = Eigen::Vector3d(rx, ry, rz);
  return p;
}

MassProperties Mass(const ReferenceHumanParameters& params, int i, const Eigen::Vector3d& com_dir) {
  const HumanSegmentParameters& s = params.segments[static_cast<size_t>(i)];
  const double length = s.length_fraction * params.height_m;
  MassProperties m;
  m.mass_kg = s.mass_fraction * params.mass_kg;
  m.p_BoBcm_B = com_dir * (s.com_fraction * length);
  const Eigen::Vector3d r = s.gyration_fraction * length;
  m.I_BBcm_B = (m.mass_kg * r.cwiseProduct(r)).asDiagonal();
  return m;
}

}  // namespace

std::array<HumanSegmentParameters, 15> ReferenceHumanParameters::DeLevaMale() {
  // de Leva 1996, Table 4 (male): mass %, length (mm, for 1741 mm stature), centre of mass from the
  // proximal end, radii of gyration (sagittal x, transverse y, longitudinal z) in % of length.
  // Pelvis = lower trunk (centre of mass 61.15 % from OMPH = 38.85 % from the hip midpoint).
  // Thorax = upper + middle trunk from the lumbar joint to C7 (386.2 mm), merged by the
  // parallel-axis theorem: centre of mass 46.3 % from the lumbar joint, radii 50.5/43.8/34.5 %.
  // Head-neck from C7 (59.76 % from the vertex = 40.24 % from C7).
  // Foot: long axis x (radii 12.4 % about x, 24.5 % about y, 25.7 % about z), centre of mass
  // 44.15 % from the heel.
  const HumanSegmentParameters pelvis = Seg(0.1117, 145.7, 0.3885, 0.615, 0.551, 0.587);
  const HumanSegmentParameters thorax = Seg(0.3229, 386.2, 0.463, 0.505, 0.438, 0.345);
  const HumanSegmentParameters head = Seg(0.0694, 203.3, 0.4024, 0.362, 0.376, 0.312);
  const HumanSegmentParameters upper_arm = Seg(0.0271, 281.7, 0.5772, 0.285, 0.269, 0.158);
  const HumanSegmentParameters forearm = Seg(0.0162, 268.9, 0.4574, 0.276, 0.265, 0.121);
  const HumanSegmentParameters hand = Seg(0.0061, 86.2, 0.7900, 0.628, 0.513, 0.401);
  const HumanSegmentParameters thigh = Seg(0.1416, 422.2, 0.4095, 0.329, 0.329, 0.149);
  const HumanSegmentParameters shank = Seg(0.0433, 434.0, 0.4459, 0.255, 0.249, 0.103);
  const HumanSegmentParameters foot = Seg(0.0137, 258.1, 0.4415, 0.124, 0.245, 0.257);
  return {pelvis,
          thorax,
          head,
          upper_arm,
          forearm,
          hand,
          upper_arm,
          forearm,
          hand,
          thigh,
          shank,
          foot,
          thigh,
          shank,
          foot};
}

bool ReferenceHumanParameters::IsValid(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!(std::isfinite(height_m) && height_m > 0.0))
    return fail("height_m must be positive, got " + std::to_string(height_m));
  if (!(std::isfinite(mass_kg) && mass_kg > 0.0))
    return fail("mass_kg must be positive, got " + std::to_string(mass_kg));
  double total = 0.0;
  for (size_t i = 0; i < segments.size(); ++i) {
    const HumanSegmentParameters& s = segments[i];
    const std::string name = kReferenceHumanSegments[i];
    if (!(s.mass_fraction > 0.0)) return fail(name + ": mass_fraction must be positive");
    if (!(s.length_fraction > 0.0)) return fail(name + ": length_fraction must be positive");
    if (!(s.com_fraction > 0.0)) return fail(name + ": com_fraction must be positive");
    if (!(s.gyration_fraction.minCoeff() > 0.0))
      return fail(name + ": gyration_fraction must be positive");
    total += s.mass_fraction;
  }
  // Fractions are given to 4 digits; 1e-9 only absorbs the rounding of their sum.
  if (std::abs(total - 1.0) > 1e-9)
    return fail("mass fractions sum to " + std::to_string(total) + ", not 1");
  return true;
}

Model<double> MakeReferenceHuman(const ReferenceHumanParameters& params) {
  std::string why;
  if (!params.IsValid(&why)) throw InputError("ReferenceHumanParameters", "", why);
  const double H = params.height_m;
  auto length = [&](int i) { return params.segments[static_cast<size_t>(i)].length_fraction * H; };
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d down = -up;

  // Joint-centre geometry as fractions of stature (typical adult proportions): hip centres
  // ±0.051 H from the midline, shoulder centres ±0.103 H and 0.026 H below C7, ankle 0.039 H above
  // the sole, heel 0.2 foot lengths behind the ankle.
  const double hip_half_width = 0.051 * H;
  const double shoulder_half_width = 0.103 * H;
  const double shoulder_drop = 0.026 * H;
  const double ankle_height = 0.039 * H;
  const double foot_length = length(11);
  const double heel_back = 0.2 * foot_length;

  // Pelvis: root, centre of mass above the hip midpoint.
  ModelBuilder b("pelvis", Mass(params, 0, up));
  b.SetGravity(params.gravity_W);
  auto joint = [](const char* seq, const Eigen::Vector3d& p) {
    JointSpec j;
    j.axis_sequence = seq;
    j.p_PoJo_P = p;
    return j;
  };
  b.AddSegment("thorax", "pelvis", joint("yxz", length(0) * up), Mass(params, 1, up));
  b.AddSegment("head", "thorax", joint("yxz", length(1) * up), Mass(params, 2, up));

  // Arms and legs, right (side = −1, y negative) then left.
  for (int side_index = 0; side_index < 2; ++side_index) {
    const double side = side_index == 0 ? -1.0 : 1.0;
    const std::string s = side_index == 0 ? "r_" : "l_";
    const int arm = 3 + 3 * side_index;
    b.AddSegment(
        s + "upper_arm",
        "thorax",
        joint("yxz", Eigen::Vector3d(0.0, side * shoulder_half_width, length(1) - shoulder_drop)),
        Mass(params, arm, down));
    b.AddSegment(s + "forearm",
                 s + "upper_arm",
                 joint("yz", length(arm) * down),
                 Mass(params, arm + 1, down));
    b.AddSegment(s + "hand",
                 s + "forearm",
                 joint("yx", length(arm + 1) * down),
                 Mass(params, arm + 2, down));
  }
  for (int side_index = 0; side_index < 2; ++side_index) {
    const double side = side_index == 0 ? -1.0 : 1.0;
    const std::string s = side_index == 0 ? "r_" : "l_";
    const int leg = 9 + 3 * side_index;
    b.AddSegment(s + "thigh",
                 "pelvis",
                 joint("yxz", Eigen::Vector3d(0.0, side * hip_half_width, 0.0)),
                 Mass(params, leg, down));
    b.AddSegment(
        s + "shank", s + "thigh", joint("y", length(leg) * down), Mass(params, leg + 1, down));
    // Foot: long axis x from the heel; centre of mass half-way down to the sole.
    MassProperties foot = Mass(params, leg + 2, Eigen::Vector3d::UnitX());
    foot.p_BoBcm_B.x() -= heel_back;
    foot.p_BoBcm_B.z() = -0.5 * ankle_height;
    b.AddSegment(s + "foot", s + "shank", joint("yx", length(leg + 1) * down), foot);
  }

  // Joint centres (each at its child segment's origin) and landmarks.
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  b.AddPoint("lumbar_jc", "thorax", origin);
  b.AddPoint("neck_jc", "head", origin);
  for (const std::string s : {"r_", "l_"}) {
    b.AddPoint(s + "shoulder_jc", s + "upper_arm", origin);
    b.AddPoint(s + "elbow_jc", s + "forearm", origin);
    b.AddPoint(s + "wrist_jc", s + "hand", origin);
    b.AddPoint(s + "hip_jc", s + "thigh", origin);
    b.AddPoint(s + "knee_jc", s + "shank", origin);
    b.AddPoint(s + "ankle_jc", s + "foot", origin);
  }
  b.AddPoint("head_vertex", "head", length(2) * up);
  b.AddPoint("c7", "thorax", Eigen::Vector3d(-0.03 * H, 0.0, length(1)));
  for (const double side : {-1.0, 1.0}) {
    const std::string s = side < 0 ? "r_" : "l_";
    b.AddPoint(s + "asis", "pelvis", Eigen::Vector3d(0.034 * H, side * 0.07 * H, 0.05 * H));
    // Fingertip: the hand's length to MET3 plus the middle finger (about as long again).
    b.AddPoint(s + "fingertip", s + "hand", 2.2 * length(5) * down);
    b.AddPoint(s + "heel", s + "foot", Eigen::Vector3d(-heel_back, 0.0, -ankle_height));
    b.AddPoint(s + "toe", s + "foot", Eigen::Vector3d(foot_length - heel_back, 0.0, -ankle_height));
  }
  return b.Build();
}

}  // namespace acro::dynamics
