#include "acro/assess/physical_check.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double FrameStep(const Motion& motion) {
  const int n = motion.num_frames();
  ACRO_DEMAND(n >= 2);
  return (motion.time_s[n - 1] - motion.time_s[0]) / (n - 1);
}

/// Rotation vector of R (axis × angle, angle in [0, π]).
Vector3d RotationVector(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

/// Derivative at sample i of a series given by `at(k)` (k = −2 … 2 relative to i, where they
/// exist among n samples): the five-point central stencil (truncation O(dt⁴); a body somersaulting
/// at 15 rad/s needs it — the three-point stencil's error of dt²/12·ω⁴·r is 0.03 m/s² at 200 Hz),
/// three-point or one-sided nearer the ends.
template <typename Value, typename Series>
Value FirstDerivative(int i, int n, double dt, const Series& at) {
  if (i >= 2 && i + 2 < n) return (at(-2) - 8.0 * at(-1) + 8.0 * at(1) - at(2)) / (12.0 * dt);
  const int lo = i > 0 ? -1 : 0;
  const int hi = i + 1 < n ? 1 : 0;
  return (at(hi) - at(lo)) / (static_cast<double>(hi - lo) * dt);
}

template <typename Value, typename Series>
Value SecondDerivative(int i, int n, double dt, const Series& at) {
  if (i >= 2 && i + 2 < n)
    return (-at(-2) + 16.0 * at(-1) - 30.0 * at(0) + 16.0 * at(1) - at(2)) / (12.0 * dt * dt);
  const int c = std::clamp(i, 1, n - 2) - i;  // the nearest three-point stencil
  return (at(c + 1) - 2.0 * at(c) + at(c - 1)) / (dt * dt);
}

/// First and second derivatives of the rows of x.
void Differentiate(const Eigen::MatrixXd& x, double dt, Eigen::MatrixXd& dx, Eigen::MatrixXd& ddx) {
  const int n = static_cast<int>(x.cols());
  dx.resize(x.rows(), n);
  ddx.resize(x.rows(), n);
  for (int i = 0; i < n; ++i) {
    const auto at = [&](int k) -> Eigen::VectorXd { return x.col(i + k); };
    dx.col(i) = FirstDerivative<Eigen::VectorXd>(i, n, dt, at);
    ddx.col(i) = SecondDerivative<Eigen::VectorXd>(i, n, dt, at);
  }
}

/// Angular velocities (and, when `wdot` is given, accelerations) of a sequence of orientations by
/// the five-point stencils on the rotation vectors relative to sample i: φ_k = Log(R_iᵀ R_k) in
/// the frame of sample i. With φ(t_i) = 0, φ̇ = J_r⁻¹(φ) ω_B gives φ̇(t_i) = ω_B, and since
/// J_r⁻¹(φ) = I + ½[φ]× + O(φ²), φ̈(t_i) = ½ ω_B × ω_B + ω̇_B = ω̇_B: both come from the same
/// samples, so the acceleration needs no second differencing of differenced velocities (which
/// would reach four frames instead of two). Returned in the moving frame (body = true) or in W.
Eigen::Matrix3Xd AngularVelocities(const std::vector<Matrix3d>& R,
                                   double dt,
                                   bool body,
                                   Eigen::Matrix3Xd* wdot = nullptr) {
  const int n = static_cast<int>(R.size());
  Eigen::Matrix3Xd w(3, n);
  if (wdot != nullptr) wdot->resize(3, n);
  for (int i = 0; i < n; ++i) {
    const Matrix3d& Ri = R[static_cast<size_t>(i)];
    const auto at = [&](int k) -> Vector3d {
      return k == 0 ? Vector3d::Zero()
                    : RotationVector(Ri.transpose() * R[static_cast<size_t>(i + k)]);
    };
    const Vector3d w_B = FirstDerivative<Vector3d>(i, n, dt, at);
    w.col(i) = body ? w_B : Vector3d(Ri * w_B);
    if (wdot != nullptr) {
      const Vector3d wdot_B = SecondDerivative<Vector3d>(i, n, dt, at);
      wdot->col(i) = body ? wdot_B : Vector3d(Ri * wdot_B);
    }
  }
  return w;
}

/// Frames of the complete flights that the check judged.
std::vector<int> JudgedFrames(const PhysicalCheck& check) {
  std::vector<int> frames;
  for (const FlightCheck& f : check.flights)
    for (int i = f.first_frame; i <= f.last_frame; ++i) frames.push_back(i);
  return frames;
}

}  // namespace

std::string FlightCheck::FailureText() const {
  std::string text;
  for (size_t i = 0; i < failures.size(); ++i) text += (i ? ", " : "") + failures[i];
  return text;
}

bool PhysicalCheckOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (!(max_force_bw > 0)) return fail("max_force_bw must be positive");
  if (!(max_moment_bwh > 0)) return fail("max_moment_bwh must be positive");
  if (!(max_momentum_variation > 0)) return fail("max_momentum_variation must be positive");
  if (!(momentum_floor_mh2_per_s > 0)) return fail("momentum_floor_mh2_per_s must be positive");
  if (!(max_gravity_error > 0)) return fail("max_gravity_error must be positive");
  if (!(max_marker_error_m > 0)) return fail("max_marker_error_m must be positive");
  if (std::isnan(edge_margin_s)) return fail("edge_margin_s is not a number");
  if (!(residual_window_s >= 0)) return fail("residual_window_s must be non-negative");
  if (!(noise_factor >= 1 && noise_factor < 100))
    return fail("noise_factor must be at least 1 (and below 100)");
  return true;
}

