#include "acro/design/skill_from_code.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/orientation.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/base/progress.h"
#include "acro/design/posture_track.h"
#include "acro/dynamics/flight_rotation.h"

namespace acro::analysis {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// One segment of the schedule: a posture held until the nominal somersault angle (deg; the
// analysis' count: 45° of bed rotation before take-off, then the rotation in the air) reaches
// `nu_end`, or, for the last segment, until the landing is prepared. `somersault` is the
// somersault (1-based) whose twist a twisting segment turns.
struct Segment {
  Posture posture = Posture::kStraight;
  double nu_end_deg = 0.0;
  int somersault = 0;
  /// The somersault whose aerial twist this segment's asymmetric arm and hip action starts (0:
  /// none): the action is made in the 90° before that twist, in the posture held then, where the
  /// body's inertia about its front-back axis is smallest (a tuck or pike), so that it tilts the
  /// body most; the twisting posture after it is symmetric.
  int action_for = 0;
  /// The somersault whose twist this segment's asymmetric action stops (0: none): after a full or
  /// more in the first somersault of a tucked or piked multiple, the tilt that made the twist is
  /// taken out by an action the other way in the 90° after the twist, so the body stops twisting
  /// in the shape (the "twist-in" of a full-in or rudi-in).
  int stop_for = 0;
};

// What the shooting varies and what it aims at.
struct Unknowns {
  bool contact_twist = false;           // x[1] is the twist component of the momentum
  std::vector<int> aerial_somersaults;  // the somersaults whose twist an arm action starts
  std::vector<int> stop_somersaults;    // the somersaults whose twist an arm action stops
  std::vector<int> target_somersaults;  // the somersaults whose cumulative twist is a residual
};

// The schedule of a skill: segments over the nominal somersault angle, the postures' times, and
// the flight's numbers.
struct Plan {
  fig::FigSkill code;
  int somersaults = 0;
  int direction = 0;      // +1 forward, −1 backward, 0 a jump
  double twist_sign = 1;  // the twist's direction
  double T = 0, step = 0;
  double lean_rad = 0;        // somersault done on the bed before take-off
  double air_target_rad = 0;  // somersault to turn in the air (magnitude)
  std::vector<Segment> segments;
  Unknowns unknowns;
};

double SegmentEntryDuration(Posture p) {
  return p == Posture::kTuck || p == Posture::kPike ? 0.22 : 0.18;
}

Plan MakePlan(const fig::FigSkill& code, double T) {
  Plan plan;
  plan.code = code;
  plan.T = T;
  const int Q = code.quarter_somersaults;
  const int n = Q / 4;
  plan.somersaults = n;
  plan.direction = code.direction == fig::SomersaultDirection::kForward    ? 1
                   : code.direction == fig::SomersaultDirection::kBackward ? -1
                                                                           : 0;
  // The twist angle is about the body's long axis (CalcSomersaultTiltTwist, as the analysis counts
  // it): positive is the athlete's left. Forward skills twist left, backward ones right — not one
  // way in every skill as an athlete does: a designer option for that was tried and left out
  // (822/ twisting left found no flight, docs/skill-design.md, "Skills from their code").
  plan.twist_sign = plan.direction < 0 ? -1.0 : 1.0;
  if (n == 0) {
    plan.lean_rad = 0;
    plan.air_target_rad = 0;
  } else {
    const double lean_deg = n == 1 ? 15.0 : 30.0, short_deg = n == 1 ? 30.0 : 45.0;
    plan.lean_rad = lean_deg * kDeg;
    plan.air_target_rad = (360.0 * n - lean_deg - short_deg) * kDeg;
  }
  const Posture shape = code.shape == fig::SkillShape::kTuck   ? Posture::kTuck
                        : code.shape == fig::SkillShape::kPike ? Posture::kPike
                                                               : Posture::kStraight;
  std::vector<Segment>& s = plan.segments;
  if (n == 0) {
    // Jumps: the shape (or straight, or twisting) in the middle of the flight; ends by time.
    s.push_back({code.total_half_twists() > 0 ? Posture::kTwist : shape, 0.0, 1});
  }
  for (int k = 1; k <= n; ++k) {
    const int d = code.half_twists[size_t(k - 1)];
    const double lo = 360.0 * (k - 1), hi = 360.0 * k;
    if (d == 0) {
      s.push_back({shape, hi, k});
    } else if (shape == Posture::kStraight) {
      s.push_back({Posture::kTwist, hi, k});
    } else if (n == 1 || k == n) {
      // The half twist out of a twist-in (821o, 831<) starts 150° into the last somersault, not
      // 90°: with 90° the shape, entered at the end of the first somersault, was shown for 135°
      // of somersault, 9–11 % of the flight, and our own analysis read the skills as straight.
      const bool twist_in = n > 1 && code.half_twists[0] >= 2;
      s.push_back({shape, lo + (n == 1 ? 180.0 : twist_in ? 150.0 : 90.0), k});
      s.push_back({Posture::kTwist, hi, k});
    } else if (k == 1) {
      // A half twist in: twisting through the first half somersault. A full or more: twisting
      // through 270° of it, the shape entered in its last 90° with an action that stops the twist.
      // (The shape entered in the last 45° closed the hips at 1 600–1 800°/s and our own analysis
      // found 831<'s marker errors over its 4 cm limit; 270° found no flight for 821o or 831<
      // until the twist-ins got their own shooting.)
      s.push_back({Posture::kTwist, lo + (d >= 2 ? 270.0 : 180.0), k});
      if (d >= 2) s.push_back({shape, hi, k, 0, k});
      s.push_back({shape, hi, k});
    } else {
      s.push_back({shape, lo + 90.0, k});
      s.push_back({Posture::kTwist, lo + 270.0, k});
      s.push_back({shape, hi, k});
    }
  }
  // A held tuck or pike opens (kick-out) three quarters into the last somersault.
  if (n > 0 && (s.back().posture == Posture::kTuck || s.back().posture == Posture::kPike)) {
    s.back().nu_end_deg = 360.0 * (n - 1) + 270.0;
    s.push_back({Posture::kStraight, 360.0 * n, n});
  }
  // Merge neighbours with the same posture (twists of different somersaults stay apart).
  std::vector<Segment> merged;
  for (const Segment& g : s) {
    if (!merged.empty() && merged.back().posture == g.posture &&
        merged.back().stop_for == g.stop_for &&
        (g.posture != Posture::kTwist || merged.back().somersault == g.somersault)) {
      merged.back().nu_end_deg = g.nu_end_deg;
    } else {
      merged.push_back(g);
    }
  }
  // Each twist that starts in the air is started by an action in the 90° before it.
  s.clear();
  for (size_t i = 0; i < merged.size(); ++i) {
    const Segment& g = merged[i];
    if (g.posture == Posture::kTwist && g.somersault > 1 && !s.empty()) {
      Segment& before = s.back();
      const double start = s.size() > 1 ? s[s.size() - 2].nu_end_deg : 45.0;
      const double split =
          std::max(start + 0.5 * (before.nu_end_deg - start), before.nu_end_deg - 90.0);
      Segment action = before;
      action.action_for = g.somersault;
      before.nu_end_deg = split;
      s.push_back(action);
    }
    s.push_back(g);
  }

  // Unknowns: the somersault momentum; the contact twist when the first somersault (or the
  // jump) twists; an aerial action for each later twisting somersault.
  Unknowns& u = plan.unknowns;
  for (int k = 1; k <= std::max(n, 1); ++k) {
    if (code.half_twists[size_t(k - 1)] == 0) continue;
    u.target_somersaults.push_back(k);
    if (k == 1) {
      u.contact_twist = true;
      for (const Segment& g : s)
        if (g.stop_for == 1) u.stop_somersaults.push_back(1);
    } else {
      u.aerial_somersaults.push_back(k);
    }
  }
  return plan;
}

// The flight of one set of unknowns.
struct Flight {
  std::vector<double> t;
  std::vector<Eigen::Quaterniond> q_WB;
  VectorXd somersault, tilt, twist;     // unwrapped, relative to heading 0
  Vector3d H_Scm_W = Vector3d::Zero();  // the take-off angular momentum about the COM
  PostureTrack track;
  double prepare_start_s = 0;  // the landing posture's transition begins
  /// The joint motion's inertia and momentum over the flight (shared by the flights that differ
  /// in their take-off momentum only).
  std::shared_ptr<const dynamics::JointMotionSamples> joint_motion;
};

class Shooter {
 public:
  Shooter(const AthleteProfile& athlete, Plan plan)
      : model_(MakeStandardHumanModel(MakeAthleteBody(athlete))), plan_(std::move(plan)) {
    mass_ = model_.total_mass();
    // The schedule's first times: the nominal angle spread evenly over the flight.
    const double nu0 = 45.0, nu1 = 45.0 + plan_.air_target_rad / kDeg;
    for (const Segment& s : plan_.segments) {
      const double f = plan_.somersaults == 0 ? 0.5 : (s.nu_end_deg - nu0) / (nu1 - nu0);
      segment_end_s_.push_back(std::clamp(f, 0.0, 1.0) * plan_.T);
    }
  }

