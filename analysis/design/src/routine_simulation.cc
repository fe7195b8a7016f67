#include "acro/design/routine_simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/orientation.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/demand.h"
#include "acro/design/skill_file.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/flight_simulation.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Model = dynamics::Model<double>;
using Workspace = dynamics::Workspace<double>;
using PoseTrack = PostureTrack;
using SkillPlan = RoutineSkillPlan;

constexpr double kPi = 3.14159265358979323846;

Matrix3d Rz(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix();
}
Matrix3d Ry(double a) {
  return Eigen::AngleAxisd(a, Vector3d::UnitY()).toRotationMatrix();
}
Matrix3d Skew(const Vector3d& u) {
  Matrix3d S;
  S << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
  return S;
}
// SO(3) exponential and logarithm (rotation vectors), and the right Jacobian J_r(u) of
// R(t) = R0·Exp(u(t)): Rᵀ Ṙ = [J_r(u) u̇]× (Chirikjian 2011, Stochastic Models, vol. 2, §10.6).
Matrix3d ExpSO3(const Vector3d& u) {
  const double theta = u.norm();
  if (theta < 1e-15) return Matrix3d::Identity() + Skew(u);
  return Eigen::AngleAxisd(theta, u / theta).toRotationMatrix();
}
Vector3d LogSO3(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}
Matrix3d RightJacobian(const Vector3d& u) {
  const double theta = u.norm();
  const Matrix3d S = Skew(u);
  if (theta < 1e-6) return Matrix3d::Identity() - 0.5 * S + S * S / 6.0;
  const double t2 = theta * theta;
  return Matrix3d::Identity() - (1.0 - std::cos(theta)) / t2 * S +
         (theta - std::sin(theta)) / (t2 * theta) * S * S;
}

// Cubic Hermite basis on s ∈ [0, 1] and its derivative.
struct Hermite {
  double h00, h10, h01, h11, d00, d10, d01, d11;
  explicit Hermite(double s) {
    const double s2 = s * s, s3 = s2 * s;
    h00 = 2 * s3 - 3 * s2 + 1;
    h10 = s3 - 2 * s2 + s;
    h01 = -2 * s3 + 3 * s2;
    h11 = s3 - s2;
    d00 = 6 * s2 - 6 * s;
    d10 = 3 * s2 - 4 * s + 1;
    d01 = -6 * s2 + 6 * s;
    d11 = 3 * s2 - 2 * s;
  }
};