void CalcMotionDerivatives(const dynamics::Model<double>& model,
                           const Motion& motion,
                           Eigen::MatrixXd& v,
                           Eigen::MatrixXd& a) {
  ACRO_DEMAND(motion.nq() == model.nq());
  const int n = motion.num_frames();
  const int nj = model.num_joint_dofs();
  const double dt = FrameStep(motion);
  v.setZero(model.nv(), n);
  a.setZero(model.nv(), n);

  // Root position and joint angles: plain central differences.
  Eigen::MatrixXd x(3 + nj, n);
  x.topRows(3) = motion.q.topRows(3);
  x.bottomRows(nj) = motion.q.bottomRows(nj);
  Eigen::MatrixXd dx, ddx;
  Differentiate(x, dt, dx, ddx);
  v.topRows(3) = dx.topRows(3);
  a.topRows(3) = ddx.topRows(3);
  v.bottomRows(nj) = dx.bottomRows(nj);
  a.bottomRows(nj) = ddx.bottomRows(nj);

  // Root angular velocity in B and its rate.
  std::vector<Matrix3d> R(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    R[static_cast<size_t>(i)] =
        dynamics::GetRootQuaternion(motion.q.col(i)).normalized().toRotationMatrix();
  Eigen::Matrix3Xd wdot;
  v.middleRows(3, 3) = AngularVelocities(R, dt, /*body=*/true, &wdot);
  a.middleRows(3, 3) = wdot;
}

FrameDynamics CalcFrameDynamics(const dynamics::Model<double>& model,
                                const Motion& motion,
                                double height_m) {
  ACRO_DEMAND(height_m > 0);
  FrameDynamics out;
  CalcMotionDerivatives(model, motion, out.v, out.a);
  const int n = motion.num_frames();
  out.joint_torque_Nm.resize(model.num_joint_dofs(), n);
  out.force_bw.resize(3, n);
  out.moment_bwh.resize(3, n);
  out.com_W.resize(3, n);
  out.angular_momentum.resize(3, n);
  dynamics::Workspace<double> ws(model);
  Eigen::VectorXd q(model.nq()), v(model.nv()), a(model.nv());
  for (int i = 0; i < n; ++i) {
    q = motion.q.col(i);
    v = out.v.col(i);
    a = out.a.col(i);
    const Eigen::VectorXd& tau = dynamics::CalcInverseDynamics(model, ws, q, v, a);
    out.joint_torque_Nm.col(i) = tau.tail(model.num_joint_dofs());
    const dynamics::RootResidual<double> r = dynamics::CalcRootResidual(model, ws, height_m);
    out.force_bw.col(i) = r.force_per_weight;
    out.moment_bwh.col(i) = r.moment_per_weight_height;
    dynamics::CalcForwardKinematics(model, ws, q, v);
    out.com_W.col(i) = dynamics::CalcCenterOfMassPosition(model, ws);
    out.angular_momentum.col(i) = dynamics::CalcCentroidalMomentum(model, ws).rotational();
  }
  return out;
}

Eigen::MatrixXd CalcSegmentWrenches(const dynamics::Model<double>& model,
                                    const Motion& motion,
                                    const Vector3d& p_WoP_W) {
  const int n = motion.num_frames();
  const int ns = model.num_segments();
  const double dt = FrameStep(motion);
  // Segment centres of mass and orientations on every frame.
  Eigen::Matrix3Xd c(3, static_cast<Eigen::Index>(n) * ns);
  std::vector<Matrix3d> R(static_cast<size_t>(n) * static_cast<size_t>(ns));
  dynamics::Workspace<double> ws(model);
  Eigen::VectorXd q(model.nq());
  for (int i = 0; i < n; ++i) {
    q = motion.q.col(i);
    dynamics::CalcForwardKinematics(model, ws, q);
    for (int s = 0; s < ns; ++s) {
      const auto& X = ws.X_WB[static_cast<size_t>(s)];
      c.col(static_cast<Eigen::Index>(i) * ns + s) =
          X.rotation() * model.segment(s).p_BoBcm_B + X.translation();
      R[static_cast<size_t>(i * ns + s)] = X.rotation();
    }
  }
  // Angular velocities and accelerations in W (ω̇_W = R ω̇_B, as Ṙ ω_B = R [ω_B]× ω_B = 0).
  Eigen::Matrix3Xd w(3, static_cast<Eigen::Index>(n) * ns);
  Eigen::Matrix3Xd wdot(3, static_cast<Eigen::Index>(n) * ns);
  for (int s = 0; s < ns; ++s) {
    std::vector<Matrix3d> Rs(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) Rs[static_cast<size_t>(i)] = R[static_cast<size_t>(i * ns + s)];
    Eigen::Matrix3Xd wdot_W;
    const Eigen::Matrix3Xd w_W = AngularVelocities(Rs, dt, /*body=*/false, &wdot_W);
    for (int i = 0; i < n; ++i) {
      w.col(static_cast<Eigen::Index>(i) * ns + s) = w_W.col(i);
      wdot.col(static_cast<Eigen::Index>(i) * ns + s) = wdot_W.col(i);
    }
  }
  const Vector3d& g = model.gravity_W();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(6 * ns, n);
  for (int i = 2; i + 2 < n; ++i) {
    for (int s = 0; s < ns; ++s) {
      const auto col = [&](int frame) { return static_cast<Eigen::Index>(frame) * ns + s; };
      const dynamics::Segment<double>& seg = model.segment(s);
      const Vector3d acc = SecondDerivative<Vector3d>(
          i, n, dt, [&](int k) -> Vector3d { return c.col(col(i + k)); });
      const Vector3d omega = w.col(col(i));
      const Vector3d alpha = wdot.col(col(i));
      const Matrix3d& Rs = R[static_cast<size_t>(i * ns + s)];
      const Matrix3d I_W = Rs * seg.I_BBcm_B * Rs.transpose();
      const Vector3d f = seg.mass * (acc - g);
      const Vector3d n_P =
          I_W * alpha + omega.cross(I_W * omega) + (c.col(col(i)) - p_WoP_W).cross(f);
      out.block<3, 1>(6 * s, i) = n_P;
      out.block<3, 1>(6 * s + 3, i) = f;
    }
  }
  return out;
}

namespace {

// ---- CheckPhysics' steps ----

// What every flight is judged with: the frame step, the frames (and seconds) left out at each
// end, g, and the floor of the angular momentum the variation is relative to.
struct FlightJudging {
  double dt = 0.0;
  int margin = 0;
  double margin_s = 0.0;
  double g = 0.0;
  double L_floor = 0.0;
};

// Peak and RMS of the residual force and moment over the flight's judged frames.
void MeasureResidualPeaks(const FrameDynamics& frames, FlightCheck& fc) {
  const int m = fc.last_frame - fc.first_frame + 1;
  const auto force = frames.force_bw.middleCols(fc.first_frame, m).colwise().norm();
  const auto moment = frames.moment_bwh.middleCols(fc.first_frame, m).colwise().norm();
  fc.peak_force_bw = force.maxCoeff();
  fc.rms_force_bw = std::sqrt(force.array().square().mean());
  fc.peak_moment_bwh = moment.maxCoeff();
  fc.rms_moment_bwh = std::sqrt(moment.array().square().mean());
}

// The judged residual: the mean over every window of residual_window_s inside the judged frames
// (the whole judged span when it is shorter), by a running sum. Each window's mean goes to the
// check at the window's centre frame; the largest, and where its window starts, to fc.
void MeasureWindowedResidual(const Motion& motion,
                             double residual_window_s,
                             double dt,
                             FlightCheck& fc,
                             PhysicalCheck& check) {
  const int m = fc.last_frame - fc.first_frame + 1;
  const int w = std::clamp(static_cast<int>(std::lround(residual_window_s / dt)), 1, m);
  const Eigen::VectorXd wf =
      WindowedMeanNorms(check.frames.force_bw.middleCols(fc.first_frame, m), w);
  const Eigen::VectorXd wm =
      WindowedMeanNorms(check.frames.moment_bwh.middleCols(fc.first_frame, m), w);
  for (Eigen::Index a = 0; a < wf.size(); ++a) {
    check.window_force_bw[fc.first_frame + a + w / 2] = wf[a];
    check.window_moment_bwh[fc.first_frame + a + w / 2] = wm[a];
    if (wf[a] > fc.window_force_bw) {
      fc.window_force_bw = wf[a];
      fc.window_force_at_s = motion.time_s[fc.first_frame + a];
    }
    if (wm[a] > fc.window_moment_bwh) {
      fc.window_moment_bwh = wm[a];
      fc.window_moment_at_s = motion.time_s[fc.first_frame + a];
    }
  }
}

// |mean L| over the judged frames, and the largest difference between two of them relative to
// it (at least L_floor).
void MeasureMomentumVariation(const FrameDynamics& frames, double L_floor, FlightCheck& fc) {
  const int m = fc.last_frame - fc.first_frame + 1;
  const Eigen::Matrix3Xd L = frames.angular_momentum.middleCols(fc.first_frame, m);
  fc.mean_angular_momentum = L.rowwise().mean().norm();
  fc.momentum_variation = CalcMomentumVariation(L, L_floor);
}

// The gravity the COM falls with over the judged frames.
void FitGravity(const Motion& motion, const FrameDynamics& frames, FlightCheck& fc) {
  const int m = fc.last_frame - fc.first_frame + 1;
  fc.fitted_gravity_m_per_s2 = FitFallingGravity(motion.time_s.segment(fc.first_frame, m),
                                                 frames.com_W.row(2).segment(fc.first_frame, m));
}

// The largest marker error of the judged frames' valid fits.
void MeasureMarkerError(const Motion& motion, FlightCheck& fc) {
  for (int i = fc.first_frame; i <= fc.last_frame; ++i) {
    const FrameFit& fit = motion.fit[static_cast<size_t>(i)];
    if (fit.valid) fc.max_marker_error_m = std::max(fc.max_marker_error_m, fit.max_m);
  }
}

// The limits a flight is judged with: the thresholds, each raised to noise_factor times what the
// noise alone gives when the flight has a noise floor.
struct FlightLimits {
  double force_bw, moment_bwh, momentum_variation, gravity_error_m_per_s2, marker_error_m;
  bool raised = false;  // some limit is the noise's
};

FlightLimits LimitsOf(const FlightCheck& fc, const PhysicalCheckOptions& options, double g) {
  FlightLimits l{options.max_force_bw,
                 options.max_moment_bwh,
                 options.max_momentum_variation,
                 options.max_gravity_error * g,
                 options.max_marker_error_m};
  if (!fc.noise) return l;
  const FlightNoiseFloor& n = *fc.noise;
  const double k = options.noise_factor;
  auto raise = [&](double& limit, double floor) {
    if (k * floor > limit) {
      limit = k * floor;
      l.raised = true;
    }
  };
  raise(l.force_bw, n.window_force_bw);
  raise(l.moment_bwh, n.window_moment_bwh);
  raise(l.momentum_variation, n.momentum_variation);
  raise(l.gravity_error_m_per_s2, n.gravity_error_m_per_s2);
  raise(l.marker_error_m, n.max_marker_error_m);
  return l;
}

// The criteria the flight's measures fail, each with its numbers (and, where the noise set the
// limit, how far beyond what the noise alone gives).
std::vector<std::string> ListFailures(const FlightCheck& fc,
                                      const PhysicalCheckOptions& options,
                                      double g) {
  const FlightLimits limit = LimitsOf(fc, options, g);
  std::vector<std::string> failures;
  const std::string over =
      options.residual_window_s > 0 ? fmt::format(" over {:.2f} s", options.residual_window_s) : "";
  // "(4.2× the noise's)" when the noise floor set this limit.
  auto beyond = [&](double value, double threshold, double floor) {
    return fc.noise && options.noise_factor * floor > threshold && floor > 0
               ? fmt::format(" ({:.1f}× the noise's)", value / floor)
               : std::string();
  };
  const FlightNoiseFloor floor = fc.noise.value_or(FlightNoiseFloor{});
  if (fc.window_force_bw > limit.force_bw)
    failures.push_back(fmt::format("residual force {:.3f} BW > {:.3f} at {:.2f} s",
                                   fc.window_force_bw,
                                   limit.force_bw,
                                   fc.window_force_at_s) +
                       over +
                       beyond(fc.window_force_bw, options.max_force_bw, floor.window_force_bw));
  if (fc.window_moment_bwh > limit.moment_bwh)
    failures.push_back(
        fmt::format("residual moment {:.4f} BW·h > {:.4f} at {:.2f} s",
                    fc.window_moment_bwh,
                    limit.moment_bwh,
                    fc.window_moment_at_s) +
        over + beyond(fc.window_moment_bwh, options.max_moment_bwh, floor.window_moment_bwh));
  if (fc.momentum_variation > limit.momentum_variation)
    failures.push_back(
        fmt::format("angular momentum varies {:.0f} % > {:.0f} %",
                    100 * fc.momentum_variation,
                    100 * limit.momentum_variation) +
        beyond(fc.momentum_variation, options.max_momentum_variation, floor.momentum_variation));
  const double gravity_error = std::abs(fc.fitted_gravity_m_per_s2 - g);
  if (gravity_error > limit.gravity_error_m_per_s2)
    failures.push_back(
        fmt::format("COM falls with {:.2f} m/s² instead of {:.2f}", fc.fitted_gravity_m_per_s2, g) +
        beyond(gravity_error, options.max_gravity_error * g, floor.gravity_error_m_per_s2));
  if (fc.max_marker_error_m > limit.marker_error_m)
    failures.push_back(
        fmt::format("marker error {:.1f} cm > {:.1f} cm",
                    100 * fc.max_marker_error_m,
                    100 * limit.marker_error_m) +
        beyond(fc.max_marker_error_m, options.max_marker_error_m, floor.max_marker_error_m));
  return failures;
}

// Judges complete flight k on its frames without the margins: its measures and the criteria they
// fail (a flight too short to judge fails for that). The windowed residual goes to the check.
FlightCheck JudgeFlight(const Motion& motion,
                        int k,
                        const Flight& flight,
                        const FlightJudging& judging,
                        const PhysicalCheckOptions& options,
                        PhysicalCheck& check) {
  const int n = motion.num_frames();
  FlightCheck fc;
  fc.flight = k;
  fc.first_frame = std::max(flight.takeoff_frame + judging.margin, 0);
  fc.last_frame = std::min(flight.landing_frame - 1 - judging.margin, n - 1);
  if (fc.last_frame - fc.first_frame < 4) {
    fc.pass = false;
    fc.failures.push_back("too short to judge once " +
                          fmt::format("{:.0f} ms", 1e3 * judging.margin_s) +
                          " are left out at each end");
    return fc;
  }
  MeasureResidualPeaks(check.frames, fc);
  MeasureWindowedResidual(motion, options.residual_window_s, judging.dt, fc, check);
  MeasureMomentumVariation(check.frames, judging.L_floor, fc);
  FitGravity(motion, check.frames, fc);
  MeasureMarkerError(motion, fc);
  fc.failures = ListFailures(fc, options, judging.g);
  fc.pass = fc.failures.empty();
  return fc;
}

// Contact phases: the frames between flights (partial ones included), each with its peak
// residual force (the bed's reaction) and when it occurs.
std::vector<ContactLoad> FindContactLoads(const FrameDynamics& frames,
                                          const Motion& motion,
                                          const std::vector<Flight>& flights) {
  const int n = motion.num_frames();
  std::vector<ContactLoad> contacts;
  int start = 0;
  auto add_contact = [&](int first, int last) {
    first = std::max(first, 0);
    last = std::min(last, n - 1);
    if (last < first) return;
    ContactLoad c;
    c.first_frame = first;
    c.last_frame = last;
    Eigen::Index peak = 0;
    c.peak_force_bw =
        frames.force_bw.middleCols(first, last - first + 1).colwise().norm().maxCoeff(&peak);
    c.peak_s = motion.time_s[first + static_cast<int>(peak)];
    contacts.push_back(c);
  };
  for (const Flight& flight : flights) {
    add_contact(start, flight.takeoff_frame - 1);
    start = flight.landing_frame;
  }
  add_contact(start, n - 1);
  return contacts;
}

// Pass when every judged flight passes; the verdict names each failing flight's failures, and the
// noise when a flight was judged against it.
void SetVerdict(PhysicalCheck& check) {
  check.pass = true;
  bool against_noise = false;
  std::string causes;
  for (const FlightCheck& fc : check.flights) {
    against_noise = against_noise || fc.judged_against_noise;
    if (fc.pass) continue;
    check.pass = false;
    if (!causes.empty()) causes += "; ";
    causes += "flight " + std::to_string(fc.flight + 1) + ": " + fc.FailureText();
  }
  const std::string noise = fmt::format("its noise (≈ {:.1f} mm per coordinate, {})",
                                        1e3 * check.noise_rms_m,
                                        check.data_class.empty() ? "markers" : check.data_class);
  if (check.flights.empty())
    check.verdict = "not judged: no complete flight";
  else if (!against_noise)
    check.verdict = check.pass ? "pass" : "fail: " + causes;
  else
    check.verdict = check.pass ? "pass within " + noise : "fail beyond " + noise + ": " + causes;
}

}  // namespace

PhysicalCheck CheckPhysics(const dynamics::Model<double>& model,
                           const Motion& motion,
                           const std::vector<Flight>& flights,
                           double height_m,
                           double cutoff_hz,
                           const PhysicalCheckOptions& options) {
  DemandValidOptions(options, "physical check options");
  PhysicalCheck check;
  check.frames = CalcFrameDynamics(model, motion, height_m);
  const int n = motion.num_frames();

  // The margin left out at each end of a flight: given, or two frames and half the filter's
  // cutoff period, whichever is longer.
  FlightJudging judging;
  judging.dt = FrameStep(motion);
  judging.margin_s = options.edge_margin_s >= 0
                         ? options.edge_margin_s
                         : std::max(2.0 * judging.dt, cutoff_hz > 0 ? 0.5 / cutoff_hz : 0.0);
  check.edge_margin_s = judging.margin_s;
  check.height_m = height_m;
  judging.margin = static_cast<int>(std::ceil(judging.margin_s / judging.dt - 1e-9));
  const double mass = model.total_mass();
  judging.g = model.gravity_W().norm();
  check.gravity_m_per_s2 = judging.g;
  judging.L_floor = options.momentum_floor_mh2_per_s * mass * height_m * height_m;
  check.window_force_bw = Eigen::VectorXd::Constant(n, kNaN);
  check.window_moment_bwh = Eigen::VectorXd::Constant(n, kNaN);

  // Each complete flight judged; the contacts between them; the verdict.
  for (size_t k = 0; k < flights.size(); ++k)
    if (!flights[k].partial)
      check.flights.push_back(
          JudgeFlight(motion, static_cast<int>(k), flights[k], judging, options, check));
  check.contacts = FindContactLoads(check.frames, motion, flights);
  SetVerdict(check);
  return check;
}

double CalcMomentumVariation(const Eigen::Matrix3Xd& L, double floor) {
  double spread = 0.0;
  for (Eigen::Index i = 0; i < L.cols(); ++i)
    for (Eigen::Index j = i + 1; j < L.cols(); ++j)
      spread = std::max(spread, (L.col(i) - L.col(j)).norm());
  return spread / std::max(L.rowwise().mean().norm(), floor);
}

double FitFallingGravity(const Eigen::VectorXd& time_s, const Eigen::VectorXd& z) {
  ACRO_DEMAND(time_s.size() == z.size() && z.size() >= 3);
  Eigen::MatrixXd A(z.size(), 3);
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    const double t = time_s[i] - time_s[0];
    A.row(i) << 1.0, t, t * t;
  }
  return -2.0 * A.colPivHouseholderQr().solve(z)[2];
}

