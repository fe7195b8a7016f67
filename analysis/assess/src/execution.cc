#include "acro/assess/execution.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "acro/assess/trial_analysis.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis {

bool ExecutionOptions::IsValid(std::string* why) const {
  auto ok = [](double v, double hi) { return std::isfinite(v) && v >= 0 && v <= hi; };
  if (!ok(angle_uncertainty_deg, 90) || !ok(elbow_uncertainty_deg, 90) ||
      !ok(position_uncertainty_m, 1) || !ok(time_uncertainty_s, 1) || !ok(takeoff_edge_s, 1) ||
      !ok(landing_edge_s, 1)) {
    if (why) *why = "execution: the uncertainties must be 0–90°, 0–1 m, 0–1 s and the edges 0–1 s";
    return false;
  }
  return true;
}

ExecutionOptions ExecutionOptions::WithNoise(double noise_rms_m) const {
  ExecutionOptions o = *this;
  if (!std::isfinite(noise_rms_m)) return o;
  const double beyond_mm = std::max(0.0, 1000.0 * noise_rms_m - 2.0);
  o.angle_uncertainty_deg += 0.4 * beyond_mm;
  o.elbow_uncertainty_deg += 1.5 * beyond_mm;
  o.position_uncertainty_m += 0.0015 * beyond_mm;
  o.time_uncertainty_s += 0.001 * beyond_mm;
  return o;
}

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

int Column(const Motion& m, const std::string& name) {
  const auto it = std::find(m.coordinate_names.begin(), m.coordinate_names.end(), name);
  return it == m.coordinate_names.end() ? -1 : static_cast<int>(it - m.coordinate_names.begin());
}

// The largest of `value(frame)` over `frames`, and where.
template <typename Value>
std::pair<double, int> Worst(const std::vector<int>& frames, const Value& value) {
  double worst = -std::numeric_limits<double>::infinity();
  int at = -1;
  for (int f : frames) {
    const double v = value(f);
    if (std::isfinite(v) && v > worst) {
      worst = v;
      at = f;
    }
  }
  return {worst, at};
}

}  // namespace