  const dynamics::Model<double>& model() const { return model_; }
  double mass() const { return mass_; }
  int simulations() const { return simulations_.load(); }

  int num_unknowns() const {
    return 1 + (plan_.unknowns.contact_twist ? 1 : 0) +
           static_cast<int>(plan_.unknowns.aerial_somersaults.size()) +
           static_cast<int>(plan_.unknowns.stop_somersaults.size());
  }

  // The action that stops the twist of `somersault` (after the aerial actions in x).
  double StopAction(const VectorXd& x, int somersault) const {
    const auto& a = plan_.unknowns.stop_somersaults;
    const int first = 1 + (plan_.unknowns.contact_twist ? 1 : 0) +
                      static_cast<int>(plan_.unknowns.aerial_somersaults.size());
    for (size_t i = 0; i < a.size(); ++i)
      if (a[i] == somersault) return x[first + static_cast<int>(i)];
    return 0.0;
  }

  double Action(const VectorXd& x, int somersault) const {
    const auto& a = plan_.unknowns.aerial_somersaults;
    const int first = 1 + (plan_.unknowns.contact_twist ? 1 : 0);
    for (size_t i = 0; i < a.size(); ++i)
      if (a[i] == somersault) return x[first + static_cast<int>(i)];
    return 0.0;
  }

