#include "acro/assess/jump_rotation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "acro/athlete/orientation.h"
#include "acro/base/demand.h"
#include "acro/base/input_error.h"

namespace acro::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Upright when the long axis leans less than the limit; otherwise front (facing down) or back.
fig::BodyPosition ClassifyPosition(const Eigen::Quaterniond& q_WB, double max_lean_deg) {
  const Eigen::Matrix3d R = q_WB.toRotationMatrix();
  const double lean = std::acos(std::clamp(R(2, 2), -1.0, 1.0));
  if (lean < max_lean_deg * kDeg || lean > kPi - max_lean_deg * kDeg)
    return fig::BodyPosition::kFeet;
  return R(2, 0) < 0 ? fig::BodyPosition::kFront
                     : fig::BodyPosition::kBack;  // body x (front) pointing down: prone
}

// The somersault axis of a flight. The body's long axis z_B sweeps the plane perpendicular to it
// whatever the twist, so it is the normal of the best-fit plane through the z_B(t) (the eigenvector
// of Σ z zᵀ with the smallest eigenvalue), signed like the lateral axis at take-off. When the long
// axis hardly moves (a jump), the lateral axis at take-off is used.
Eigen::Vector3d SomersaultAxis(const std::vector<Eigen::Quaterniond>& flight) {
  const Eigen::Vector3d lateral0 = flight.front().normalized() * Eigen::Vector3d::UnitY();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Quaterniond& q : flight) {
    const Eigen::Vector3d z = q.normalized() * Eigen::Vector3d::UnitZ();
    scatter += z * z.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter / double(flight.size()));
  // Eigenvalues ascending: the sweep is planar and wide when the middle one is not small (a long
  // axis that turns through 60° or more spreads at least 0.1 of its weight off its mean direction).
  if (eigen.eigenvalues()[1] < 0.05) return lateral0;
  Eigen::Vector3d axis = eigen.eigenvectors().col(0);
  if (axis.dot(lateral0) < 0) axis = -axis;
  return axis;
}

// The integer nearest to `target` that is congruent to `residue` modulo 4.
int NearestCongruent(double target, int residue) {
  const int r = ((residue % 4) + 4) % 4;
  const int base = static_cast<int>(std::floor((target - r) / 4.0)) * 4 + r;
  return (std::abs(base - target) <= std::abs(base + 4 - target)) ? base : base + 4;
}

}  // namespace

bool JumpRotationOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (!(upright_max_lean_deg > 0 && upright_max_lean_deg < 90))
    return fail("upright_max_lean_deg must be in (0, 90)");
  if (!(bed_rotation_quarters >= 0 && bed_rotation_quarters < 2))
    return fail("bed_rotation_quarters must be in [0, 2)");
  if (!(closed_angle_deg > 0 && closed_angle_deg < 180))
    return fail("closed_angle_deg must be in (0, 180)");
  if (!(shape_uncertainty_deg >= 0 && shape_uncertainty_deg <= 45))
    return fail("shape_uncertainty_deg must be in [0, 45]");
  if (!(min_shape_hold_fraction > 0 && min_shape_hold_fraction <= 1))
    return fail("min_shape_hold_fraction must be in (0, 1]");
  if (!(shape_median_frames >= 1 && shape_median_frames % 2 == 1 && shape_median_frames <= 99))
    return fail("shape_median_frames must be odd, 1 to 99");
  return true;
}

RotationAngles CalcRotationAngles(const std::vector<Eigen::Quaterniond>& q_WB,
                                  const Eigen::Vector3d& lateral_W) {
  // The somersault frame S: y the horizontal lateral axis, z up, x = y × z.
  Eigen::Vector3d y_S(lateral_W.x(), lateral_W.y(), 0.0);
  ACRO_DEMAND(y_S.norm() > 1e-9);
  y_S.normalize();
  const Eigen::Vector3d z_S = Eigen::Vector3d::UnitZ();
  Eigen::Matrix3d R_WS;
  R_WS << y_S.cross(z_S), y_S, z_S;
  const int n = static_cast<int>(q_WB.size());
  RotationAngles out;
  out.somersault_rad.resize(n);
  out.tilt_rad.resize(n);
  out.twist_rad.resize(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d R =
        R_WS.transpose() * q_WB[static_cast<std::size_t>(i)].normalized().toRotationMatrix();
    const SomersaultTiltTwist angles = CalcSomersaultTiltTwist(R);
    out.tilt_rad[i] = angles.tilt_rad;
    out.twist_rad[i] = angles.twist_rad;
    out.somersault_rad[i] = angles.somersault_rad;
  }
  UnwrapAngles(&out.somersault_rad);
  UnwrapAngles(&out.twist_rad);
  return out;
}