Eigen::VectorXd WindowedMeanNorms(const Eigen::Matrix3Xd& x, int window) {
  const int m = static_cast<int>(x.cols());
  if (m == 0) return Eigen::VectorXd();
  const int w = std::clamp(window, 1, m);
  Eigen::VectorXd out(m - w + 1);
  Eigen::Vector3d sum = x.leftCols(w).rowwise().sum();
  for (int a = 0;; ++a) {
    out[a] = sum.norm() / w;
    if (a + w >= m) break;
    sum += x.col(a + w) - x.col(a);
  }
  return out;
}

void JudgeAgainstNoise(PhysicalCheck& check,
                       const std::vector<FlightNoiseFloor>& floors,
                       double noise_rms_m,
                       const std::string& data_class,
                       const PhysicalCheckOptions& options) {
  DemandValidOptions(options, "physical check options");
  ACRO_DEMAND(floors.size() == check.flights.size());
  check.noise_rms_m = noise_rms_m;
  check.data_class = data_class;
  for (size_t k = 0; k < floors.size(); ++k) {
    FlightCheck& fc = check.flights[k];
    if (fc.last_frame - fc.first_frame < 4) continue;  // too short to judge: stays so
    // Judged against the noise when the thresholds alone fail the flight and the floor raised a
    // limit: a flight within the thresholds passes as it would without the floor ("pass").
    fc.noise.reset();
    const bool fails_thresholds = !ListFailures(fc, options, check.gravity_m_per_s2).empty();
    fc.noise = floors[k];
    fc.judged_against_noise =
        fails_thresholds && LimitsOf(fc, options, check.gravity_m_per_s2).raised;
    fc.failures = ListFailures(fc, options, check.gravity_m_per_s2);
    fc.pass = fc.failures.empty();
  }
  SetVerdict(check);
}