  // The postures over time for the unknowns x (the aerial actions) and the current segment times.
  PostureTrack MakeTrack(const VectorXd& x, double* prepare_start) const {
    const double T = plan_.T;
    PostureTrack track;
    track.Add(0.0, PostureJoints(Posture::kTakeoff));
    const std::vector<Segment>& s = plan_.segments;
    const double prepare = std::min(0.24, 0.2 * T);  // into the landing posture
    const double landing_reached = T - 0.04;
    // Segment i spans [start_i, end_i]; posture transitions are centred on the boundaries.
    std::vector<double> ends = segment_end_s_;
    ends.back() = landing_reached - prepare;
    // The kick-out lasts at least the straight posture's entry: a double's tuck or pike, opened
    // three quarters into its last somersault, would otherwise open in 40 ms at the start of the
    // landing preparation (the straight body turns its last quarter slowly); such a kick-out made
    // an impossible joint speed and left Model 1 at 5 % momentum variation in 800o. (A single's
    // kick-out, 90° before its landing, has the time.)
    if (plan_.somersaults >= 2 && s.size() >= 2 && s.back().posture == Posture::kStraight &&
        (s[s.size() - 2].posture == Posture::kTuck || s[s.size() - 2].posture == Posture::kPike))
      ends[s.size() - 2] =
          std::min(ends[s.size() - 2], ends.back() - SegmentEntryDuration(Posture::kStraight));
    double previous_end = 0.0;
    for (size_t i = 0; i < s.size(); ++i) {
      const VectorXd joints = PostureJoints(s[i].posture,
                                            s[i].action_for > 0 ? Action(x, s[i].action_for)
                                            : s[i].stop_for > 0 ? StopAction(x, s[i].stop_for)
                                                                : 0.0);
      if (i == 0) {
        const double entry = std::min(SegmentEntryDuration(s[0].posture), 0.6 * ends[0]);
        track.Add(std::max(entry, 0.05), joints);
      } else {
        const double b = previous_end;
        const double span_before = b - (i == 1 ? 0.0 : ends[i - 2]);
        const double span_after = ends[i] - b;
        const double d = std::max(
            0.04,
            std::min({SegmentEntryDuration(s[i].posture), 0.8 * span_before, 0.8 * span_after}));
        const double from = std::max(b - d / 2, track.keys().back().first);
        track.Add(from, track.keys().back().second);
        track.Add(std::max(b + d / 2, from + 0.02), joints);
      }
      previous_end = ends[i];
    }
    const double from = std::max(ends.back(), track.keys().back().first);
    track.Add(from, track.keys().back().second);
    track.Add(std::max(landing_reached, from + 0.05), PostureJoints(Posture::kLanding));
    if (prepare_start) *prepare_start = from;
    return track;
  }

  // The flight of the unknowns x; `same_joints`, when given, is a flight whose joint motion x
  // leaves unchanged (x differs from its unknowns in the take-off momentum only).
  Flight Simulate(const VectorXd& x, const Flight* same_joints = nullptr) {
    ++simulations_;
    Flight f;
    if (same_joints != nullptr) {
      f.track = same_joints->track;
      f.prepare_start_s = same_joints->prepare_start_s;
      f.joint_motion = same_joints->joint_motion;
    } else {
      f.track = MakeTrack(x, &f.prepare_start_s);
      const PostureTrack& track = f.track;
      f.joint_motion =
          std::make_shared<const dynamics::JointMotionSamples>(dynamics::SampleJointMotion(
              model_,
              plan_.T,
              static_cast<int>(std::lround(plan_.T / plan_.step)),
              [&track](const double& t,
                       dynamics::VectorXRef<double> qq,
                       dynamics::VectorXRef<double> qd,
                       dynamics::VectorXRef<double> qdd) { track.Eval(t, qq, qd, qdd); }));
    }
    const Eigen::Quaterniond q0(
        Eigen::AngleAxisd(plan_.direction * plan_.lean_rad, Vector3d::UnitY()));
    f.H_Scm_W = Momentum(x);
    f.q_WB = dynamics::SimulateFlightRotation(*f.joint_motion, q0, f.H_Scm_W);
    const size_t m = f.q_WB.size();
    f.t.resize(m);
    f.somersault.resize(Eigen::Index(m));
    f.tilt.resize(Eigen::Index(m));
    f.twist.resize(Eigen::Index(m));
    for (size_t i = 0; i < m; ++i) {
      f.t[i] = f.joint_motion->step_s * static_cast<double>(i);
      const SomersaultTiltTwist a = CalcSomersaultTiltTwist(f.q_WB[i].toRotationMatrix());
      const auto k = Eigen::Index(i);
      f.somersault[k] =
          i == 0 ? a.somersault_rad : UnwrapAngle(f.somersault[k - 1], a.somersault_rad);
      f.twist[k] = i == 0 ? a.twist_rad : UnwrapAngle(f.twist[k - 1], a.twist_rad);
      f.tilt[k] = a.tilt_rad;
    }
    return f;
  }

  Vector3d Momentum(const VectorXd& x) const {
    const Matrix3d R_lean =
        Eigen::AngleAxisd(plan_.direction * plan_.lean_rad, Vector3d::UnitY()).toRotationMatrix();
    Vector3d H = x[0] * Vector3d::UnitY();
    if (plan_.unknowns.contact_twist) H += x[1] * (R_lean * Vector3d::UnitZ());
    return H;
  }

  // The nominal somersault angle (deg) over the flight: 45° of bed rotation, then the air's.
  VectorXd Nominal(const Flight& f) const {
    const double sign = plan_.direction == 0 ? 1.0 : plan_.direction;
    return ((sign * (f.somersault.array() - f.somersault[0])) / kDeg + 45.0).matrix();
  }