namespace {

// The flight's frames of `angle_rad` median-filtered over `width` frames (the window shrinks at
// the ends), in degrees.
std::vector<double> MedianDeg(const Eigen::VectorXd& angle_rad, int first, int last, int width) {
  std::vector<double> out;
  std::vector<double> window;
  for (int i = first; i <= last; ++i) {
    window.clear();
    for (int k = std::max(first, i - width / 2); k <= std::min(last, i + width / 2); ++k)
      window.push_back(angle_rad[k] / kDeg);
    std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
    out.push_back(window[window.size() / 2]);
  }
  return out;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// FIG body positions over the flight (JumpRotationOptions::closed_angle_deg).
void ClassifyShape(const Eigen::VectorXd& hip_flexion_rad,
                   const Eigen::VectorXd& knee_flexion_rad,
                   int first,
                   int last,
                   const JumpRotationOptions& options,
                   JumpRotation* out) {
  const int width = options.shape_median_frames;
  const std::vector<double> hip = MedianDeg(hip_flexion_rad, first, last, width);
  const bool has_knee = knee_flexion_rad.size() > last;
  const std::vector<double> knee =
      has_knee ? MedianDeg(knee_flexion_rad, first, last, width) : std::vector<double>(hip.size());
  // Closed: the body angle (180° − flexion) at or below the limit.
  const double min_flexion = 180.0 - options.closed_angle_deg;
  // The longest run of frames with the hips closed.
  int run_start = -1, best_start = 0, best_length = 0;
  for (int i = 0; i <= static_cast<int>(hip.size()); ++i) {
    const bool closed = i < static_cast<int>(hip.size()) && hip[size_t(i)] >= min_flexion;
    if (closed && run_start < 0) run_start = i;
    if (!closed && run_start >= 0) {
      if (i - run_start > best_length) {
        best_length = i - run_start;
        best_start = run_start;
      }
      run_start = -1;
    }
  }
  const int frames = static_cast<int>(hip.size());
  out->shape_hold_fraction = double(best_length) / std::max(1, frames);
  std::vector<double> hip_angles, knee_angles;
  int knees_closed = 0;
  for (int i = best_start; i < best_start + best_length; ++i) {
    hip_angles.push_back(180.0 - hip[size_t(i)]);
    knee_angles.push_back(180.0 - knee[size_t(i)]);
    knees_closed += knee[size_t(i)] >= min_flexion ? 1 : 0;
  }
  out->shape_hip_angle_deg = best_length > 0 ? Median(hip_angles) : 180.0 - Median(hip);
  out->shape_knee_angle_deg = best_length > 0 ? Median(knee_angles) : 180.0 - Median(knee);
  out->shape_knees_closed_fraction = double(knees_closed) / std::max(1, best_length);
  const int limit = static_cast<int>(std::lround(options.closed_angle_deg));
  const int held_percent = static_cast<int>(std::lround(100 * out->shape_hold_fraction));
  if (out->shape_hold_fraction < options.min_shape_hold_fraction) {
    out->skill.shape = fig::SkillShape::kStraight;
    out->shape_reason = "straight: the trunk–thigh angle stayed above " + std::to_string(limit) +
                        "° (closed over " + std::to_string(held_percent) +
                        " % of the flight at the most; median " +
                        std::to_string(static_cast<int>(std::lround(180.0 - Median(hip)))) + "°)";
    return;
  }
  const bool tuck = has_knee && out->shape_knees_closed_fraction >= 0.5;
  out->skill.shape = tuck ? fig::SkillShape::kTuck : fig::SkillShape::kPike;
  out->shape_reason = std::string(tuck ? "tuck" : "pike") + ": trunk–thigh " +
                      std::to_string(static_cast<int>(std::lround(out->shape_hip_angle_deg))) +
                      "°, thigh–shank " +
                      std::to_string(static_cast<int>(std::lround(out->shape_knee_angle_deg))) +
                      "° (medians) held over " + std::to_string(held_percent) +
                      " % of the flight (FIG: " + (tuck ? "both" : "the hips") + " at or below " +
                      std::to_string(limit) + "°" + (tuck ? "" : ", the knees above") + ")";
  // A close call: the knees' (tuck or pike) or the hips' (closed or straight) median within the
  // uncertainty of the line.
  const double u = options.shape_uncertainty_deg;
  if (has_knee && std::abs(out->shape_knee_angle_deg - options.closed_angle_deg) < u)
    out->shape_alternative = tuck ? "pike" : "tuck";
  else if (std::abs(out->shape_hip_angle_deg - options.closed_angle_deg) < u)
    out->shape_alternative = "straight";
  if (!out->shape_alternative.empty())
    out->shape_reason +=
        "; a close call (within " + std::to_string(static_cast<int>(std::lround(u))) + "° of " +
        std::to_string(limit) + "°): it could be read as a " + out->shape_alternative;
}

}  // namespace

JumpRotation CountJumpRotation(const std::vector<Eigen::Quaterniond>& q_WB,
                               int takeoff_frame,
                               int landing_frame,
                               const Eigen::VectorXd& hip_flexion_rad,
                               const Eigen::VectorXd& knee_flexion_rad,
                               const JumpRotationOptions& options) {
  DemandValidOptions(options, "rotation options");
  ACRO_DEMAND(takeoff_frame >= 0 && landing_frame > takeoff_frame &&
              landing_frame < static_cast<int>(q_WB.size()));
  JumpRotation out;
  const std::vector<Eigen::Quaterniond> flight(q_WB.begin() + takeoff_frame,
                                               q_WB.begin() + landing_frame + 1);
  const Eigen::Vector3d lateral_W = SomersaultAxis(flight);
  const RotationAngles angles = CalcRotationAngles(flight, lateral_W);
  const int n = static_cast<int>(flight.size());
  out.measured_somersault_rad = angles.somersault_rad[n - 1] - angles.somersault_rad[0];
  out.measured_twist_rad = angles.twist_rad[n - 1] - angles.twist_rad[0];
  out.takeoff_position = ClassifyPosition(flight.front(), options.upright_max_lean_deg);
  out.landing_position = ClassifyPosition(flight.back(), options.upright_max_lean_deg);

  // Nominal quarters: congruent to the change of position, nearest to the in-air rotation plus what
  // happens on the bed (in the direction of rotation).
  const double measured_quarters = out.measured_somersault_rad / (kPi / 2);
  const bool both_upright = out.takeoff_position == fig::BodyPosition::kFeet &&
                            out.landing_position == fig::BodyPosition::kFeet;
  const double bed = (both_upright ? 1.0 : 0.5) * options.bed_rotation_quarters;
  const double direction_sign = measured_quarters >= 0 ? 1.0 : -1.0;
  const int residue =
      static_cast<int>(out.landing_position) - static_cast<int>(out.takeoff_position);
  const int signed_quarters = NearestCongruent(measured_quarters + direction_sign * bed, residue);
  fig::FigSkill& skill = out.skill;
  skill.quarter_somersaults = std::abs(signed_quarters);
  skill.direction = skill.quarter_somersaults == 0 ? fig::SomersaultDirection::kNone
                    : signed_quarters > 0          ? fig::SomersaultDirection::kForward
                                                   : fig::SomersaultDirection::kBackward;

  // Twists per somersault: the nominal somersault angle runs from the bed rotation done before
  // take-off (half the shortfall) to the nominal total; each full turn is one somersault.
  const int slots = fig::FigSkill::SomersaultSlots(skill.quarter_somersaults);
  const double before_takeoff =
      std::max(0.0, (skill.quarter_somersaults - std::abs(measured_quarters)) / 2) * kPi / 2;
  std::vector<double> twist_in_slot(static_cast<std::size_t>(slots), 0.0);
  for (int i = 1; i < n; ++i) {
    const double progress =
        before_takeoff + 0.5 * std::abs((angles.somersault_rad[i] + angles.somersault_rad[i - 1]) -
                                        2 * angles.somersault_rad[0]);
    const int slot = std::clamp(static_cast<int>(progress / (2 * kPi)), 0, slots - 1);
    twist_in_slot[static_cast<std::size_t>(slot)] += angles.twist_rad[i] - angles.twist_rad[i - 1];
  }
  for (double twist : twist_in_slot)
    skill.half_twists.push_back(static_cast<int>(std::lround(std::abs(twist) / kPi)));

  // Shape: the longest hold with the hips closed, and whether the knees were closed over it.
  skill.shape = fig::SkillShape::kStraight;
  out.shape_reason = "straight: no hip angle measured";
  if (hip_flexion_rad.size() > landing_frame) {
    int best = takeoff_frame;
    for (int i = takeoff_frame; i <= landing_frame; ++i) {
      if (hip_flexion_rad[i] > hip_flexion_rad[best]) best = i;
    }
    out.max_hip_flexion_deg = hip_flexion_rad[best] / kDeg;
    out.knee_flexion_at_max_hip_deg =
        knee_flexion_rad.size() > best ? knee_flexion_rad[best] / kDeg : 0.0;
    ClassifyShape(hip_flexion_rad, knee_flexion_rad, takeoff_frame, landing_frame, options, &out);
  }
  return out;
}

fig::TwistDirection TwistDirectionOf(const JumpRotation& rotation) {
  return TwistDirectionOf(rotation.skill.total_half_twists(), rotation.measured_twist_rad);
}

fig::TwistDirection TwistDirectionOf(int half_twists, double twist_rad) {
  if (half_twists == 0) return fig::TwistDirection::kNone;
  return twist_rad > 0 ? fig::TwistDirection::kLeft : fig::TwistDirection::kRight;
}

const char* TwistDirectionName(fig::TwistDirection direction) {
  switch (direction) {
    case fig::TwistDirection::kLeft:
      return "left";
    case fig::TwistDirection::kRight:
      return "right";
    case fig::TwistDirection::kNone:
      return "none";
  }
  return "none";
}

}  // namespace acro::analysis