std::vector<fig::MeasuredFault> MeasureExecution(const TrialAnalysis& a,
                                                 size_t jump,
                                                 const fig::ExecutionRules& rules,
                                                 const ExecutionOptions& options) {
  std::vector<fig::MeasuredFault> out;
  if (jump >= a.jumps.size()) return out;
  const JumpMetrics& j = a.jumps[jump];
  if (j.partial()) return out;
  const Motion& m = a.reconstruction.motion;
  const dynamics::Model<double>& model = a.reconstruction.model;
  const fig::FigSkill& skill = j.rotation.skill;
  // The element's own frames: the flight less its edges.
  std::vector<int> frames;
  for (int f = std::max(0, j.flight.takeoff_frame);
       f <= std::min(m.num_frames() - 1, j.flight.landing_frame);
       ++f)
    if (m.time_s[f] > j.flight.takeoff_s + options.takeoff_edge_s &&
        m.time_s[f] < j.flight.landing_s - options.landing_edge_s)
      frames.push_back(f);
  if (frames.empty()) return out;

  auto add =
      [&](const char* fault, const char* quantity, double value, double uncertainty, int frame) {
        const fig::FaultRule* rule = rules.Find(fault);
        if (rule == nullptr || !std::isfinite(value)) return;
        fig::MeasuredFault f;
        f.fault = fault;
        f.quantity = quantity;
        f.unit = rule->unit;
        f.value = value;
        f.uncertainty = uncertainty;
        if (!rule->steps.empty()) f.threshold = rule->steps.front().first;
        f.smaller_is_worse = rule->smaller_is_worse;
        f.frame = frame;
        f.time_s = frame >= 0 && frame < m.num_frames() ? m.time_s[frame]
                                                        : std::numeric_limits<double>::quiet_NaN();
        f.reported = rule->Exceeds(value, uncertainty);
        f.deduction = f.reported ? rule->DeductionFor(value) : 0.0;
        out.push_back(std::move(f));
      };
  // Mean of the two sides of a joint angle (deg, anatomical: `sign` makes flexion positive).
  auto both = [&](const char* name, double sign) {
    const int r = Column(m, std::string("r_") + name), l = Column(m, std::string("l_") + name);
    return [&m, r, l, sign](int f) {
      if (r < 0 || l < 0) return std::numeric_limits<double>::quiet_NaN();
      return sign * 0.5 * (m.q(r, f) + m.q(l, f)) / kDeg;
    };
  };
  const double ua = options.angle_uncertainty_deg;

  // Legs and arms: bent knees (not a tuck's — unless the tuck is a close call with a pike, whose
  // bent knees a judge would see), bent elbows, arms lifted sideways.
  if (skill.shape != fig::SkillShape::kTuck || j.rotation.shape_alternative == "pike") {
    const auto [v, f] = Worst(frames, both("knee_flexion", 1.0));
    add("knees_bent", "knee flexion", v, ua, f);
  }
  if (skill.shape != fig::SkillShape::kTuck) {  // a tuck's hands hold the shins: elbows bent
    const auto [v, f] = Worst(frames, both("elbow_flexion", -1.0));
    add("arms_bent", "elbow flexion", v, options.elbow_uncertainty_deg, f);
  }
  // The arms away from a held position, in a straight somersault's middle half (a tuck's and a
  // pike's hands hold the legs; jumps swing the arms — the sample's in-bounce reaches 53°; the
  // take-off's arm swing and the landing's are not the element's): the
  // angle between the upper arm and the trunk, from the nearer of "by the sides" (0°) and
  // "overhead" (180°) — arms out sideways or forward at 45° read 45°, overhead 0°.
  const int sh[2] = {model.FindPoint("r_shoulder_jc"), model.FindPoint("l_shoulder_jc")};
  const int el[2] = {model.FindPoint("r_elbow_jc"), model.FindPoint("l_elbow_jc")};
  const int neck = model.FindPoint("neck_jc"), lumbar = model.FindPoint("lumbar_jc");
  dynamics::Workspace<double> ws(model);
  auto at = [&](int point) {
    const auto& p = model.point(point);
    const auto& X = ws.X_WB[static_cast<size_t>(p.segment)];
    return Eigen::Vector3d(X.rotation() * p.p_BoP_B + X.translation());
  };
  if (skill.shape == fig::SkillShape::kStraight && skill.quarter_somersaults > 0 && sh[0] >= 0 &&
      sh[1] >= 0 && el[0] >= 0 && el[1] >= 0 && neck >= 0 && lumbar >= 0) {
    std::vector<int> middle;
    for (int f : frames)
      if (std::abs(m.time_s[f] - 0.5 * (j.flight.takeoff_s + j.flight.landing_s)) <=
          0.25 * j.time_of_flight_s())
        middle.push_back(f);
    const auto [v, f] = Worst(middle, [&](int k) {
      const Eigen::VectorXd q = m.q.col(k);
      dynamics::CalcForwardKinematics(model, ws, q);
      const Eigen::Vector3d down = (at(lumbar) - at(neck)).normalized();
      double sum = 0;
      for (int s = 0; s < 2; ++s) {
        const double angle =
            std::acos(std::clamp((at(el[s]) - at(sh[s])).normalized().dot(down), -1.0, 1.0)) / kDeg;
        sum += std::min(angle, 180.0 - angle);
      }
      return 0.5 * sum;
    });
    add("arms_out", "arms away from the sides or overhead (middle half)", v, ua, f);
  }
  // The legs' spread: the ankles' distance beyond the hips' (legs hanging parallel give 0).
  {
    const int ra = model.FindPoint("r_ankle_jc"), la = model.FindPoint("l_ankle_jc");
    const int rh = model.FindPoint("r_hip_jc"), lh = model.FindPoint("l_hip_jc");
    if (ra >= 0 && la >= 0 && rh >= 0 && lh >= 0) {
      const auto [v, f] = Worst(frames, [&](int k) {
        const Eigen::VectorXd q = m.q.col(k);
        dynamics::CalcForwardKinematics(model, ws, q);
        return (at(ra) - at(la)).norm() - (at(rh) - at(lh)).norm();
      });
      add("legs_apart", "ankles apart beyond the hips", v, options.position_uncertainty_m, f);
    }
  }
  // The shape: a straight body bent at the hips; a pike's or a tuck's trunk–thigh angle over its
  // hold (the angle the shape was counted from).
  if (skill.shape == fig::SkillShape::kStraight && skill.quarter_somersaults > 0) {
    const auto [v, f] = Worst(frames, both("hip_flexion", -1.0));
    add("body_bent", "hip flexion", v, ua, f);
  }
  if (skill.shape != fig::SkillShape::kStraight && j.rotation.shape_hold_fraction > 0) {
    // Where the hold is most open: the frame whose trunk–thigh angle is largest below the closed
    // limit, for the studio to jump to.
    const auto hip = both("hip_flexion", -1.0);
    int frame = -1;
    double widest = -1;
    for (int f : frames) {
      const double angle = 180.0 - hip(f);
      if (angle <= 135.0 && angle > widest) {
        widest = angle;
        frame = f;
      }
    }
    add(skill.shape == fig::SkillShape::kPike ? "pike_open" : "tuck_open",
        "trunk-thigh angle (median of the hold)",
        j.rotation.shape_hip_angle_deg,
        ua,
        frame);
  }
  // The opening before landing: a somersault in a tuck or pike opens (trunk–thigh past 135°) at
  // the end of its longest closed hold, this long before the feet touch. Not the last closed frame:
  // athletes meet the bed with the hips bent again (the s2mLab athlete lands at 120–135°).
  if (skill.shape != fig::SkillShape::kStraight && skill.quarter_somersaults >= 4) {
    const auto hip = both("hip_flexion", -1.0);
    int best_end = -1, best_length = 0, run = 0;
    for (int f = std::max(0, j.flight.takeoff_frame);
         f <= std::min(m.num_frames() - 1, j.flight.landing_frame);
         ++f) {
      const bool closed = m.time_s[f] < j.flight.landing_s && 180.0 - hip(f) <= 135.0;
      run = closed ? run + 1 : 0;
      if (closed && run > best_length) {
        best_length = run;
        best_end = f;
      }
    }
    if (best_end >= 0) {
      const int opened = std::min(best_end + 1, m.num_frames() - 1);
      add("late_opening",
          "opening before landing",
          j.flight.landing_s - m.time_s[opened],
          options.time_uncertainty_s,
          opened);
    }
  }
  // Travel on the bed, and height lost against the element before.
  add("travel",
      "landing from take-off",
      j.displacement_from_takeoff_m,
      options.position_uncertainty_m,
      j.flight.landing_frame);
  for (size_t k = jump; k-- > 0;) {
    if (a.jumps[k].partial()) continue;
    add("height_loss",
        "apex below the element before",
        a.jumps[k].apex_m() - j.apex_m(),
        options.position_uncertainty_m,
        frames[frames.size() / 2]);
    break;
  }
  return out;
}

}  // namespace acro::analysis