  // The time (s) at which the nominal angle first reaches nu (deg), by linear interpolation; the
  // landing when it never does.
  static double TimeAt(const Flight& f, const VectorXd& nu, double nu_deg) {
    for (Eigen::Index i = 1; i < nu.size(); ++i)
      if (nu[i] >= nu_deg && nu[i - 1] < nu_deg) {
        const double w = (nu_deg - nu[i - 1]) / (nu[i] - nu[i - 1]);
        return f.t[size_t(i - 1)] + w * (f.t[size_t(i)] - f.t[size_t(i - 1)]);
      }
    return f.t.back();
  }
  static double TwistAt(const Flight& f, double t) {
    for (size_t i = 1; i < f.t.size(); ++i)
      if (f.t[i] >= t) {
        const double w = (t - f.t[i - 1]) / (f.t[i] - f.t[i - 1]);
        return f.twist[Eigen::Index(i - 1)] +
               w * (f.twist[Eigen::Index(i)] - f.twist[Eigen::Index(i - 1)]);
      }
    return f.twist[f.twist.size() - 1];
  }

  VectorXd Residual(const Flight& f) const {
    const Unknowns& u = plan_.unknowns;
    VectorXd r(num_unknowns());
    const double air = f.somersault[f.somersault.size() - 1] - f.somersault[0];
    r[0] = plan_.direction == 0 ? 0.0 : air - plan_.direction * plan_.air_target_rad;
    const VectorXd nu = Nominal(f);
    const double twist0 = f.twist[0];
    int row = 1;
    for (int k : u.target_somersaults) {
      int halves = 0;
      for (int j = 0; j < k; ++j) halves += plan_.code.half_twists[size_t(j)];
      const double t = k >= plan_.somersaults ? f.t.back() : TimeAt(f, nu, 360.0 * k);
      r[row++] = TwistAt(f, t) - twist0 - plan_.twist_sign * halves * kPi;
    }
    // A stopped twist is done by the end of its stop. (The stop ends where its somersault's twist
    // is counted, so this row repeats that one: the system is rank-deficient by one and Newton's
    // steps are least-norm, through the complete orthogonal decomposition; the repeated row
    // weighs the first somersault's twist twice, which is what let the shooting turn 831<.)
    for (int k : u.stop_somersaults) {
      int halves = 0;
      for (int j = 0; j < k; ++j) halves += plan_.code.half_twists[size_t(j)];
      double nu_end = 0;
      for (const Segment& g : plan_.segments)
        if (g.stop_for == k) nu_end = g.nu_end_deg;
      r[row++] = TwistAt(f, TimeAt(f, nu, nu_end)) - twist0 - plan_.twist_sign * halves * kPi;
    }
    return r;
  }

  // The segment ends from a flight: the times its nominal angle reaches them. With `whole_body`
  // the angle is the whole body's somersault scaled to the pelvis' total, which grows smoothly
  // where the pelvis' angle runs back for a moment as a tuck or pike opens (the legs swing down,
  // the pelvis turns back: 507° → 501° → 513° in 821o), so that the times do not jump.
  void UpdateSchedule(const Flight& f, bool whole_body = false) {
    if (plan_.somersaults == 0) return;
    VectorXd nu = Nominal(f);
    if (whole_body) {
      // ∫ ω_y dt by the trapezoidal rule, ω = R I_Scm⁻¹ Rᵀ H the whole body's angular velocity.
      VectorXd progress(nu.size());
      double previous = 0;
      for (Eigen::Index i = 0; i < progress.size(); ++i) {
        const Matrix3d R = f.q_WB[size_t(i)].toRotationMatrix();
        const double w =
            (R * (f.joint_motion->I_Scm_B_inverse[2 * size_t(i)] * (R.transpose() * f.H_Scm_W)))[1];
        progress[i] = i == 0 ? 0.0 : progress[i - 1] + 0.5 * plan_.step * (previous + w);
        previous = w;
      }
      const double total = progress[progress.size() - 1];
      nu = (45.0 + (progress.array() / total) * (nu[nu.size() - 1] - 45.0)).matrix();
    }
    for (size_t i = 0; i + 1 < plan_.segments.size(); ++i)
      segment_end_s_[i] = TimeAt(f, nu, plan_.segments[i].nu_end_deg);
  }

  // The schedule from the flight without its twist: the somersault momentum alone, the postures
  // without their arm actions, the segment ends moved to where that flight's whole-body angle
  // reaches theirs until they stay (to 1 µs; 7–15 passes). Returns the somersault momentum.
  double FitScheduleWithoutTwist(double x0) {
    VectorXd x = VectorXd::Zero(num_unknowns());
    x[0] = x0;
    for (int pass = 0; pass < 30; ++pass) {
      const Flight base = Simulate(x);
      Flight f = base;
      // The somersault momentum by Newton on row 0 (the joints unchanged: cheap flights).
      for (int it = 0; it < 20; ++it) {
        const double r0 = Residual(f)[0];
        if (std::abs(r0) < 1e-10) break;
        const double h = 1e-4 * std::max(1.0, std::abs(x[0]));
        VectorXd xp = x;
        xp[0] += h;
        const double d = (Residual(Simulate(xp, &base))[0] - r0) / h;
        x[0] -= r0 / d;
        f = Simulate(x, &base);
      }
      const std::vector<double> before = segment_end_s_;
      UpdateSchedule(f, true);
      double change = 0;
      for (size_t i = 0; i + 1 < before.size(); ++i)
        change = std::max(change, std::abs(segment_end_s_[i] - before[i]));
      if (change < 1e-6) break;
    }
    return x[0];
  }

  static constexpr double kMaxAction = 1.6;  // an arm cannot go past overhead
  bool Bounded(int j) const { return j >= 1 + (plan_.unknowns.contact_twist ? 1 : 0); }