// Root finding on a bracket [a, b] with f(a), f(b) of opposite signs (Illinois variant of regula
// falsi, Dahlquist & Björck 1974, §6.2.2).
double FindRoot(const std::function<double(double)>& f, double a, double b, double fa, double fb) {
  int side = 0;
  for (int it = 0; it < 200; ++it) {
    const double c = (a * fb - b * fa) / (fb - fa);
    const double fc = f(c);
    if (fc == 0.0 || std::abs(b - a) < 1e-14) return c;
    if ((fc > 0) == (fb > 0)) {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c;
      fa = fc;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
    if (std::abs(b - a) < 1e-14) return 0.5 * (a + b);
  }
  return 0.5 * (a + b);
}

// Per unit of push: a squat (hips flex φ, knees 2φ, ankles −φ keep the feet flat).
VectorXd Squat() {
  VectorXd q = VectorXd::Zero(StandardJointDofCount());
  for (const char* side : {"r_", "l_"}) {
    const std::string s = side;
    q[StandardJointDofIndex(s + "thigh", 0)] = -1.0;
    q[StandardJointDofIndex(s + "shank", 0)] = 2.0;
    q[StandardJointDofIndex(s + "foot", 0)] = -1.0;
  }
  return q;
}

// ---------------------------------------------------------------------------------------------
// The athlete and the bed.

struct Context {
  Model model;
  double mass = 0;
  double g = 9.81;
  double k = 0, c = 0;  // bed
  double z_rest = 0;
  bool late_squat = true;  // RoutineSimulationOptions::absorb_by_late_squat
  double h_grid = 0;       // integration step (s); frames lie on the grid
  int substeps = 10;
  // Sole centres (midpoint of toe tip and the heel below the ankle) of both feet.
  int foot[2] = {0, 0};
  Vector3d p_FoSole_F[2];
  std::unique_ptr<Workspace> ws;

  Vector3d Com() const { return dynamics::CalcCenterOfMassPosition(model, *ws); }
  Vector3d ComVelocity() const { return dynamics::CalcCenterOfMassVelocity(model, *ws); }
  Vector3d Feet() const {
    Vector3d p = Vector3d::Zero();
    for (int s = 0; s < 2; ++s) p += 0.5 * (ws->X_WB[size_t(foot[s])] * p_FoSole_F[s]);
    return p;
  }
  Vector3d FeetVelocity() const {
    Vector3d v = Vector3d::Zero();
    for (int s = 0; s < 2; ++s) {
      const auto V = dynamics::CalcSegmentSpatialVelocity(*ws, foot[s]);
      const auto& X = ws->X_WB[size_t(foot[s])];
      const Vector3d r = X.rotation() * p_FoSole_F[s];
      v += 0.5 * (V.translational() + V.rotational().cross(r));
    }
    return v;
  }
  void Fk(const VectorXd& q) { dynamics::CalcForwardKinematics(model, *ws, q); }
  void Fk(const VectorXd& q, const VectorXd& v) {
    dynamics::CalcForwardKinematics(model, *ws, q, v);
  }
};

// A configuration from orientation and joint angles, root at the origin.
VectorXd Configuration(const Context& ctx, const Matrix3d& R_WB, const VectorXd& joints) {
  VectorXd q = dynamics::MakeNeutralConfiguration(ctx.model);
  dynamics::SetRootQuaternion<double>(Eigen::Quaterniond(R_WB).normalized(), q);
  q.tail(joints.size()) = joints;
  return q;
}

// ---------------------------------------------------------------------------------------------
// Flights.

struct FlightPath {
  double t0 = 0;               ///< take-off (absolute, or 0 when canonical)
  int first_grid = 0;          ///< absolute grid index of samples[0]
  std::vector<VectorXd> q, v;  ///< grid states after take-off, before landing
  double landing_rel = 0;      ///< landing − take-off
  VectorXd q0, v0;             ///< take-off state
  VectorXd q_land, v_land;     ///< landing state
  double somersault_land = 0, twist_land = 0, somersault0 = 0;
};

dynamics::JointTrajectory<double> Joints(const PoseTrack& track, double shift) {
  return [&track, shift](const double& t,
                         dynamics::VectorXRef<double> q,
                         dynamics::VectorXRef<double> qd,
                         dynamics::VectorXRef<double> qdd) { track.Eval(t + shift, q, qd, qdd); };
}

// Simulates from (q0, v0) at absolute time t0 with steps on the absolute grid (multiples of
// ctx.h_grid), until the feet come down to the bed's rest level; `heading` is the somersault frame.
FlightPath SimulateSkillFlight(Context& ctx,
                               const PoseTrack& track,
                               const VectorXd& q0,
                               const VectorXd& v0,
                               double t0,
                               double duration_guess,
                               const Matrix3d& R_heading) {
  FlightPath path;
  path.t0 = t0;
  path.q0 = q0;
  path.v0 = v0;
  const double h = ctx.h_grid;
  // First step: from take-off to the next grid time.
  std::int64_t g0 = static_cast<std::int64_t>(std::floor(t0 / h + 1e-9)) + 1;
  if (double(g0) * h - t0 < 1e-7) ++g0;  // no vanishing first step
  const double delta = double(g0) * h - t0;
  path.first_grid = static_cast<int>(g0);
  dynamics::FlightSimulationOptions first;
  first.duration_s = delta;
  first.step_s = std::min(delta, h);
  const auto r1 = dynamics::SimulateFlight<double>(
      ctx.model, first, q0.head<7>(), v0.head<6>(), Joints(track, 0.0));
  ACRO_DEMAND(r1.summary.status == dynamics::FlightSimulationStatus::kSuccess);
  const VectorXd q1 = r1.q.back(), v1 = r1.v.back();

  dynamics::FlightSimulationOptions rest;
  rest.step_s = h;
  rest.duration_s = duration_guess * 1.2 + 0.2;
  const auto r2 = dynamics::SimulateFlight<double>(
      ctx.model, rest, q1.head<7>(), v1.head<6>(), Joints(track, delta));
  ACRO_DEMAND(r2.summary.status == dynamics::FlightSimulationStatus::kSuccess);

  // The landing: the first downward crossing of the bed's rest level by the feet.
  auto feet_z = [&](const VectorXd& q) {
    ctx.Fk(q);
    return ctx.Feet().z() - ctx.z_rest;
  };
  size_t land = 0;
  double f_prev = feet_z(r2.q[0]);
  bool high = f_prev > 0.3;
  for (size_t j = 1; j < r2.q.size(); ++j) {
    const double f = feet_z(r2.q[j]);
    if (f > 0.3) high = true;
    if (high && f_prev > 0 && f <= 0) {
      land = j;
      break;
    }
    f_prev = f;
  }
  ACRO_DEMAND(land > 0);
  // Refine within the step by partial RK4 steps from the last state above the bed.
  const VectorXd& qa = r2.q[land - 1];
  const VectorXd& va = r2.v[land - 1];
  const double shift = delta + double(land - 1) * h;
  auto partial = [&](double tau, VectorXd* q, VectorXd* v) {
    dynamics::FlightSimulationOptions o;
    o.duration_s = tau;
    o.step_s = tau;
    const auto r = dynamics::SimulateFlight<double>(
        ctx.model, o, qa.head<7>(), va.head<6>(), Joints(track, shift));
    *q = r.q.back();
    *v = r.v.back();
  };
  const double tau = FindRoot(
      [&](double s) {
        VectorXd q, v;
        partial(s, &q, &v);
        return feet_z(q);
      },
      0.0,
      h,
      f_prev,
      feet_z(r2.q[land]));
  partial(tau, &path.q_land, &path.v_land);
  path.landing_rel = shift + tau;
  path.q.assign(r2.q.begin(), r2.q.begin() + long(land));
  path.v.assign(r2.v.begin(), r2.v.begin() + long(land));

  // Somersault and twist, unwrapped from take-off to landing.
  const SomersaultTiltTwist start = CalcSomersaultTiltTwist(
      R_heading.transpose() * dynamics::GetRootQuaternion(q0).toRotationMatrix());
  double som = start.somersault_rad;
  path.somersault0 = som;
  double twist = start.twist_rad;
  auto accumulate = [&](const VectorXd& q) {
    const SomersaultTiltTwist a = CalcSomersaultTiltTwist(
        R_heading.transpose() * dynamics::GetRootQuaternion(q).normalized().toRotationMatrix());
    som = UnwrapAngle(som, a.somersault_rad);
    twist = UnwrapAngle(twist, a.twist_rad);
  };
  for (const VectorXd& q : path.q) accumulate(q);
  accumulate(path.q_land);
  path.somersault_land = som;
  path.twist_land = twist;
  return path;
}

// The take-off state of a flight: orientation R_WB, the track's joints at time 0, COM velocity
// v_com and angular momentum H about the COM; the feet at the depth where the bed's force
// k d + c ḋ falls to zero (d = c·ż_feet / k) and the COM above `com_xy`.
void MakeTakeoffState(Context& ctx,
                      const PoseTrack& track,
                      const Matrix3d& R_WB,
                      const Vector3d& v_com,
                      const Vector3d& H,
                      const Vector2d& com_xy,
                      VectorXd* q,
                      VectorXd* v,
                      double* depth) {
  const int n = ctx.model.num_joint_dofs();
  VectorXd qj(n), qdj(n), qddj(n);
  track.Eval(0.0, qj, qdj, qddj);
  *q = Configuration(ctx, R_WB, qj);
  *v = VectorXd::Zero(ctx.model.nv());
  v->tail(n) = qdj;
  v->head<6>() =
      dynamics::CalcRootVelocityFromMomentum<double>(ctx.model, *ctx.ws, *q, *v, v_com, H);
  ctx.Fk(*q, *v);
  const double feet_vz = ctx.FeetVelocity().z();
  *depth = ctx.c * feet_vz / ctx.k;
  const Vector3d com = ctx.Com();
  const Vector3d feet = ctx.Feet();
  q->head<3>() =
      Vector3d(com_xy.x() - com.x(), com_xy.y() - com.y(), ctx.z_rest - *depth - feet.z());
}

// Shoots the take-off angular momentum (somersault component along the heading's lateral axis,
// twist component along the body's long axis at take-off) so that the skill lands with its
// nominal somersault less landing_short and its nominal twist.
struct Shot {
  FlightPath path;
  Vector3d H = Vector3d::Zero();
  Matrix3d R_TO = Matrix3d::Identity();
};

Shot ShootSkill(Context& ctx, const SkillPlan& plan, double heading) {
  const double T = plan.flight_s;
  const Vector3d v_com(0, 0, ctx.g * T / 2);
  const Matrix3d R_h = Rz(heading);
  const double lean = plan.direction * plan.takeoff_lean_rad;
  const Matrix3d R_TO = R_h * Ry(lean);
  const double target_som = plan.direction * (plan.nominal_rad - plan.landing_short_rad);
  const double target_twist = plan.twist_halves * kPi;
  auto run = [&](const Vector2d& x, Shot* shot) {
    shot->H = R_h * (x[0] * Vector3d::UnitY() + x[1] * Ry(lean) * Vector3d::UnitZ());
    shot->R_TO = R_TO;
    VectorXd q, v;
    double depth;
    MakeTakeoffState(ctx, plan.track, R_TO, v_com, shot->H, Vector2d::Zero(), &q, &v, &depth);
    shot->path = SimulateSkillFlight(ctx, plan.track, q, v, 0.0, T, R_h);
    return Vector2d(shot->path.somersault_land - target_som, shot->path.twist_land - target_twist);
  };
  Shot shot;
  if (plan.direction == 0) {
    run(Vector2d::Zero(), &shot);
    return shot;
  }
  const bool twisting = plan.twist_halves != 0;
  // A first guess from a mean somersault inertia of 9 kg·m² (tucked 4–5, straight 13).
  Vector2d x(plan.direction * 9.0 * (std::abs(target_som) - plan.takeoff_lean_rad) / T,
             twisting ? 1.5 * target_twist / T : 0.0);
  if (plan.momentum_guess) x = *plan.momentum_guess;
  Vector2d r = run(x, &shot);
  for (int it = 0; it < 30 && r.norm() > 1e-9; ++it) {
    // Newton with a forward-difference Jacobian; the twist row only when the skill twists.
    Shot probe;
    Eigen::Matrix2d J = Eigen::Matrix2d::Identity();
    const double hs = 1e-4 * std::max(1.0, std::abs(x[0]));
    J.col(0) = (run(x + Vector2d(hs, 0), &probe) - r) / hs;
    Vector2d dx;
    if (twisting) {
      const double ht = 1e-4;
      J.col(1) = (run(x + Vector2d(0, ht), &probe) - r) / ht;
      dx = -J.partialPivLu().solve(r);
    } else {
      dx = Vector2d(-r[0] / J(0, 0), 0);
    }
    double step = 1.0;
    for (int back = 0; back < 8; ++back) {
      Shot trial;
      const Vector2d rt = run(x + step * dx, &trial);
      if (rt.norm() < r.norm() || back == 7) {
        x += step * dx;
        r = rt;
        shot = std::move(trial);
        break;
      }
      step *= 0.5;
    }
  }
  return shot;
}

// ---------------------------------------------------------------------------------------------
// Contacts.

// Orientation, joints and horizontal COM blended over [t0, t0 + duration] from one state to
// another (cubic Hermite; the orientation in the tangent space at the start), plus a squat of
// amplitude |push| (rad of hip flexion). A positive push is shaped s²(1 − s)⁴, which peaks at a
// third of the contact: the athlete bends as the bed goes down and extends against its largest
// force, which gives energy. A negative push is shaped s⁴(1 − s)², which peaks at two thirds: the
// athlete bends against the largest force and extends when the bed has little left, which takes
// energy ("killing" part of the bounce, for a lower flight).
struct Blend {
  double t0 = 0, duration = 0.35;
  Matrix3d R0 = Matrix3d::Identity();
  Vector3d w0_B = Vector3d::Zero(), r1 = Vector3d::Zero(), m1 = Vector3d::Zero();
  VectorXd q0, qd0, q1, qd1, squat;
  double push = 0;
  Vector2d x0 = Vector2d::Zero(), xd0 = Vector2d::Zero(), x1 = Vector2d::Zero(),
           xd1 = Vector2d::Zero();

  void SetEnds(const Matrix3d& R_start,
               const Vector3d& w_start_B,
               const Matrix3d& R_end,
               const Vector3d& w_end_B) {
    R0 = R_start;
    w0_B = w_start_B;
    r1 = LogSO3(R_start.transpose() * R_end);
    m1 = RightJacobian(r1).inverse() * w_end_B;
  }
  // Configuration (root at the origin) and velocities (root linear velocity zero) at time t.
  void Eval(const Context& ctx, double t, VectorXd* q, VectorXd* v) const {
    const double s = (t - t0) / duration;
    const Hermite H(s);
    const Vector3d u = H.h10 * duration * w0_B + H.h01 * r1 + H.h11 * duration * m1;
    const Vector3d du = (H.d10 * duration * w0_B + H.d01 * r1 + H.d11 * duration * m1) / duration;
    const double bmax = 16.0 / 729.0;
    const double sc = std::clamp(s, 0.0, 1.0);
    const bool late = push < 0 && ctx.late_squat;
    const double early = late ? 1 - sc : sc;  // the late shape is the early one mirrored
    const double b = early * early * std::pow(1 - early, 4) / bmax;
    const double db =
        (late ? -1.0 : 1.0) *
        (2 * early * std::pow(1 - early, 4) - 4 * early * early * std::pow(1 - early, 3)) / bmax;
    const double amplitude = ctx.late_squat ? std::abs(push) : push;
    const VectorXd joints = H.h00 * q0 + H.h10 * duration * qd0 + H.h01 * q1 +
                            H.h11 * duration * qd1 + amplitude * b * squat;
    const VectorXd rates = (H.d00 * q0 + H.d10 * duration * qd0 + H.d01 * q1 +
                            H.d11 * duration * qd1 + amplitude * db * squat) /
                           duration;
    *q = Configuration(ctx, R0 * ExpSO3(u), joints);
    *v = VectorXd::Zero(ctx.model.nv());
    v->segment<3>(3) = RightJacobian(u) * du;
    v->tail(rates.size()) = rates;
  }
  void Horizontal(double t, Vector2d* x, Vector2d* xd) const {
    const Hermite H((t - t0) / duration);
    *x = H.h00 * x0 + H.h10 * duration * xd0 + H.h01 * x1 + H.h11 * duration * xd1;
    *xd = (H.d00 * x0 + H.d10 * duration * xd0 + H.d01 * x1 + H.d11 * duration * xd1) / duration;
  }
};

// Height of the COM above the feet and its rate, for the blended configuration at t.
void ComOverFeet(Context& ctx, const Blend& blend, double t, double* h, double* hd) {
  VectorXd q, v;
  blend.Eval(ctx, t, &q, &v);
  ctx.Fk(q, v);
  *h = ctx.Com().z() - ctx.Feet().z();
  *hd = ctx.ComVelocity().z() - ctx.FeetVelocity().z();
}

enum class ContactEnd { kTakeoff, kBottom };

struct ContactRun {
  std::vector<std::int64_t> grid;  ///< absolute grid indices of the stored states
  std::vector<Vector2d> y;         ///< (z, ż) of the COM at those times
  double t_end = 0;
  Vector2d y_end = Vector2d::Zero();
  double peak_force = 0, max_depth = 0;
};

// The bed's force on the athlete: k d + c ḋ, never pulling; d from the feet.
struct BedForce {
  double force, depth;
};
BedForce Bed(Context& ctx, const Blend& blend, double t, const Vector2d& y) {
  double h, hd;
  ComOverFeet(ctx, blend, t, &h, &hd);
  const double d = ctx.z_rest - (y[0] - h);
  const double dd = -(y[1] - hd);
  return {std::max(0.0, ctx.k * d + ctx.c * dd), d};
}
// The unclipped force (its zero is the take-off).
double BedForceRaw(Context& ctx, const Blend& blend, double t, const Vector2d& y) {
  double h, hd;
  ComOverFeet(ctx, blend, t, &h, &hd);
  return ctx.k * (ctx.z_rest - (y[0] - h)) + ctx.c * (hd - y[1]);
}

Vector2d ContactStep(Context& ctx, const Blend& blend, double t, const Vector2d& y, double dt) {
  // m z̈ = −m g + F_bed (classical RK4).
  auto f = [&](double tt, const Vector2d& yy) {
    return Vector2d(yy[1], -ctx.g + Bed(ctx, blend, tt, yy).force / ctx.mass);
  };
  const Vector2d k1 = f(t, y);
  const Vector2d k2 = f(t + dt / 2, y + dt / 2 * k1);
  const Vector2d k3 = f(t + dt / 2, y + dt / 2 * k2);
  const Vector2d k4 = f(t + dt, y + dt * k3);
  return y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
}

// Integrates forward on the absolute grid from (t0, y0) until the event: take-off (the bed's
// force falls to zero while the athlete rises) or the bottom (ż = 0).
ContactRun IntegrateContact(
    Context& ctx, const Blend& blend, double t0, const Vector2d& y0, ContactEnd end) {
  ContactRun run;
  const double h = ctx.h_grid;
  auto event = [&](double t, const Vector2d& y) {
    return end == ContactEnd::kTakeoff ? BedForceRaw(ctx, blend, t, y) : y[1];
  };
  auto fired = [&](double e_prev, double e, const Vector2d& y) {
    if (end == ContactEnd::kTakeoff) return y[1] > 0 && e_prev > 0 && e <= 0;
    return e_prev < 0 && e >= 0;
  };
  std::int64_t g = static_cast<std::int64_t>(std::floor(t0 / h + 1e-9)) + 1;
  double t = t0;
  Vector2d y = y0;
  double e_prev = event(t, y);
  if (end == ContactEnd::kBottom) e_prev = std::min(e_prev, -1e-300);
  const BedForce b0 = Bed(ctx, blend, t, y);
  run.peak_force = b0.force;
  run.max_depth = b0.depth;
  for (int it = 0; it < 100000; ++it) {
    const double t_next = double(g) * h;
    const Vector2d y_next = ContactStep(ctx, blend, t, y, t_next - t);
    const double e = event(t_next, y_next);
    if (fired(e_prev, e, y_next)) {
      const double tau =
          FindRoot([&](double s) { return event(t + s, ContactStep(ctx, blend, t, y, s)); },
                   0.0,
                   t_next - t,
                   e_prev,
                   e);
      run.t_end = t + tau;
      run.y_end = ContactStep(ctx, blend, t, y, tau);
      return run;
    }
    t = t_next;
    y = y_next;
    e_prev = e;
    const BedForce b = Bed(ctx, blend, t, y);
    run.peak_force = std::max(run.peak_force, b.force);
    run.max_depth = std::max(run.max_depth, b.depth);
    run.grid.push_back(g);
    run.y.push_back(y);
    ++g;
  }
  ACRO_DEMAND(false);
  return run;
}

// Integrates backward (fixed steps) from (t0, y0) until ż = 0: the bottom of the contact before the
// first take-off. Returns the time and state there.
std::pair<double, Vector2d> IntegrateToBottomBackward(Context& ctx,
                                                      const Blend& blend,
                                                      double t0,
                                                      const Vector2d& y0) {
  const double h = ctx.h_grid;
  double t = t0;
  Vector2d y = y0;
  for (int it = 0; it < 100000; ++it) {
    const Vector2d y_next = ContactStep(ctx, blend, t, y, -h);
    if (y_next[1] <= 0) {
      const double tau = FindRoot(
          [&](double s) { return ContactStep(ctx, blend, t, y, -s)[1]; }, 0.0, h, y[1], y_next[1]);
      return {t - tau, ContactStep(ctx, blend, t, y, -tau)};
    }
    t -= h;
    y = y_next;
  }
  ACRO_DEMAND(false);
  return {};
}

struct Phase {
  bool flight = false;
  int index = 0;  ///< into flights or contacts
  double t_start = 0, t_end = 0;
};

struct ContactPhase {
  Blend blend;
  ContactRun run;
  double t_start = 0;
  Vector2d y_start = Vector2d::Zero();
  double vz_error = 0;  ///< the take-off's vertical velocity less the one asked for
};

// ---------------------------------------------------------------------------------------------
// SimulateRoutine's steps.

// The context: the athlete's standard human, the bed, and the integration grid (substeps per
// frame).
void SetUpContext(const AthleteBody& body, const RoutineSimulationOptions& options, Context& ctx) {
  ctx.model = MakeStandardHumanModel(body);
  ctx.ws = std::make_unique<Workspace>(ctx.model);
  ctx.mass = ctx.model.total_mass();
  ctx.g = -ctx.model.gravity_W().z();
  ctx.k = options.bed_stiffness_N_per_m;
  ctx.c = options.bed_damping_N_s_per_m;
  ctx.z_rest = options.bed_centre_m.z();
  ctx.late_squat = options.absorb_by_late_squat;
  ctx.substeps = options.substeps_per_frame;
  ctx.h_grid = 1.0 / (options.point_rate_hz * ctx.substeps);
}

// Sole centres from the reference pose: halfway from the toe tip to the point below the ankle.
void FindSoleCentres(Context& ctx) {
  const Model& model = ctx.model;
  const VectorXd q = dynamics::MakeNeutralConfiguration(model);
  ctx.Fk(q);
  const char* sides[2] = {"r_", "l_"};
  for (int s = 0; s < 2; ++s) {
    const std::string side = sides[s];
    ctx.foot[s] = model.FindSegment(side + "foot");
    const Vector3d toe = dynamics::CalcPointPosition(model, *ctx.ws, model.FindPoint(side + "toe"));
    const Vector3d ankle =
        dynamics::CalcPointPosition(model, *ctx.ws, model.FindPoint(side + "ankle_jc"));
    const Vector3d sole = 0.5 * (toe + Vector3d(ankle.x(), ankle.y(), toe.z()));
    const auto& X = ctx.ws->X_WB[size_t(ctx.foot[s])];
    ctx.p_FoSole_F[s] = X.rotation().transpose() * (sole - X.translation());
  }
}

// The routine's skills, each shot in its own heading (take-off at t = 0, COM above the origin);
// every skill turns the heading by its half twists.
struct Skills {
  std::vector<SkillPlan> plans;
  std::vector<double> headings;
  std::vector<Shot> shots;
  double final_heading = 0;
};

Skills ShootSkills(Context& ctx, const std::vector<SkillPlan>& plans) {
  Skills skills;
  skills.plans = plans;
  double heading = 0;
  for (const SkillPlan& plan : skills.plans) {
    skills.headings.push_back(heading);
    skills.shots.push_back(ShootSkill(ctx, plan, heading));
    heading += plan.twist_halves * kPi;
  }
  skills.final_heading = heading;
  return skills;
}

// The routine's time line: contacts and flights alternating, from the first contact (from the
// bottom of a bounce, standing) to the last (to the bottom after the last landing).
struct Timeline {
  std::vector<Phase> phases;
  std::vector<ContactPhase> contacts;
  std::vector<FlightPath> flights;
};

// Builds the time line: the first contact, then per skill the flight and the contact after it.
class TimelineBuilder {
 public:
  TimelineBuilder(Context& ctx, const Skills& skills, const Vector2d& centre)
      : ctx_(ctx),
        skills_(skills),
        centre_(centre),
        nj_(ctx.model.num_joint_dofs()),
        feet_xy_(centre + Vector2d(-0.03, 0.02)) {}

  Timeline Build() && {
    AddFirstContact();
    const std::vector<SkillPlan>& plans = skills_.plans;
    for (size_t i = 0; i < plans.size(); ++i) {
      if (i + 1 == plans.size()) {
        AddLastContact(i);
        break;
      }
      AddContactToNextSkill(i);
    }
    return std::move(timeline_);
  }

 private:
  // Horizontal COM offset from the feet in a configuration.
  Vector2d ComMinusFeet(const VectorXd& q) {
    ctx_.Fk(q);
    return Vector2d((ctx_.Com() - ctx_.Feet()).head<2>());
  }

  // The take-off state of skill i, its COM above `com_xy` with horizontal velocity `v_xy` and
  // vertical velocity `vz`.
  void TakeoffState(int i,
                    const Vector2d& com_xy,
                    const Vector2d& v_xy,
                    double vz,
                    VectorXd* q,
                    VectorXd* v,
                    double* depth) {
    MakeTakeoffState(ctx_,
                     skills_.plans[size_t(i)].track,
                     skills_.shots[size_t(i)].R_TO,
                     Vector3d(v_xy.x(), v_xy.y(), vz),
                     skills_.shots[size_t(i)].H,
                     com_xy,
                     q,
                     v,
                     depth);
  }

  // The horizontal COM coasts through a contact of duration Δ that starts at x_l with velocity
  // v_l (the bed pushes almost vertically; the feet slide with the bed as the body turns about
  // them): x_to = x_l + (v_l + v_to) Δ / 2. The take-off velocity v_to of skill i puts its feet at
  // the landing target: x_to + v_to T + (feet − COM at landing) = target, T the shot's flight time.
  Vector2d Aim(int i, const Vector2d& x_l, const Vector2d& v_l, double duration) {
    const FlightPath& p = skills_.shots[size_t(i)].path;
    // In the canonical shot the COM starts above the origin and moves only vertically.
    const Vector2d feet_rel_land = -ComMinusFeet(p.q_land);
    const Vector2d target = centre_ + skills_.plans[size_t(i)].landing_target_m;
    const double T = p.landing_rel;
    return Vector2d((target - feet_rel_land - x_l - 0.5 * duration * v_l) / (T + 0.5 * duration));
  }

  // Skill n's flight from the contact's end, its COM above com_to with horizontal velocity v_xy.
  FlightPath FlyFromContact(int n,
                            const ContactRun& run,
                            const Vector2d& com_to,
                            const Vector2d& v_xy) {
    const SkillPlan& plan = skills_.plans[size_t(n)];
    VectorXd q_to, v_to;
    double depth;
    TakeoffState(n, com_to, v_xy, run.y_end[1], &q_to, &v_to, &depth);
    ctx_.Fk(q_to);
    q_to[2] += run.y_end[0] - ctx_.Com().z();
    return SimulateSkillFlight(
        ctx_, plan.track, q_to, v_to, run.t_end, plan.flight_s, Rz(skills_.headings[size_t(n)]));
  }

  // First contact: standing at the bottom of a bounce, to the first take-off; then the first
  // flight.
  void AddFirstContact() {
    const SkillPlan& plan = skills_.plans[0];
    const double vz = ctx_.g * plan.flight_s / 2;
    VectorXd q_to, v_to;
    double depth;
    TakeoffState(0, Vector2d::Zero(), Vector2d::Zero(), vz, &q_to, &v_to, &depth);
    ctx_.Fk(q_to);
    const double z_to = ctx_.Com().z();
    const Matrix3d R_stand = Rz(skills_.headings[0]);
    ContactPhase cp;
    Blend& b = cp.blend;
    b.SetEnds(R_stand, Vector3d::Zero(), skills_.shots[0].R_TO, v_to.segment<3>(3));
    b.q0 = VectorXd::Zero(nj_);
    b.qd0 = VectorXd::Zero(nj_);
    b.q1 = q_to.tail(nj_);
    b.qd1 = v_to.tail(nj_);
    b.squat = Squat();
    // The contact's duration: backward from take-off to the bottom, with the blend spanning it.
    double duration = 0.18;
    std::pair<double, Vector2d> bottom;
    for (int it = 0; it < 100; ++it) {
      b.duration = duration;
      b.t0 = -duration;
      bottom = IntegrateToBottomBackward(ctx_, b, 0.0, Vector2d(z_to, vz));
      const double next = -bottom.first;
      const bool done = std::abs(next - duration) < 1e-13;
      duration = next;
      if (done) break;
    }
    // The horizontal COM from standing over the feet to the take-off that aims the first skill.
    b.duration = duration;
    b.t0 = 0.0;
    b.x0 = feet_xy_ + ComMinusFeet(Configuration(ctx_, R_stand, b.q0));
    const Vector2d v_xy = Aim(0, b.x0, Vector2d::Zero(), duration);
    const Vector2d com_to = b.x0 + 0.5 * duration * v_xy;
    b.x1 = com_to;
    b.xd1 = v_xy;
    // The contact forward from the bottom, and the flight from its end state.
    cp.t_start = 0.0;
    cp.y_start = Vector2d(bottom.second[0], 0.0);
    cp.run = IntegrateContact(ctx_, b, 0.0, cp.y_start, ContactEnd::kTakeoff);
    std::vector<FlightPath>& flights = timeline_.flights;
    flights.push_back(FlyFromContact(0, cp.run, com_to, v_xy));
    timeline_.phases.push_back({false, 0, 0.0, cp.run.t_end});
    timeline_.phases.push_back({true, 0, cp.run.t_end, cp.run.t_end + flights[0].landing_rel});
    timeline_.contacts.push_back(std::move(cp));
  }

  // The contact after flight i's landing, from its landing state: start, joints and horizontal
  // COM (the ends toward which it blends are the caller's).
  ContactPhase StartLandingContact(const FlightPath& f) {
    const double t_land = f.t0 + f.landing_rel;
    ctx_.Fk(f.q_land, f.v_land);
    const Vector3d com_l = ctx_.Com();
    const Vector3d vcom_l = ctx_.ComVelocity();
    ContactPhase cp;
    cp.t_start = t_land;
    cp.y_start = Vector2d(com_l.z(), vcom_l.z());
    Blend& b = cp.blend;
    b.t0 = t_land;
    b.q0 = f.q_land.tail(nj_);
    b.qd0 = f.v_land.tail(nj_);
    b.squat = Squat();
    b.x0 = com_l.head<2>();
    b.xd0 = vcom_l.head<2>();
    return cp;
  }

  // Last contact: to the bottom, standing up straight, arms by the sides.
  void AddLastContact(size_t i) {
    const FlightPath& f = timeline_.flights[i];
    const double t_land = f.t0 + f.landing_rel;
    ContactPhase cp = StartLandingContact(f);
    Blend& b = cp.blend;
    const Matrix3d R_l = dynamics::GetRootQuaternion(f.q_land).normalized().toRotationMatrix();
    const Vector3d w_l = f.v_land.segment<3>(3);
    b.SetEnds(R_l, w_l, Rz(skills_.final_heading), Vector3d::Zero());
    b.q1 = VectorXd::Zero(nj_);
    b.qd1 = VectorXd::Zero(nj_);
    b.xd1 = Vector2d::Zero();
    // The duration: the blend spans the contact to its bottom.
    double duration = 0.18;
    for (int it = 0; it < 100; ++it) {
      b.duration = duration;
      cp.run = IntegrateContact(ctx_, b, t_land, cp.y_start, ContactEnd::kBottom);
      const double next = cp.run.t_end - t_land;
      const bool done = std::abs(next - duration) < 1e-13;
      duration = next;
      if (done) break;
    }
    b.duration = duration;
    b.x1 = b.x0 + 0.5 * duration * b.xd0;
    cp.run = IntegrateContact(ctx_, b, t_land, cp.y_start, ContactEnd::kBottom);
    timeline_.phases.push_back({false, int(timeline_.contacts.size()), t_land, cp.run.t_end});
    timeline_.contacts.push_back(std::move(cp));
  }

  // Duration Δ and push p of the contact `b` from t_land such that the bed lets go at t_land + Δ
  // with vertical velocity vz (Newton on both, forward-difference Jacobian, halving steps that do
  // not reduce the residual). Leaves b's last trial values set.
  Vector2d SolveDurationAndPush(Blend& b, double t_land, const Vector2d& y_start, double vz) {
    auto residual = [&](const Vector2d& x) {
      b.duration = x[0];
      b.push = x[1];
      const ContactRun r = IntegrateContact(ctx_, b, t_land, y_start, ContactEnd::kTakeoff);
      return Vector2d(r.t_end - t_land - x[0], r.y_end[1] - vz);
    };
    Vector2d x(0.36, 0.3);
    Vector2d r = residual(x);
    for (int it = 0; it < 40 && r.norm() > 1e-11; ++it) {
      Eigen::Matrix2d J;
      const double e = 1e-6;
      J.col(0) = (residual(x + Vector2d(e, 0)) - r) / e;
      J.col(1) = (residual(x + Vector2d(0, e)) - r) / e;
      const Vector2d dx = -J.partialPivLu().solve(r);
      double step = 1.0;
      for (int back = 0; back < 10; ++back) {
        const Vector2d rt = residual(x + step * dx);
        if (rt.norm() < r.norm() || back == 9) {
          x += step * dx;
          r = rt;
          break;
        }
        step *= 0.5;
      }
    }
    return x;
  }

  // The contact after flight i to the take-off of skill i + 1, then that skill's flight.
  void AddContactToNextSkill(size_t i) {
    const FlightPath& f = timeline_.flights[i];
    const double t_land = f.t0 + f.landing_rel;
    ContactPhase cp = StartLandingContact(f);
    Blend& b = cp.blend;
    const Matrix3d R_l = dynamics::GetRootQuaternion(f.q_land).normalized().toRotationMatrix();
    const Vector3d w_l = f.v_land.segment<3>(3);
    // Toward the next skill's take-off pose.
    const size_t n = i + 1;
    const double vz = ctx_.g * skills_.plans[n].flight_s / 2;
    VectorXd q_to, v_to;
    double depth;
    TakeoffState(int(n), Vector2d::Zero(), Vector2d::Zero(), vz, &q_to, &v_to, &depth);
    b.SetEnds(R_l, w_l, skills_.shots[n].R_TO, v_to.segment<3>(3));
    b.q1 = q_to.tail(nj_);
    b.qd1 = v_to.tail(nj_);
    // Duration and push for the next skill's vertical velocity; the horizontal COM aimed.
    const Vector2d x = SolveDurationAndPush(b, t_land, cp.y_start, vz);
    b.duration = x[0];
    b.push = x[1];
    const Vector2d v_xy = Aim(int(n), b.x0, b.xd0, x[0]);
    const Vector2d com_to = b.x0 + 0.5 * x[0] * (b.xd0 + v_xy);
    b.x1 = com_to;
    b.xd1 = v_xy;
    // The contact, then the flight from its end state.
    cp.run = IntegrateContact(ctx_, b, t_land, cp.y_start, ContactEnd::kTakeoff);
    cp.vz_error = cp.run.y_end[1] - vz;
    const double t_to = cp.run.t_end;
    FlightPath next = FlyFromContact(int(n), cp.run, com_to, v_xy);
    timeline_.phases.push_back({false, int(timeline_.contacts.size()), t_land, t_to});
    timeline_.contacts.push_back(std::move(cp));
    timeline_.flights.push_back(std::move(next));
    timeline_.phases.push_back({true, int(n), t_to, t_to + timeline_.flights.back().landing_rel});
  }

  Context& ctx_;
  const Skills& skills_;
  const Vector2d centre_;
  const int nj_;
  const Vector2d feet_xy_;
  Timeline timeline_;
};

// A contact's state at time t with the COM at height and vertical rate y: the blend's
// configuration and velocities, the root placed so that the COM follows the blend's horizontal
// path and y.
void ContactState(
    Context& ctx, const ContactPhase& c, double t, const Vector2d& y, VectorXd* q, VectorXd* v) {
  c.blend.Eval(ctx, t, q, v);
  Vector2d xy, vxy;
  c.blend.Horizontal(t, &xy, &vxy);
  ctx.Fk(*q, *v);
  const Vector3d com = ctx.Com();
  const Vector3d vcom = ctx.ComVelocity();
  q->head<3>() = Vector3d(xy.x(), xy.y(), y[0]) - com;
  v->head<3>() = Vector3d(vxy.x(), vxy.y(), y[1]) - vcom;
}

// Noise-free q and v per frame, from the phase each frame time falls in: flights on the grid,
// contacts from their stored COM heights.
void SampleFrames(
    Context& ctx, const Timeline& timeline, int num_frames, double rate, SimulatedRoutine& out) {
  const std::vector<Phase>& phases = timeline.phases;
  const int N = ctx.substeps;
  out.q.resize(ctx.model.nq(), num_frames);
  out.v.resize(ctx.model.nv(), num_frames);
  size_t ph = 0;
  for (int fr = 0; fr < num_frames; ++fr) {
    const double t = fr / rate;
    const std::int64_t g = std::int64_t(fr) * N;
    while (ph + 1 < phases.size() && t >= phases[ph].t_end) ++ph;
    const Phase& p = phases[ph];
    if (p.flight) {
      const FlightPath& f = timeline.flights[size_t(p.index)];
      const std::int64_t j = g - f.first_grid;
      ACRO_DEMAND(j >= 0 && j < std::int64_t(f.q.size()));
      out.q.col(fr) = f.q[size_t(j)];
      out.v.col(fr) = f.v[size_t(j)];
    } else {
      const ContactPhase& c = timeline.contacts[size_t(p.index)];
      Vector2d y;
      if (fr == 0) {
        y = c.y_start;
      } else {
        const auto it = std::lower_bound(c.run.grid.begin(), c.run.grid.end(), g);
        ACRO_DEMAND(it != c.run.grid.end() && *it == g);
        y = c.run.y[size_t(it - c.run.grid.begin())];
      }
      VectorXd q, v;
      ContactState(ctx, c, t, y, &q, &v);
      out.q.col(fr) = q;
      out.v.col(fr) = v;
    }
  }
}

// Raises out's largest boundary jumps to those between two states (COM position and velocity,
// orientation, angular velocity, joint angles and rates).
void CompareBoundaryStates(Context& ctx,
                           const VectorXd& qa,
                           const VectorXd& va,
                           const VectorXd& qb,
                           const VectorXd& vb,
                           SimulatedRoutine& out) {
  const int nj = ctx.model.num_joint_dofs();
  ctx.Fk(qa, va);
  const Vector3d ca = ctx.Com(), vca = ctx.ComVelocity();
  ctx.Fk(qb, vb);
  const Vector3d cb = ctx.Com(), vcb = ctx.ComVelocity();
  const Matrix3d Ra = dynamics::GetRootQuaternion(qa).normalized().toRotationMatrix();
  const Matrix3d Rb = dynamics::GetRootQuaternion(qb).normalized().toRotationMatrix();
  out.max_boundary_position_jump_m = std::max(out.max_boundary_position_jump_m, (ca - cb).norm());
  out.max_boundary_velocity_jump_m_per_s =
      std::max(out.max_boundary_velocity_jump_m_per_s, (vca - vcb).norm());
  out.max_boundary_orientation_jump_rad =
      std::max(out.max_boundary_orientation_jump_rad, LogSO3(Ra.transpose() * Rb).norm());
  out.max_boundary_angular_velocity_jump_rad_per_s =
      std::max(out.max_boundary_angular_velocity_jump_rad_per_s,
               (va.segment<3>(3) - vb.segment<3>(3)).norm());
  out.max_boundary_joint_jump_rad =
      std::max(out.max_boundary_joint_jump_rad, (qa.tail(nj) - qb.tail(nj)).cwiseAbs().maxCoeff());
  out.max_boundary_joint_rate_jump_rad_per_s =
      std::max(out.max_boundary_joint_rate_jump_rad_per_s,
               (va.tail(nj) - vb.tail(nj)).cwiseAbs().maxCoeff());
}

// C¹ continuity at every take-off and landing: the contact's state at its end (start) against
// the flight's first (last) state.
void MeasureBoundaryJumps(Context& ctx, const Timeline& timeline, SimulatedRoutine& out) {
  const std::vector<ContactPhase>& contacts = timeline.contacts;
  for (size_t i = 0; i < timeline.flights.size(); ++i) {
    const FlightPath& f = timeline.flights[i];
    VectorXd q, v;
    ContactState(ctx, contacts[i], contacts[i].run.t_end, contacts[i].run.y_end, &q, &v);
    CompareBoundaryStates(ctx, q, v, f.q0, f.v0, out);
    ContactState(ctx, contacts[i + 1], contacts[i + 1].t_start, contacts[i + 1].y_start, &q, &v);
    CompareBoundaryStates(ctx, q, v, f.q_land, f.v_land, out);
  }
}

// Ground truth of every flight (times, take-off and landing COM, apex, momentum, rotations) and
// every contact (times, peak force, depression).
void RecordGroundTruth(Context& ctx,
                       const Timeline& timeline,
                       const std::vector<SkillPlan>& plans,
                       SimulatedRoutine& out) {
  for (size_t i = 0; i < timeline.flights.size(); ++i) {
    const FlightPath& f = timeline.flights[i];
    const SkillPlan& plan = plans[i];
    RoutineFlightTruth t;
    t.name = plan.name;
    t.fig_code = plan.fig_code;
    t.takeoff_s = f.t0;
    t.landing_s = f.t0 + f.landing_rel;
    ctx.Fk(f.q0, f.v0);
    t.takeoff_com_m = ctx.Com();
    t.takeoff_vertical_velocity_m_per_s = ctx.ComVelocity().z();
    t.apex_com_z_m = t.takeoff_com_m.z() + t.takeoff_vertical_velocity_m_per_s *
                                               t.takeoff_vertical_velocity_m_per_s / (2 * ctx.g);
    t.H_Scm_W = dynamics::CalcCentroidalMomentum(ctx.model, *ctx.ws).rotational();
    ctx.Fk(f.q_land);
    t.landing_com_m = ctx.Com();
    t.landing_feet_m = ctx.Feet();
    t.air_somersault_rad = f.somersault_land - f.somersault0;
    t.air_twist_rad = f.twist_land;
    t.takeoff_lean_rad = f.somersault0;
    out.flights.push_back(t);
  }
  for (const ContactPhase& c : timeline.contacts) {
    RoutineContactTruth t;
    t.start_s = c.t_start;
    t.end_s = c.run.t_end;
    t.peak_force_body_weights = c.run.peak_force / (ctx.mass * ctx.g);
    t.max_depression_m = c.run.max_depth;
    t.push_rad = c.blend.push;
    t.takeoff_velocity_error_m_per_s = c.vz_error;
    out.contacts.push_back(t);
  }
}

}  // namespace

