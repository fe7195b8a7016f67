#include "sample_routine.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include <nlohmann/json.hpp>

#include "acro/athlete/athlete_profile.h"
#include "acro/base/demand.h"
#include "acro/design/posture_track.h"
#include "acro/design/skill_file.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/report/routine_report.h"

namespace acro::samples {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using SkillPlan = analysis::RoutineSkillPlan;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// ---------------------------------------------------------------------------------------------
// Poses: joint-angle vectors of the standard human (32 angles, standard_human.h signs: anatomical
// flexion of hip, shoulder and elbow negative, of the knee positive; foot positive = toes down).

class Poses {
 public:
  Poses() : n_(analysis::StandardJointDofCount()) {}
  VectorXd Zero() const { return VectorXd::Zero(n_); }
  void Set(VectorXd& q, std::string_view segment, int axis, double value) const {
    const int i = analysis::StandardJointDofIndex(segment, axis);
    ACRO_DEMAND(i >= 0);
    q[i] = value;
  }
  // Both sides; `mirror_sign` multiplies the left side's value (−1 for abduction about x).
  void Both(
      VectorXd& q, const std::string& segment, int axis, double right, double mirror = 1) const {
    Set(q, "r_" + segment, axis, right);
    Set(q, "l_" + segment, axis, mirror * right);
  }
  VectorXd Standing() const { return Zero(); }
  // The postures of the skill designer (acro/design/posture_track.h).
  VectorXd Takeoff() const { return analysis::PostureJoints(analysis::Posture::kTakeoff); }
  VectorXd Straight() const { return analysis::PostureJoints(analysis::Posture::kStraight); }
  VectorXd Tuck() const { return analysis::PostureJoints(analysis::Posture::kTuck); }
  VectorXd Pike() const { return analysis::PostureJoints(analysis::Posture::kPike); }
  VectorXd Landing() const { return analysis::PostureJoints(analysis::Posture::kLanding); }