  // Newton with a forward-difference Jacobian and halved steps; an arm action at its bound is
  // held there while the step would push it further.
  VectorXd Shoot(VectorXd x,
                 const SkillFromCodeOptions& options,
                 bool break_stalls,
                 bool careful,
                 double* residual) {
    Flight flight = Simulate(x);
    VectorXd r = Residual(flight);
    const int n = num_unknowns();
    double best = r.cwiseAbs().maxCoeff();
    int stalled = 0;
    for (int it = 0; it < 40 && r.cwiseAbs().maxCoeff() > 1e-7; ++it) {
      // A pass that no longer gains 0.1 % in four iterations has stalled against the schedule
      // (an arm action at its bound, a posture change at the wrong angle): the schedule's
      // update, not more iterations, moves it on.
      if (r.cwiseAbs().maxCoeff() < 0.999 * best) {
        best = r.cwiseAbs().maxCoeff();
        stalled = 0;
      } else if (++stalled >= 4 && break_stalls) {
        break;
      }
      if (options.cancelled && options.cancelled()) throw Cancelled("design: cancelled");
      // The forward-difference Jacobian, its columns on two threads (each a flight simulation).
      Eigen::MatrixXd J(r.size(), n);
      auto column = [&](int j) {
        const double h = (j == 0 ? 1e-4 : 1e-5) * std::max(1.0, std::abs(x[j]));
        VectorXd xp = x;
        xp[j] += h * (Bounded(j) && x[j] + h > kMaxAction ? -1 : 1);
        J.col(j) = (Residual(Simulate(xp, Bounded(j) ? nullptr : &flight)) - r) / (xp[j] - x[j]);
      };
      {
        std::thread odd([&] {
          for (int j = 1; j < n; j += 2) column(j);
        });
        for (int j = 0; j < n; j += 2) column(j);
        odd.join();
      }
      if (plan_.direction == 0) J.row(0).setZero(), J(0, 0) = 1.0;  // a jump: x[0] stays 0
      VectorXd dx = -J.completeOrthogonalDecomposition().solve(r);
      for (int j = 0; j < n; ++j)
        if (Bounded(j) && std::abs(x[j]) >= kMaxAction - 1e-12 && dx[j] * x[j] > 0) {
          Eigen::MatrixXd Jf = J;
          Jf.col(j).setZero();
          dx = -Jf.completeOrthogonalDecomposition().solve(r);
          dx[j] = 0;
        }
      // Careful steps stay in a trust region (the momentum moves by at most a fifth, an arm action
      // by 0.5 rad) and a pass ends where no halved step lowers the residual; otherwise the tenth
      // halving is taken whatever it gives (the drift that the passes of the twist-free and
      // half-out skills rely on).
      double step = 1.0;
      if (careful) {
        double scale = 1.0;
        for (int j = 0; j < n; ++j) {
          const double limit = Bounded(j) ? 0.5 : 0.2 * std::max(std::abs(x[j]), 5.0);
          if (std::abs(dx[j]) > limit) scale = std::min(scale, limit / std::abs(dx[j]));
        }
        step = scale;
      }
      bool moved = false;
      for (int back = 0; back < 10; ++back) {
        VectorXd xt = x + step * dx;
        for (int j = 0; j < n; ++j)
          if (Bounded(j)) xt[j] = std::clamp(xt[j], -kMaxAction, kMaxAction);
        Flight ft = Simulate(xt);
        const VectorXd rt = Residual(ft);
        // (a step into a flight that does not integrate, NaN, is never taken)
        if (rt.allFinite() && (rt.norm() < r.norm() || (back == 9 && !careful))) {
          x = xt;
          r = rt;
          flight = std::move(ft);
          moved = true;
          break;
        }
        step *= 0.5;
      }
      if (careful && !moved) break;
      if (options.progress) {
        std::string xs;
        for (int j = 0; j < n; ++j) xs += fmt::format(" {:.4g}", x[j]);
        options.progress(fmt::format("shooting iteration {}: largest residual {:.3g}° at x ={}",
                                     it + 1,
                                     r.cwiseAbs().maxCoeff() / kDeg,
                                     xs));
      }
    }
    *residual = r.cwiseAbs().maxCoeff();
    return x;
  }

  // A first guess: the somersault momentum from a mean inertia, the contact twist from the
  // twist's rate in the twisting posture, each aerial action's sign from a probe either way.
  // (With `somersault_momentum`, that instead, and the contact twist scanned for the first
  // somersault's twist.)
  double MomentumGuess() const {
    const double inertia = plan_.code.shape == fig::SkillShape::kStraight ? 11.0 : 7.0;
    return plan_.direction * inertia * (plan_.air_target_rad + plan_.lean_rad) / plan_.T;
  }
  VectorXd Guess(double somersault_momentum = 0) {
    const int n = num_unknowns();
    VectorXd x = VectorXd::Zero(n);
    const double T = plan_.T;
    x[0] = somersault_momentum != 0 ? somersault_momentum : MomentumGuess();
    int row = 1;
    if (plan_.unknowns.contact_twist) {
      const double halves = plan_.code.half_twists[0];
      x[row++] = plan_.twist_sign * 1.3 * halves * kPi / (0.5 * T);
      if (somersault_momentum != 0) {
        // The contact twist that turns the first somersault's twist without the arms: a scan of
        // 0.1–2.5 times the estimate (the joints unchanged: cheap flights).
        const Flight base = Simulate(x);
        const double estimate = x[1];
        double best = estimate, best_r = 1e300;
        for (int i = 1; i <= 48; ++i) {
          VectorXd xt = x;
          xt[1] = estimate * 0.05 * (i + 1);
          const double r1 = std::abs(Residual(Simulate(xt, &base))[1]);
          if (r1 < best_r) {
            best_r = r1;
            best = xt[1];
          }
        }
        x[1] = best;
      }
    }
    for (; row < n; ++row) {
      double best = 0, best_norm = 1e300;
      for (double a : {0.8, -0.8}) {
        VectorXd xt = x;
        xt[row] = a;
        const double norm = Residual(Simulate(xt)).norm();
        if (norm < best_norm) {
          best = a;
          best_norm = norm;
        }
      }
      x[row] = best;
    }
    return x;
  }