MassSuggestion SuggestSegmentMasses(const dynamics::Model<double>& model,
                                    const Motion& motion,
                                    const PhysicalCheck& check,
                                    double height_m) {
  MassSuggestion out;
  const int ns = model.num_segments();
  out.current_kg.resize(ns);
  for (int s = 0; s < ns; ++s) {
    out.segments.push_back(model.segment(s).name);
    out.current_kg[s] = model.segment(s).mass;
  }
  out.suggested_kg = out.current_kg;
  const std::vector<int> frames = JudgedFrames(check);
  if (frames.size() < 8) return out;
  Vector3d P = Vector3d::Zero();
  for (int i : frames) P += check.frames.com_W.col(i);
  P /= static_cast<double>(frames.size());
  const Eigen::MatrixXd W = CalcSegmentWrenches(model, motion, P);
  const double mass = model.total_mass();
  const double weight = mass * model.gravity_W().norm();
  // A k = the normalised residual of the judged frames for segment mass scale factors k.
  Eigen::MatrixXd A(6 * static_cast<Eigen::Index>(frames.size()), ns);
  for (size_t r = 0; r < frames.size(); ++r)
    for (int s = 0; s < ns; ++s) {
      const auto wrench = W.block<6, 1>(6 * s, frames[r]);
      A.block<3, 1>(6 * static_cast<Eigen::Index>(r), s) = wrench.head<3>() / (weight * height_m);
      A.block<3, 1>(6 * static_cast<Eigen::Index>(r) + 3, s) = wrench.tail<3>() / weight;
    }
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(ns);
  const double rows = static_cast<double>(A.rows());
  out.residual_before = std::sqrt((A * ones).squaredNorm() / rows);
  // min |A k|² + λ |k − 1|²  subject to  Σ m_s k_s = m (the weighed mass is kept) and
  // kMinScale ≤ k_s ≤ kMaxScale (a segment is neither massless nor four times its regression): the
  // KKT system, with an active set for the bounds (a bound that the free solution crosses is held
  // there and the rest solved again). λ is a small ridge that keeps segments the flights cannot
  // tell apart at their current mass.
  constexpr double kMinScale = 0.25, kMaxScale = 4.0;
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const double lambda = 1e-3 * AtA.trace() / ns;
  std::vector<double> fixed(static_cast<size_t>(ns), kNaN);  // held scale, or NaN when free
  Eigen::VectorXd k = ones;
  for (int pass = 0; pass <= ns; ++pass) {
    // Unknowns: the free scales and the multiplier; held ones move to the right-hand side.
    std::vector<int> free_index;
    for (int s = 0; s < ns; ++s)
      if (std::isnan(fixed[static_cast<size_t>(s)])) free_index.push_back(s);
    const int nf = static_cast<int>(free_index.size());
    Eigen::VectorXd held = Eigen::VectorXd::Zero(ns);
    for (int s = 0; s < ns; ++s)
      if (!std::isnan(fixed[static_cast<size_t>(s)])) held[s] = fixed[static_cast<size_t>(s)];
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nf + 1, nf + 1);
    Eigen::VectorXd rhs(nf + 1);
    const Eigen::VectorXd coupling = AtA * held;
    for (int a = 0; a < nf; ++a) {
      const int sa = free_index[static_cast<size_t>(a)];
      for (int b = 0; b < nf; ++b) K(a, b) = AtA(sa, free_index[static_cast<size_t>(b)]);
      K(a, a) += lambda;
      K(a, nf) = out.current_kg[sa];
      K(nf, a) = out.current_kg[sa];
      rhs[a] = lambda - coupling[sa];
    }
    rhs[nf] = mass - out.current_kg.dot(held);
    const Eigen::VectorXd solution = K.fullPivLu().solve(rhs);
    k = held;
    bool crossed = false;
    for (int a = 0; a < nf; ++a) {
      const int sa = free_index[static_cast<size_t>(a)];
      k[sa] = solution[a];
      if (k[sa] < kMinScale || k[sa] > kMaxScale) {
        fixed[static_cast<size_t>(sa)] = std::clamp(k[sa], kMinScale, kMaxScale);
        crossed = true;
      }
    }
    if (!crossed) break;
  }
  out.suggested_kg = k.cwiseProduct(out.current_kg);
  out.residual_after = std::sqrt((A * k).squaredNorm() / rows);
  return out;
}