SimulatedRoutine SimulateRoutine(const AthleteProfile& athlete,
                                 const std::vector<RoutineSkillPlan>& plans,
                                 const RoutineSimulationOptions& options) {
  ACRO_DEMAND(!plans.empty());
  const AthleteBody body = MakeAthleteBody(athlete);
  Context ctx;
  SetUpContext(body, options, ctx);
  FindSoleCentres(ctx);

  SimulatedRoutine out;
  out.options = options;
  out.model = ctx.model;
  out.mass_kg = ctx.mass;
  out.gravity_m_per_s2 = ctx.g;

  // 1. Shoot every skill in its own heading (take-off at t = 0, COM above the origin).
  const Skills skills = ShootSkills(ctx, plans);

  // 2. Time line: the first contact (from the bottom of a bounce, standing), then per skill the
  // flight and the contact after it.
  const Timeline timeline = TimelineBuilder(ctx, skills, options.bed_centre_m.head<2>()).Build();

  // 3. Frames: noise-free q and v per frame, from the phase each frame time falls in.
  const double rate = options.point_rate_hz;
  const double t_last = timeline.phases.back().t_end;
  const int num_frames = static_cast<int>(std::floor(t_last * rate + 1e-9)) + 1;
  SampleFrames(ctx, timeline, num_frames, rate, out);

  // 4. C¹ continuity at every take-off and landing.
  MeasureBoundaryJumps(ctx, timeline, out);

  // 5. Ground truth.
  RecordGroundTruth(ctx, timeline, skills.plans, out);
  return out;
}