 private:
  dynamics::Model<double> model_;
  Plan plan_;
  double mass_ = 0;
  std::vector<double> segment_end_s_;
  std::atomic<int> simulations_{0};
};

// Keyframe times: every posture key, then even parts of any interval whose orientation or root
// angles change by more than `limit_deg`; on the simulation's grid.
std::vector<size_t> KeyframeSamples(const Flight& f, double limit_deg) {
  const double h = f.t[1] - f.t[0];
  const size_t last = f.t.size() - 1;
  std::vector<size_t> idx{0, last};
  for (const auto& [t, joints] : f.track.keys()) {
    const auto i = static_cast<size_t>(std::llround(t / h));
    if (i > 0 && i < last) idx.push_back(i);
  }
  std::sort(idx.begin(), idx.end());
  idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
  // Drop keys closer than 40 ms to the one before (the last one stays).
  std::vector<size_t> kept{idx.front()};
  for (size_t j = 1; j < idx.size(); ++j)
    if (idx[j] == last || double(idx[j] - kept.back()) * h >= 0.04) kept.push_back(idx[j]);
  if (kept.size() > 2 && double(last - kept[kept.size() - 2]) * h < 0.04)
    kept.erase(kept.end() - 2);
  auto far = [&](size_t a, size_t b) {
    const double limit = limit_deg * kDeg;
    return f.q_WB[a].angularDistance(f.q_WB[b]) > limit ||
           std::abs(f.somersault[Eigen::Index(b)] - f.somersault[Eigen::Index(a)]) > limit ||
           std::abs(f.twist[Eigen::Index(b)] - f.twist[Eigen::Index(a)]) > limit;
  };
  std::vector<size_t> out{kept.front()};
  for (size_t j = 1; j < kept.size(); ++j) {
    const size_t a = out.back(), b = kept[j];
    const int parts = [&] {
      for (int p = 1; p < 64; ++p) {
        bool ok = true;
        for (int s = 0; s < p && ok; ++s) {
          const size_t lo = a + (b - a) * size_t(s) / size_t(p);
          const size_t hi = a + (b - a) * size_t(s + 1) / size_t(p);
          ok = !far(lo, hi);
        }
        if (ok) return p;
      }
      return 64;
    }();
    for (int s = 1; s <= parts; ++s) out.push_back(a + (b - a) * size_t(s) / size_t(parts));
  }
  return out;
}

std::string KeyframeName(const Plan& plan, const Flight& f, size_t i, size_t last) {
  if (i == 0) return "take-off";
  if (i == last) return "landing";
  // The posture the track is in or moving to at this instant, and the somersaults done.
  const double t = f.t[i];
  Posture now = Posture::kTakeoff;
  double best = 1e300;
  const VectorXd q = f.track.At(t);
  for (Posture p : {Posture::kTakeoff,
                    Posture::kStraight,
                    Posture::kTuck,
                    Posture::kPike,
                    Posture::kTwist,
                    Posture::kLanding}) {
    const double d = (PostureJoints(p) - q).norm();
    if (d < best) {
      best = d;
      now = p;
    }
  }
  const double turns = std::abs(f.somersault[Eigen::Index(i)] - f.somersault[0]) / (2 * kPi);
  const double twists = std::abs(f.twist[Eigen::Index(i)] - f.twist[0]) / (2 * kPi);
  std::string name = PostureName(now);
  if (plan.somersaults > 0) name += fmt::format(", {:.2f} somersaults", turns);
  if (twists > 0.05) name += fmt::format(", {:.2f} twists", twists);
  return name;
}

}  // namespace

double DefaultFlightTime(const fig::FigSkill& skill) {
  return BaseFlightTime(skill) + 0.05 * skill.total_half_twists();
}

double BaseFlightTime(const fig::FigSkill& skill) {
  switch (skill.quarter_somersaults / 4) {
    case 0:
      return 1.2;
    case 1:
      return 1.45;
    case 2:
      return 1.65;
    case 3:
      return 1.85;
    default:
      return 2.0;
  }
}