namespace {

// ---- LocalisePhysicsFailure's finders ----

// The measured and the model's positions of nm markers on every frame, frame-major, and how far
// apart they are.
class MarkerResiduals {
 public:
  MarkerResiduals(const Eigen::Matrix3Xd& measured, Eigen::Matrix3Xd predicted, int nm)
      : measured_(measured), predicted_(std::move(predicted)), nm_(nm) {}

  auto measured(int frame, int j) const {
    return measured_.col(static_cast<Eigen::Index>(frame) * nm_ + j);
  }
  auto predicted(int frame, int j) const {
    return predicted_.col(static_cast<Eigen::Index>(frame) * nm_ + j);
  }
  bool present(int frame, int j) const { return std::isfinite(measured(frame, j)[0]); }
  // |measured − predicted| (m), NaN where the marker is missing.
  double error(int frame, int j) const {
    return present(frame, j) ? (measured(frame, j) - predicted(frame, j)).norm() : kNaN;
  }

 private:
  const Eigen::Matrix3Xd& measured_;
  const Eigen::Matrix3Xd predicted_;
  const int nm_;
};

// The model's marker positions on every frame, frame-major.
Eigen::Matrix3Xd CalcModelMarkerPositions(const dynamics::Model<double>& model,
                                          const Motion& motion,
                                          const std::vector<ModelMarker>& markers) {
  const int n = motion.num_frames();
  const int nm = static_cast<int>(markers.size());
  Eigen::Matrix3Xd model_positions(3, static_cast<Eigen::Index>(n) * nm);
  dynamics::Workspace<double> ws(model);
  Eigen::VectorXd q(model.nq());
  for (int i = 0; i < n; ++i) {
    q = motion.q.col(i);
    dynamics::CalcForwardKinematics(model, ws, q);
    for (int j = 0; j < nm; ++j) {
      const auto& X = ws.X_WB[static_cast<size_t>(markers[static_cast<size_t>(j)].segment)];
      model_positions.col(static_cast<Eigen::Index>(i) * nm + j) =
          X.rotation() * markers[static_cast<size_t>(j)].p_BoM_B + X.translation();
    }
  }
  return model_positions;
}

// 1. Swaps: two markers far (beyond threshold) from their own model positions and each close to
// the other's, on 3 frames or more. One finding per pair; the pair is marked in `named`.
std::vector<Finding> FindSwappedMarkers(const MarkerResiduals& residuals,
                                        const std::vector<ModelMarker>& markers,
                                        const Motion& motion,
                                        double threshold,
                                        std::vector<bool>& named) {
  const int n = motion.num_frames();
  const int nm = static_cast<int>(markers.size());
  // The frames on which each pair (a < b) looks exchanged.
  std::vector<std::vector<int>> swap_frames(static_cast<size_t>(nm) * nm);
  for (int i = 0; i < n; ++i) {
    std::vector<int> bad;
    for (int j = 0; j < nm; ++j)
      if (residuals.error(i, j) > threshold) bad.push_back(j);
    for (size_t x = 0; x < bad.size(); ++x)
      for (size_t y = x + 1; y < bad.size(); ++y) {
        const int a = bad[x], b = bad[y];
        if ((residuals.measured(i, a) - residuals.predicted(i, b)).norm() < threshold &&
            (residuals.measured(i, b) - residuals.predicted(i, a)).norm() < threshold)
          swap_frames[static_cast<size_t>(a * nm + b)].push_back(i);
      }
  }
  // A finding for each pair exchanged on 3 frames or more.
  std::vector<Finding> findings;
  for (int a = 0; a < nm; ++a)
    for (int b = a + 1; b < nm; ++b) {
      const std::vector<int>& f = swap_frames[static_cast<size_t>(a * nm + b)];
      if (f.size() < 3) continue;
      Finding finding;
      finding.kind = Finding::Kind::kSwap;
      finding.names = {markers[static_cast<size_t>(a)].name, markers[static_cast<size_t>(b)].name};
      finding.value = static_cast<double>(f.size());
      finding.text =
          "markers " + finding.names[0] + " and " + finding.names[1] + " are swapped in " +
          std::to_string(f.size()) + " frames (" +
          fmt::format("{:.3f}–{:.3f} s", motion.time_s[f.front()], motion.time_s[f.back()]) +
          "): relabel them";
      named[static_cast<size_t>(a)] = named[static_cast<size_t>(b)] = true;
      findings.push_back(finding);
    }
  return findings;
}

// A pair of markers on one segment and how much later b is recorded than a (s).
struct PairLag {
  int a, b;
  double lag_s;
};

// The lag of marker b relative to marker a (same segment) that makes their distance steadiest
// over the judged frames, searched in quarter frames within ±`steps`/4 frames and refined by a
// parabola through the best three; none when the pair cannot be trusted.
std::optional<double> EstimatePairLag(const MarkerResiduals& residuals,
                                      const std::vector<int>& frames,
                                      int n,
                                      double dt,
                                      int steps,
                                      int a,
                                      int b) {
  // b's position at frame i + δ/dt by linear interpolation (NaN outside or across a gap).
  auto shifted = [&](int j, int i, double frames_ahead) -> Vector3d {
    const double x = i + frames_ahead;
    const int k = static_cast<int>(std::floor(x));
    if (k < 0 || k + 1 >= n) return Vector3d::Constant(kNaN);
    const double u = x - k;
    return (1 - u) * residuals.measured(k, j) + u * residuals.measured(k + 1, j);
  };
  // Variance of the distance for every candidate lag.
  std::vector<double> variance(static_cast<size_t>(2 * steps + 1), kNaN);
  for (int s = -steps; s <= steps; ++s) {
    double sum = 0, sum2 = 0;
    int count = 0;
    for (int i : frames) {
      if (!residuals.present(i, a)) continue;
      const Vector3d pb = shifted(b, i, s / 4.0);
      if (!std::isfinite(pb[0])) continue;
      const double d = (residuals.measured(i, a) - pb).norm();
      sum += d;
      sum2 += d * d;
      ++count;
    }
    if (count < static_cast<int>(frames.size()) * 3 / 4) continue;
    variance[static_cast<size_t>(s + steps)] =
        std::max(0.0, sum2 / count - (sum / count) * (sum / count));
  }
  // The steadiest lag, strictly inside the range.
  int best = -1;
  for (int s = 0; s <= 2 * steps; ++s)
    if (std::isfinite(variance[static_cast<size_t>(s)]) &&
        (best < 0 || variance[static_cast<size_t>(s)] < variance[static_cast<size_t>(best)]))
      best = s;
  const double at_zero = variance[static_cast<size_t>(steps)];
  if (best <= 0 || best >= 2 * steps || !std::isfinite(at_zero)) return std::nullopt;
  // Trust a pair whose distance varies by more than marker noise at zero lag and that a lag
  // makes clearly steadier.
  if (std::sqrt(at_zero) < 0.002 || at_zero < 2.0 * variance[static_cast<size_t>(best)])
    return std::nullopt;
  // Sub-step refinement by the parabola through the best and its neighbours.
  const double v0 = variance[static_cast<size_t>(best - 1)],
               v1 = variance[static_cast<size_t>(best)],
               v2 = variance[static_cast<size_t>(best + 1)];
  double step = best - steps;
  if (std::isfinite(v0) && std::isfinite(v2) && v0 - 2 * v1 + v2 > 0)
    step += 0.5 * (v0 - v2) / (v0 - 2 * v1 + v2);
  return step / 4.0 * dt;
}

// The timing finding from the pairs' lags: per-marker lags by least squares (lag_b − lag_a = pair
// lag, their mean pinned to zero); the lagging group is the markers more than half the spread
// above the earliest, reported when the spread exceeds half a frame and 8 ms.
std::optional<Finding> FindLaggingGroup(const std::vector<PairLag>& pairs,
                                        const std::vector<ModelMarker>& markers,
                                        double dt) {
  const int nm = static_cast<int>(markers.size());
  // Per-marker lags.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(pairs.size()) + 1, nm);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(A.rows());
  std::vector<bool> involved(static_cast<size_t>(nm), false);
  for (size_t r = 0; r < pairs.size(); ++r) {
    A(static_cast<Eigen::Index>(r), pairs[r].b) = 1.0;
    A(static_cast<Eigen::Index>(r), pairs[r].a) = -1.0;
    rhs[static_cast<Eigen::Index>(r)] = pairs[r].lag_s;
    involved[static_cast<size_t>(pairs[r].a)] = involved[static_cast<size_t>(pairs[r].b)] = true;
  }
  for (int j = 0; j < nm; ++j) A(A.rows() - 1, j) = 1.0;
  const Eigen::VectorXd lag = A.completeOrthogonalDecomposition().solve(rhs);
  // Their spread among the markers of some pair.
  std::vector<std::pair<double, int>> lags;
  for (int j = 0; j < nm; ++j)
    if (involved[static_cast<size_t>(j)]) lags.emplace_back(lag[j], j);
  std::sort(lags.begin(), lags.end());
  const double lo = lags.front().first, hi = lags.back().first;
  if (!(hi - lo > std::max(0.5 * dt, 0.008))) return std::nullopt;
  // The late group, and how much later than the early one it is on average.
  Finding finding;
  finding.kind = Finding::Kind::kTiming;
  std::vector<double> late, early;
  for (const auto& [value, j] : lags) {
    if (value > 0.5 * (lo + hi)) {
      finding.names.push_back(markers[static_cast<size_t>(j)].name);
      late.push_back(value);
    } else {
      early.push_back(value);
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m += x;
    return m / static_cast<double>(v.size());
  };
  finding.value = mean(late) - mean(early);
  std::string list;
  for (size_t i = 0; i < finding.names.size(); ++i) list += (i ? ", " : "") + finding.names[i];
  finding.text = "timing: markers " + list +
                 fmt::format(" lag the others by {:.0f} ms", 1e3 * finding.value) +
                 " (unsynchronised cameras or a time shift in the data)";
  return finding;
}

// 2. Timing: markers recorded late. Two markers on one rigid segment keep their distance; if
// one of them lags by δ, the distance between a's position at t and b's at t + δ is the one
// that stays constant. Each pair's relative lag is the δ that makes their distance steadiest over
// the judged frames (8 or more); the per-marker lags follow by least squares over the pairs.
std::optional<Finding> FindTimingLag(const MarkerResiduals& residuals,
                                     const std::vector<ModelMarker>& markers,
                                     const std::vector<int>& frames,
                                     int n,
                                     double dt) {
  if (frames.size() < 8) return std::nullopt;
  const int nm = static_cast<int>(markers.size());
  const double max_lag_s = 0.05;
  const int steps = static_cast<int>(std::ceil(max_lag_s / dt)) * 4;  // quarter frames
  std::vector<PairLag> pairs;
  for (int a = 0; a < nm; ++a)
    for (int b = a + 1; b < nm; ++b) {
      if (markers[static_cast<size_t>(a)].segment != markers[static_cast<size_t>(b)].segment)
        continue;
      const std::optional<double> lag_s = EstimatePairLag(residuals, frames, n, dt, steps, a, b);
      if (lag_s) pairs.push_back({a, b, *lag_s});
    }
  if (pairs.size() < 2) return std::nullopt;
  return FindLaggingGroup(pairs, markers, dt);
}

// 3. Segment masses that best zero the flight residuals: a finding when the suggestion halves
// the residual with no segment at a bound of its range, and changes some segment's mass by more
// than 25 % (the one or two largest changes named).
std::optional<Finding> FindSegmentMassFinding(const MassSuggestion& ms) {
  // A suggestion that needs a segment at a bound of its range does not describe a wrong mass
  // (noise or kinematics the masses cannot explain): not reported as a cause.
  bool at_bound = false;
  for (Eigen::Index s = 0; s < ms.current_kg.size(); ++s) {
    const double scale = ms.suggested_kg[s] / ms.current_kg[s];
    at_bound = at_bound || scale < 0.25 + 1e-6 || scale > 4.0 - 1e-6;
  }
  if (at_bound || !(ms.residual_before > 0 && ms.residual_after < 0.5 * ms.residual_before))
    return std::nullopt;
  // The segments by how much their mass changes (log ratio), largest first.
  std::vector<std::pair<double, int>> change;
  for (int s = 0; s < static_cast<int>(ms.segments.size()); ++s)
    change.emplace_back(std::abs(std::log(std::max(ms.suggested_kg[s], 1e-6) / ms.current_kg[s])),
                        s);
  std::sort(change.rbegin(), change.rend());
  if (change.empty() || !(change[0].first > std::log(1.25))) return std::nullopt;
  // The largest change, and the second when at least half as large.
  Finding finding;
  finding.kind = Finding::Kind::kSegmentMass;
  std::string text = "segment mass: ";
  for (size_t i = 0; i < change.size() && i < 2; ++i) {
    if (i > 0 && change[i].first < 0.5 * change[0].first) break;
    const int s = change[i].second;
    finding.names.push_back(ms.segments[static_cast<size_t>(s)]);
    if (i) text += ", ";
    text += ms.segments[static_cast<size_t>(s)] +
            fmt::format(" {:.1f} kg in the model, {:.1f} kg fits the flights",
                        ms.current_kg[s],
                        ms.suggested_kg[s]);
  }
  const int s0 = change[0].second;
  finding.value = ms.suggested_kg[s0] / ms.current_kg[s0];
  text += fmt::format(
      " (residual {:.3f} → {:.3f}; check the athlete file)", ms.residual_before, ms.residual_after);
  finding.text = text;
  return finding;
}

// 4. The markers (not already named) that fit worst at the 5 judged frames of largest residual:
// mean error there above 1 cm and 3 times the marker's median error; up to 3 named.
std::optional<Finding> FindWorstMarkers(const MarkerResiduals& residuals,
                                        const std::vector<ModelMarker>& markers,
                                        const std::vector<int>& frames,
                                        const std::vector<bool>& named,
                                        int n,
                                        const PhysicalCheck& check,
                                        const PhysicalCheckOptions& options) {
  const int nm = static_cast<int>(markers.size());
  // The peak-residual frames.
  std::vector<int> peak = frames;
  auto score = [&](int i) {
    return check.frames.force_bw.col(i).norm() / options.max_force_bw +
           check.frames.moment_bwh.col(i).norm() / options.max_moment_bwh;
  };
  const size_t top = std::min<size_t>(5, peak.size());
  std::partial_sort(
      peak.begin(), peak.begin() + static_cast<long>(top), peak.end(), [&](int x, int y) {
        return score(x) > score(y);
      });
  peak.resize(top);
  // Each marker's mean error there against its median error over the trial.
  std::vector<std::pair<double, int>> worst;
  for (int j = 0; j < nm; ++j) {
    if (named[static_cast<size_t>(j)]) continue;
    std::vector<double> all;
    for (int i = 0; i < n; ++i)
      if (residuals.present(i, j)) all.push_back(residuals.error(i, j));
    if (all.empty()) continue;
    std::nth_element(all.begin(), all.begin() + static_cast<long>(all.size() / 2), all.end());
    const double median = all[all.size() / 2];
    double at_peak = 0.0;
    int count = 0;
    for (int i : peak)
      if (residuals.present(i, j)) {
        at_peak += residuals.error(i, j);
        ++count;
      }
    if (count == 0) continue;
    at_peak /= count;
    if (at_peak > 0.01 && at_peak > 3.0 * median) worst.emplace_back(at_peak, j);
  }
  std::sort(worst.rbegin(), worst.rend());
  if (worst.empty()) return std::nullopt;
  // The finding: the worst three.
  Finding finding;
  finding.kind = Finding::Kind::kMarkers;
  std::string text = "markers fitting worst at the peak-residual frames: ";
  for (size_t i = 0; i < worst.size() && i < 3; ++i) {
    finding.names.push_back(markers[static_cast<size_t>(worst[i].second)].name);
    text +=
        (i ? ", " : "") + finding.names.back() + fmt::format(" {:.1f} cm", 100 * worst[i].first);
  }
  finding.value = worst[0].first;
  finding.text = text;
  return finding;
}

}  // namespace

void LocalisePhysicsFailure(const dynamics::Model<double>& model,
                            const Motion& motion,
                            const Eigen::Matrix3Xd& marker_positions,
                            const std::vector<ModelMarker>& markers,
                            const PhysicalCheckOptions& options,
                            PhysicalCheck& check) {
  const int n = motion.num_frames();
  const int nm = static_cast<int>(markers.size());
  ACRO_DEMAND(marker_positions.cols() == static_cast<Eigen::Index>(n) * nm);
  const double dt = FrameStep(motion);
  check.findings.clear();

  // Measured against model marker positions on every frame.
  const MarkerResiduals residuals(
      marker_positions, CalcModelMarkerPositions(model, motion, markers), nm);
  std::vector<bool> named(static_cast<size_t>(nm), false);

  // 1. Swapped markers.
  for (Finding& finding :
       FindSwappedMarkers(residuals, markers, motion, options.max_marker_error_m, named))
    check.findings.push_back(std::move(finding));

  // 2. Markers recorded late, judged on the flights' frames.
  const std::vector<int> frames = JudgedFrames(check);
  if (std::optional<Finding> timing = FindTimingLag(residuals, markers, frames, n, dt))
    check.findings.push_back(std::move(*timing));

  // 3. Segment masses that best zero the flight residuals.
  check.mass_suggestion = SuggestSegmentMasses(model, motion, check, check.height_m);
  if (std::optional<Finding> mass = FindSegmentMassFinding(check.mass_suggestion))
    check.findings.push_back(std::move(*mass));

  // 4. When nothing above explains it: the markers that fit worst at the frames of largest
  // residual.
  if (!frames.empty() && check.findings.empty())
    if (std::optional<Finding> worst =
            FindWorstMarkers(residuals, markers, frames, named, n, check, options))
      check.findings.push_back(std::move(*worst));
}

}  // namespace acro::analysis