RoutineFlightPhysics CheckRoutineFlight(const Model& model,
                                        const Eigen::MatrixXd& q,
                                        const Eigen::MatrixXd& v,
                                        double rate,
                                        const RoutineFlightTruth& f) {
  Workspace ws(model);
  RoutineFlightPhysics out;
  std::vector<double> t, z;
  Vector3d H0 = Vector3d::Zero();
  Vector2d vxy0 = Vector2d::Zero();
  for (int fr = 0; fr < q.cols(); ++fr) {
    const double tf = fr / rate;
    if (tf <= f.takeoff_s || tf >= f.landing_s) continue;
    dynamics::CalcForwardKinematics(model, ws, q.col(fr), v.col(fr));
    const Vector3d H = dynamics::CalcCentroidalMomentum(model, ws).rotational();
    const Vector2d vxy = dynamics::CalcCenterOfMassVelocity(model, ws).head<2>();
    if (t.empty()) {
      H0 = H;
      vxy0 = vxy;
    }
    out.momentum_norm_N_m_s = H0.norm();
    out.max_relative_momentum_drift =
        std::max(out.max_relative_momentum_drift, (H - H0).norm() / std::max(1.0, H0.norm()));
    out.max_horizontal_velocity_change_m_per_s =
        std::max(out.max_horizontal_velocity_change_m_per_s, (vxy - vxy0).norm());
    t.push_back(tf - f.takeoff_s);
    z.push_back(dynamics::CalcCenterOfMassPosition(model, ws).z());
  }
  out.num_frames = int(t.size());
  // Least-squares parabola z = a + b t + c t² (QR of the Vandermonde matrix).
  Eigen::MatrixXd A(t.size(), 3);
  Eigen::VectorXd b(t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    A.row(long(i)) << 1.0, t[i], t[i] * t[i];
    b[long(i)] = z[i];
  }
  const Eigen::Vector3d coef = A.colPivHouseholderQr().solve(b);
  out.fitted_vertical_acceleration_m_per_s2 = 2 * coef[2];
  out.parabola_max_error_m = (A * coef - b).cwiseAbs().maxCoeff();
  return out;
}

}  // namespace acro::analysis