namespace {

// Which codes are designed: feet to feet, up to four somersaults, up to 8 half twists in one.
void CheckDesignable(const fig::FigSkill& code, const std::string& where) {
  if (code.quarter_somersaults % 4 != 0)
    throw InputError("",
                     where,
                     std::to_string(code.quarter_somersaults) +
                         " quarter somersaults land on the back, front or seat; only feet-to-feet "
                         "skills (multiples of 4) are designed from their code");
  if (code.quarter_somersaults > 16)
    throw InputError("", where, "more than four somersaults are not designed");
  if (code.quarter_somersaults == 0 && code.shape != fig::SkillShape::kStraight &&
      code.total_half_twists() > 0)
    throw InputError("", where, "a tuck or pike jump with a twist is not designed");
  for (int d : code.half_twists)
    if (d > 8) throw InputError("", where, "more than 8 half twists in one somersault");
}

// The flight as the analysis would count it: somersault, twist and its direction, half twists per
// somersault, tilt, the time left to prepare the landing.
void DescribeFlight(const fig::FigSkill& code,
                    const Plan& plan,
                    const Flight& flight,
                    const VectorXd& nu,
                    double T,
                    SkillFromCodeResult* out) {
  SkillFromCodeResult& result = *out;
  // The flight as the analysis would count it.
  const Eigen::Index last = flight.somersault.size() - 1;
  result.air_somersault_rad = flight.somersault[last] - flight.somersault[0];
  result.air_twist_rad = flight.twist[last] - flight.twist[0];
  result.twist_direction = TwistDirectionOf(code.total_half_twists(), result.air_twist_rad);
  {
    double before = 0;
    for (int k = 1; k <= std::max(plan.somersaults, 1); ++k) {
      const double t =
          k >= plan.somersaults ? flight.t.back() : Shooter::TimeAt(flight, nu, 360.0 * k);
      const double tw = std::abs(Shooter::TwistAt(flight, t) - flight.twist[0]);
      result.half_twists_per_somersault.push_back((tw - before) / kPi);
      before = tw;
    }
  }
  result.max_tilt_rad = flight.tilt.cwiseAbs().maxCoeff();
  result.landing_tilt_rad = std::abs(flight.tilt[last]);
  // The time left to prepare the landing: from the end of the twist (its last 20° left) or of the
  // opening (the landing posture's transition starts), whichever is later.
  double done = flight.prepare_start_s;
  if (code.total_half_twists() > 0) {
    for (Eigen::Index i = last; i >= 0; --i)
      if (std::abs(flight.twist[last] - flight.twist[i]) > 20.0 * kDeg) {
        done = std::max(done, flight.t[size_t(i)]);
        break;
      }
  }
  result.time_to_prepare_landing_s = T - done;
}

// Can this athlete do it? Each limit passed, one line.
void CheckFeasible(const SkillFromCodeOptions& options, double T, SkillFromCodeResult* out) {
  SkillFromCodeResult& result = *out;
  // Can this athlete do it?
  if (T > options.max_flight_time_s)
    result.not_feasible.push_back(
        fmt::format("needs {:.2f} s of flight (take-off {:.2f} m/s), more than the {:.2f} s this "
                    "athlete reaches",
                    T,
                    result.takeoff_vertical_velocity_mps,
                    options.max_flight_time_s));
  if (result.normalized_somersault_momentum > options.max_normalized_somersault_momentum)
    result.not_feasible.push_back(fmt::format(
        "needs a somersault angular momentum of {:.1f} kg·m²/s ({:.3f} per kg and m² of height), "
        "more than elite trampolinists produce ({:.3f})",
        result.somersault_momentum,
        result.normalized_somersault_momentum,
        options.max_normalized_somersault_momentum));
  if (result.max_tilt_rad > options.max_tilt_deg * kDeg)
    result.not_feasible.push_back(
        fmt::format("needs a tilt of {:.1f}° to twist in time, more than {:.0f}°",
                    result.max_tilt_rad / kDeg,
                    options.max_tilt_deg));
  if (result.time_to_prepare_landing_s < options.min_time_to_prepare_landing_s)
    result.not_feasible.push_back(fmt::format(
        "leaves {:.2f} s between the end of the rotation and the landing, less than {:.2f} s",
        result.time_to_prepare_landing_s,
        options.min_time_to_prepare_landing_s));
}

// The keyframes: samples of the flight.
void MakeKeyframes(const fig::FigSkill& code,
                   const Plan& plan,
                   const Flight& flight,
                   double T,
                   double g,
                   const std::filesystem::path& athlete_path,
                   const AthleteProfile& athlete,
                   SkillFromCodeResult* out) {
  Skill& skill = out->skill;
  skill.fig_code = fig::FormatFigCode(code);
  const std::string common = fig::FigSkillName(code);
  skill.name = common.empty() ? skill.fig_code : common + " (" + skill.fig_code + ")";
  skill.source = "generated from " + skill.fig_code;
  skill.athlete_path = athlete_path;
  skill.athlete = athlete;
  skill.takeoff_com_velocity_mps = Vector3d(0, 0, g * T / 2);
  skill.flight_time_s = T;
  skill.gravity_mps2 = g;
  // At most 100° apart (60° in triples and more: with 100° Model 1 left 2.8 % of momentum
  // variation in 12001o, with 60° 0.02 %; in singles 60° made Model 1 stop worse, 13 % in 40/).
  const std::vector<size_t> samples = KeyframeSamples(flight, plan.somersaults >= 3 ? 60.0 : 100.0);
  for (size_t j = 0; j < samples.size(); ++j) {
    const size_t i = samples[j];
    SkillKeyframe k;
    k.name = KeyframeName(plan, flight, i, flight.t.size() - 1);
    k.somersault_rad = flight.somersault[Eigen::Index(i)];
    k.tilt_rad = flight.tilt[Eigen::Index(i)];
    k.twist_rad = flight.twist[Eigen::Index(i)];
    k.joint_angles_rad = flight.track.At(flight.t[i]);
    k.time_s = j + 1 == samples.size() ? T : flight.t[i];
    if (j == 0) k.time_s = 0.0;
    skill.keyframes.push_back(std::move(k));
  }
}

}  // namespace