 private:
  int n_;
};

// The fraction u of a posture track's transition where its blend (analysis::PostureBlend) reaches
// s (bisection: the blend is monotonic on [0, 1]).
double PostureBlendInverse(double s) {
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i)
    (analysis::PostureBlend(0.5 * (lo + hi)) < s ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

// Puts the faults into their skills' posture tracks (SampleFault says what each does).
void ApplyFaults(const Poses& P,
                 const std::vector<SampleFault>& faults,
                 std::vector<SkillPlan>& plans) {
  using Kind = SampleFault::Kind;
  const int r_thigh = analysis::StandardJointDofIndex("r_thigh", 0);
  // Hip flexion (positive) of a posture, and "closed": trunk–thigh at or below 135°.
  auto hip_flexion = [&](const VectorXd& q) { return -q[r_thigh]; };
  auto closed = [&](const VectorXd& q) { return 180.0 - hip_flexion(q) / kDeg <= 135.0; };
  for (const SampleFault& fault : faults) {
    ACRO_DEMAND(fault.skill >= 0 && fault.skill < int(plans.size()));
    SkillPlan& plan = plans[size_t(fault.skill)];
    std::vector<std::pair<double, VectorXd>> keys = plan.track.keys();
    ACRO_DEMAND(keys.size() >= 3);
    const size_t last = keys.size() - 1;
    switch (fault.kind) {
      case Kind::kKneesBent:
        for (size_t k = 1; k < last; ++k) {
          P.Set(keys[k].second,
                "r_shank",
                0,
                keys[k].second[analysis::StandardJointDofIndex("r_shank", 0)] + fault.value * kDeg);
          P.Set(keys[k].second,
                "l_shank",
                0,
                keys[k].second[analysis::StandardJointDofIndex("l_shank", 0)] + fault.value * kDeg);
        }
        break;
      case Kind::kLegsApart:  // abduction of the right thigh negative about x, the left mirrored
        for (size_t k = 1; k < last; ++k)
          P.Both(keys[k].second, "thigh", 2, -fault.value * kDeg, -1);
        break;
      case Kind::kArmsOut:
        for (size_t k = 1; k < last; ++k)
          P.Both(keys[k].second, "upper_arm", 2, -fault.value * kDeg, -1);
        break;
      case Kind::kTuckAngle:
        for (size_t k = 1; k < last; ++k)
          if (closed(keys[k].second))
            P.Both(keys[k].second, "thigh", 0, -(180.0 - fault.value) * kDeg);
        break;
      case Kind::kOpening: {
        // The last closed posture held, then one transition (0.2 s) into the landing posture,
        // timed so that the hips pass 135° `value` before landing (at plan.flight_s).
        size_t c = last;
        while (c > 0 && !closed(keys[c].second)) --c;
        ACRO_DEMAND(c > 0);
        const VectorXd hold = keys[c].second, land = keys[last].second;
        const double d = 0.2;
        const double u = PostureBlendInverse((hip_flexion(hold) - 45 * kDeg) /
                                             (hip_flexion(hold) - hip_flexion(land)));
        const double t_hold = plan.flight_s - fault.value - u * d;
        ACRO_DEMAND(t_hold > keys[c - 1].first);
        keys.resize(c);
        keys.emplace_back(t_hold, hold);
        keys.emplace_back(t_hold + d, land);
        break;
      }
      case Kind::kLanding:
        plan.landing_target_m += fault.offset_m;
        break;
    }
    analysis::PostureTrack track;
    for (auto& [t, q] : keys) track.Add(t, std::move(q));
    plan.track = std::move(track);
  }
}

std::vector<SkillPlan> MakePlans(const Poses& P, const SampleRoutineOptions& options) {
  std::vector<SkillPlan> plans;
  const double scale = options.flight_time_scale;
  auto add = [&](std::string name,
                 std::string code,
                 double T,
                 int dir,
                 double nominal_deg,
                 int halves,
                 double lean_deg,
                 double short_deg,
                 Vector2d target,
                 const std::vector<std::pair<double, VectorXd>>& keys) {
    SkillPlan s;
    s.name = std::move(name);
    s.fig_code = std::move(code);
    T *= scale;  // a higher or lower routine: every flight time scaled
    s.flight_s = T;
    s.direction = dir;
    s.nominal_rad = nominal_deg * kDeg;
    s.twist_halves = halves;
    s.takeoff_lean_rad = lean_deg * kDeg;
    s.landing_short_rad = short_deg * kDeg;
    s.landing_target_m = target + options.landing_offset_m;
    for (const auto& [frac, q] : keys) s.track.Add(frac * T, q);
    plans.push_back(std::move(s));
  };
  add("straight jump",
      "00",
      1.20,
      0,
      0,
      0,
      0,
      0,
      {0.05, -0.03},
      {{0, P.Takeoff()}, {0.45, P.Straight()}, {0.9, P.Landing()}});
  add("back somersault tuck",
      "40o",
      1.35,
      -1,
      360,
      0,
      15,
      30,
      {-0.12, 0.06},
      {{0, P.Takeoff()},
       {0.22, P.Tuck()},
       {0.62, P.Tuck()},
       {0.80, P.Straight()},
       {0.93, P.Landing()}});
  add("back somersault pike",
      "40<",
      1.40,
      -1,
      360,
      0,
      15,
      30,
      {-0.04, 0.24},
      {{0, P.Takeoff()},
       {0.22, P.Pike()},
       {0.60, P.Pike()},
       {0.80, P.Straight()},
       {0.93, P.Landing()}});
  add("barani straight",
      "41/",
      1.40,
      1,
      360,
      1,
      15,
      30,
      {0.21, 0.12},
      {{0, P.Takeoff()}, {0.25, P.Straight()}, {0.72, P.Straight()}, {0.93, P.Landing()}});
  add("full",
      "42/",
      1.50,
      -1,
      360,
      2,
      15,
      30,
      {0.03, -0.14},
      {{0, P.Takeoff()}, {0.22, P.Straight()}, {0.74, P.Straight()}, {0.93, P.Landing()}});
  add("double back somersault tuck",
      "800o",
      1.65,
      -1,
      720,
      0,
      30,
      45,
      {-0.14, -0.06},
      {{0, P.Takeoff()},
       {0.14, P.Tuck()},
       {0.76, P.Tuck()},
       {0.88, P.Straight()},
       {0.96, P.Landing()}});
  if (!options.skill_order.empty()) {
    std::vector<SkillPlan> ordered;
    for (int k : options.skill_order) {
      ACRO_DEMAND(k >= 0 && k < int(plans.size()));
      ordered.push_back(plans[size_t(k)]);
    }
    plans = std::move(ordered);
  }
  if (options.num_skills < int(plans.size())) plans.resize(size_t(std::max(options.num_skills, 1)));
  ApplyFaults(P, options.faults, plans);
  return plans;
}

double Round9(double x) {
  return std::round(x * 1e9) / 1e9;
}

// Gaps: a finger marker in the full's twist, an ASIS closed by the tuck of the back somersault,
// an elbow in the double, a toe on the bed.
void AddGaps(SampleRoutine& out) {
  capture::Trial& trial = out.trial;
  const double rate = out.options.point_rate_hz;
  auto gap = [&](const std::string& label, double t_centre, int frames) {
    const int m = trial.FindPoint(label);
    ACRO_DEMAND(m >= 0);
    const int first = int(std::lround(t_centre * rate)) - frames / 2;
    ACRO_DEMAND(first >= 0 && first + frames <= trial.num_frames);
    for (int fr = first; fr < first + frames; ++fr) {
      trial.position(fr, m).setConstant(std::nan(""));
      trial.residuals(m, fr) = -1.0f;
    }
  };
  auto during = [&](size_t flight, double frac) {
    return out.flights[flight].takeoff_s +
           frac * (out.flights[flight].landing_s - out.flights[flight].takeoff_s);
  };
  // (a routine of fewer skills keeps the gaps of the skills it has)
  if (out.flights.size() > 4) gap("RFIN", during(4, 0.45), 18);
  if (out.flights.size() > 1) gap("LASI", during(1, 0.45), 12);
  if (out.flights.size() > 5) gap("LELB", during(5, 0.55), 24);
  if (out.contacts.size() > 3)
    gap("RTOE", 0.5 * (out.contacts[3].start_s + out.contacts[3].end_s), 6);
}

}  // namespace

SampleRoutine MakeSampleRoutine(const std::filesystem::path& athlete_path,
                                const std::string& athlete_label,
                                const SampleRoutineOptions& options) {
  // The athlete on the bed, the routine's skills simulated.
  const analysis::AthleteProfile profile = analysis::ReadAthleteProfile(athlete_path);
  SampleRoutine out;
  static_cast<analysis::SimulatedRoutine&>(out) =
      analysis::SimulateRoutine(profile, MakePlans(Poses(), options), options);
  out.athlete_file = athlete_label;
  // The trial: markers by forward kinematics, the bed's corners, noise, and gaps.
  ui::RoutineMarkerOptions markers;
  markers.noise_sd_m = options.noise_sd_m;
  markers.noise_seed = options.noise_seed;
  out.trial = ui::MakeRoutineMarkerTrial(out, profile, markers);
  AddGaps(out);
  return out;
}

std::string SampleRoutine::TruthJson() const {
  using Json = nlohmann::ordered_json;  // keys in the order written
  // A vector with every coordinate rounded to 1e-9 (Round9).
  auto rounded = [](const Eigen::VectorXd& x) {
    Json values = Json::array();
    for (int a = 0; a < x.size(); ++a) values.push_back(Round9(x[a]));
    return values;
  };
  // The routine, the athlete and the bed.
  Json j;
  j["description"] =
      "Ground truth of the sample trampoline routine (tools/make_sample_routine.cc): exact, "
      "sub-frame times from the simulation, SI units, lab frame Z up.";
  j["athlete"] = athlete_file;
  j["mass_kg"] = Round9(mass_kg);
  j["gravity_m_per_s2"] = gravity_m_per_s2;
  j["point_rate_hz"] = options.point_rate_hz;
  j["num_frames"] = trial.num_frames;
  j["bed"] = {
      {"centre_m", {options.bed_centre_m.x(), options.bed_centre_m.y(), options.bed_centre_m.z()}},
      {"length_m", options.bed_length_m},
      {"width_m", options.bed_width_m},
      {"stiffness_N_per_m", options.bed_stiffness_N_per_m},
      {"damping_N_s_per_m", options.bed_damping_N_s_per_m}};
  // Every flight.
  j["flights"] = Json::array();
  for (const SampleFlightTruth& f : flights) {
    Json flight;
    flight["name"] = f.name;
    flight["fig_code"] = f.fig_code;
    flight["takeoff_s"] = Round9(f.takeoff_s);
    flight["landing_s"] = Round9(f.landing_s);
    flight["time_of_flight_s"] = Round9(f.landing_s - f.takeoff_s);
    flight["takeoff_vertical_velocity_m_per_s"] = Round9(f.takeoff_vertical_velocity_m_per_s);
    flight["apex_com_z_m"] = Round9(f.apex_com_z_m);
    flight["apex_above_bed_m"] = Round9(f.apex_com_z_m - options.bed_centre_m.z());
    flight["takeoff_com_m"] = rounded(f.takeoff_com_m);
    flight["landing_com_m"] = rounded(f.landing_com_m);
    flight["landing_feet_m"] = rounded(f.landing_feet_m);
    flight["landing_com_from_bed_centre_m"] =
        Round9((f.landing_com_m - options.bed_centre_m).head<2>().norm());
    flight["landing_from_takeoff_m"] = Round9((f.landing_com_m - f.takeoff_com_m).head<2>().norm());
    flight["takeoff_somersault_deg"] = Round9(f.takeoff_lean_rad / kDeg);
    flight["air_somersault_deg"] = Round9(f.air_somersault_rad / kDeg);
    flight["air_twist_deg"] = Round9(f.air_twist_rad / kDeg);
    flight["angular_momentum_N_m_s"] = rounded(f.H_Scm_W);
    j["flights"].push_back(std::move(flight));
  }
  // Every bed contact.
  j["contacts"] = Json::array();
  for (const SampleContactTruth& c : contacts) {
    j["contacts"].push_back({{"start_s", Round9(c.start_s)},
                             {"end_s", Round9(c.end_s)},
                             {"peak_bed_force_body_weights", Round9(c.peak_force_body_weights)},
                             {"max_depression_m", Round9(c.max_depression_m)}});
  }
  return j.dump(2) + "\n";
}

SampleFlightPhysics CheckSampleFlight(const SampleRoutine& routine, int flight) {
  return analysis::CheckRoutineFlight(routine.model,
                                      routine.q,
                                      routine.v,
                                      routine.options.point_rate_hz,
                                      routine.flights[size_t(flight)]);
}

}  // namespace acro::samples