SkillFromCodeResult DesignSkillFromCode(const std::string& code_text,
                                        const std::filesystem::path& athlete_path,
                                        const SkillFromCodeOptions& options) {
  const fig::FigSkill code = fig::ParseFigCode(code_text);
  const std::string where = "FIG code '" + code_text + "'";
  CheckDesignable(code, where);

  SkillFromCodeResult result;
  result.code = code;
  result.difficulty = fig::CalcFigDifficulty(code);
  const AthleteProfile athlete = ReadAthleteProfile(athlete_path);
  double T = DefaultFlightTime(code);
  const double g = 9.81;
  if (options.takeoff_vertical_velocity_mps > 0) {
    T = 2 * options.takeoff_vertical_velocity_mps / g;
  } else if (options.flight_time_s > 0) {
    T = options.flight_time_s;
  }
  if (!(T >= 0.5 && T <= 3.0))
    throw InputError("", where, fmt::format("flight time {:.3f} s is outside 0.5–3 s", T));

  Plan plan = MakePlan(code, T);
  plan.step = T / std::max(1.0, std::round(T / options.step_s));
  // Shoot, move the postures to the angles where they belong, shoot again. A stalled pass ends
  // early (it only waits for the schedule's update).
  //
  // Twist-ins (a stop action: 821o, 831<) are shot differently. Their stop row repeats the first
  // somersault's twist row, so the solutions form a one-parameter family along which those passes
  // wandered: where they ended hung on the path (10⁻⁷ rad in the flights picked another design or
  // none, docs/skill-design.md). Their schedule is fixed first, from the flight without the twist
  // (smooth, it settles); the contact twist is then scanned for the one that turns the first
  // somersault's twist, and one careful Newton pass shoots the rest. 821o: 135 simulations
  // (597 before), 831<: 124 (2 639).
  const bool has_stop = !plan.unknowns.stop_somersaults.empty();
  constexpr double kTurned = 1e-3;  // rad: the largest residual of a flight found
  double residual = 0;
  Shooter shooter(athlete, plan);
  VectorXd x;
  if (has_stop) {
    const double momentum = shooter.FitScheduleWithoutTwist(shooter.MomentumGuess());
    x = shooter.Shoot(shooter.Guess(momentum), options, false, true, &residual);
  } else {
    x = shooter.Guess();
    for (int pass = 0; pass < 4; ++pass) {
      x = shooter.Shoot(x, options, true, false, &residual);
      shooter.UpdateSchedule(shooter.Simulate(x));
    }
    x = shooter.Shoot(x, options, true, false, &residual);
  }
  const int simulations = shooter.simulations();
  ACRO_DEMAND(std::abs(shooter.model().gravity_W().norm() - g) < 1e-12);
  const Flight flight = shooter.Simulate(x);
  result.shooting_residual_rad = residual;
  result.shooting_simulations = simulations;
  if (!(residual <= kTurned))
    throw InputError("",
                     where,
                     fmt::format("no flight of {:.2f} s turns its rotation for this athlete "
                                 "(shooting left {:.1f}° unturned)",
                                 T,
                                 residual / kDeg));

  // The take-off.
  const double m = shooter.mass();
  result.flight_time_s = T;
  result.takeoff_vertical_velocity_mps = g * T / 2;
  result.H_Scm_W = shooter.Momentum(x);
  result.somersault_momentum = std::abs(x[0]);
  result.twist_momentum = plan.unknowns.contact_twist ? std::abs(x[1]) : 0.0;
  result.normalized_somersault_momentum =
      result.somersault_momentum / (m * athlete.height_m * athlete.height_m);
  for (int k : plan.unknowns.aerial_somersaults)
    result.aerial_twist_actions_rad.push_back(shooter.Action(x, k));
  result.track = flight.track;
  result.takeoff_lean_rad = plan.lean_rad;
  result.landing_short_rad = plan.somersaults == 0
                                 ? 0.0
                                 : 2 * kPi * plan.somersaults - plan.lean_rad - plan.air_target_rad;
  result.momentum_components = Eigen::Vector2d(x[0], plan.unknowns.contact_twist ? x[1] : 0.0);

  DescribeFlight(code, plan, flight, shooter.Nominal(flight), T, &result);
  CheckFeasible(options, T, &result);
  MakeKeyframes(code, plan, flight, T, g, athlete_path, athlete, &result);
  return result;
}

std::string FormatSkillFromCode(const SkillFromCodeResult& r) {
  std::string out = fmt::format(
      "{}: DD {:.1f} ({})\n"
      "  take-off: vertical velocity {:.2f} m/s, flight time {:.3f} s, somersault momentum "
      "{:.1f} kg·m²/s ({:.3f} /s per m h²), twist momentum {:.1f} kg·m²/s\n",
      r.skill.name,
      r.difficulty.total(),
      r.difficulty.Explain(),
      r.takeoff_vertical_velocity_mps,
      r.flight_time_s,
      r.somersault_momentum,
      r.normalized_somersault_momentum,
      r.twist_momentum);
  std::string halves;
  for (double h : r.half_twists_per_somersault)
    halves += (halves.empty() ? "" : ", ") + fmt::format("{:.2f}", h);
  out += fmt::format(
      "  flight: {:.3f} somersaults and {:.3f} twists{} in the air, half twists per somersault {}, "
      "tilt up to {:.1f}° ({:.1f}° at landing), {:.2f} s left to prepare the landing\n",
      r.air_somersault_rad / (2 * kPi),
      std::abs(r.air_twist_rad) / (2 * kPi),
      r.twist_direction == fig::TwistDirection::kNone
          ? std::string()
          : std::string(" to the ") + TwistDirectionName(r.twist_direction),
      halves.empty() ? "-" : halves,
      r.max_tilt_rad / kDeg,
      r.landing_tilt_rad / kDeg,
      r.time_to_prepare_landing_s);
  if (r.feasible()) {
    out += "  feasible for this athlete\n";
  } else {
    for (const std::string& why : r.not_feasible) out += "  not feasible: " + why + "\n";
  }
  return out;
}

}  // namespace acro::analysis
