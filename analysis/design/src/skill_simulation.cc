// The flight simulation of a designed skill (skill_simulation.h).

#include "acro/design/skill_simulation.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include <ceres/ceres.h>

#include "acro/athlete/motion.h"
#include "acro/base/demand.h"
#include "acro/base/text_format.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/kinematics.h"
#include "skill_motion.h"

namespace acro::analysis {

namespace {

// Per output sample: the rotation vector from the designed orientation to the simulated one.
void OrientationMisfit(const std::vector<Eigen::Quaterniond>& designed,
                       const dynamics::FlightSimulationResult<double>& f,
                       double* r) {
  for (size_t k = 0; k < designed.size(); ++k) {
    const Eigen::VectorXd& q = f.q[std::min(k, f.q.size() - 1)];
    const Eigen::Quaterniond sim = dynamics::GetRootQuaternion(q);
    const Eigen::AngleAxisd e(designed[k].conjugate() * sim.normalized());
    const Eigen::Vector3d v = e.axis() * e.angle();
    for (int c = 0; c < 3; ++c) r[3 * k + c] = v[c];
  }
}

// The take-off momentum that the design needs: the H that makes the simulated orientation follow
// the designed one best over the whole flight (least squares over the output samples; Ceres with
// central differences, each evaluation one flight simulation), from `H0`.
Eigen::Vector3d FitTakeoffMomentum(
    const Eigen::Vector3d& H0,
    const std::vector<Eigen::Quaterniond>& designed,
    const std::function<dynamics::FlightSimulationResult<double>(const Eigen::Vector3d&)>&
        simulate) {
  struct Misfit {
    std::function<void(const double*, double*)> eval;
    bool operator()(const double* H, double* r) const {
      eval(H, r);
      return true;
    }
  };
  const int residuals = 3 * static_cast<int>(designed.size());
  auto* cost = new ceres::NumericDiffCostFunction<Misfit, ceres::CENTRAL, ceres::DYNAMIC, 3>(
      new Misfit{[&](const double* H, double* r) {
        OrientationMisfit(designed, simulate(Eigen::Vector3d(H[0], H[1], H[2])), r);
      }},
      ceres::TAKE_OWNERSHIP,
      residuals);
  double H[3] = {H0[0], H0[1], H0[2]};
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, H);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 20;
  so.function_tolerance = 1e-8;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return Eigen::Vector3d(H[0], H[1], H[2]);
}

// Somersault angle of the root's long axis z_B in W's x–z plane, unwrapped (turns).
double SomersaultTurns(const std::vector<Eigen::Quaterniond>& qs) {
  double total = 0.0, prev = 0.0;
  for (size_t i = 0; i < qs.size(); ++i) {
    const Eigen::Vector3d z = qs[i] * Eigen::Vector3d::UnitZ();
    const double a = std::atan2(z.x(), z.z());
    if (i > 0) total += std::remainder(a - prev, 2.0 * std::numbers::pi);
    prev = a;
  }
  return total / (2.0 * std::numbers::pi);
}

// Twist: the angle about the pelvis' long axis in R_y(somersault) R_x(tilt) R_z(twist), from row
// y of R = (cos t sin w, cos t cos w, −sin t), unwrapped (turns).
double TwistTurns(const std::vector<Eigen::Quaterniond>& qs) {
  double total = 0.0, prev = 0.0;
  for (size_t i = 0; i < qs.size(); ++i) {
    const Eigen::Matrix3d R = qs[i].normalized().toRotationMatrix();
    const double w = std::atan2(R(1, 0), R(1, 1));
    if (i > 0) total += std::remainder(w - prev, 2.0 * std::numbers::pi);
    prev = w;
  }
  return total / (2.0 * std::numbers::pi);
}

}  // namespace

SkillSimulationResult SimulateSkill(const SkillDesign& design,
                                    const SkillTrajectory& trajectory,
                                    double step_s,
                                    bool fit_momentum) {
  const dynamics::Model<double>& m = design.model();
  const internal::MotionEvaluator motion(design, trajectory, Eigen::Vector3d(0, 0, 1));
  SkillSimulationResult out;
  // The designed motion's angular momentum about the COM; its mean over the flight is the
  // take-off momentum to start from.
  const SkillMotionProfile profile = CalcSkillMotionProfile(design, trajectory, 200);
  out.H_mean_W = profile.H_Scm_W.rowwise().mean();
  const SkillMotionState s0 = motion.Eval(0.0);
  dynamics::Workspace<double> ws(m);
  dynamics::FlightSimulationOptions fo;
  fo.duration_s = design.flight_time_s();
  fo.step_s = step_s;
  fo.output_interval_s = 0.01;
  const dynamics::JointTrajectory<double> joints = [&](const double& t,
                                                       dynamics::VectorXRef<double> qj,
                                                       dynamics::VectorXRef<double> vj,
                                                       dynamics::VectorXRef<double> aj) {
    motion.Joints(t, qj, vj, aj);
  };
  auto simulate = [&](const Eigen::Vector3d& H) {
    const dynamics::Vector6<double> v_root0 = dynamics::CalcRootVelocityFromMomentum(
        m, ws, s0.q, s0.v, Eigen::Vector3d(design.skill().takeoff_com_velocity_mps), H);
    return dynamics::SimulateFlight(
        m,
        fo,
        Eigen::Matrix<double, dynamics::kRootNq, 1>(s0.q.head<dynamics::kRootNq>()),
        v_root0,
        joints);
  };
  out.H_Scm_W = out.H_mean_W;
  out.flight = simulate(out.H_Scm_W);
  // The designed orientation at the simulation's output times.
  std::vector<Eigen::Quaterniond> designed;
  for (double t : out.flight.t) {
    const SkillMotionState s = motion.Eval(t);
    designed.emplace_back(s.q[3], s.q[4], s.q[5], s.q[6]);
  }
  if (fit_momentum) {
    out.H_Scm_W = FitTakeoffMomentum(out.H_mean_W, designed, simulate);
    out.flight = simulate(out.H_Scm_W);
  }
  std::vector<double> r(3 * designed.size());
  OrientationMisfit(designed, out.flight, r.data());
  double sum = 0;
  for (size_t k = 0; k < designed.size(); ++k)
    sum += r[3 * k] * r[3 * k] + r[3 * k + 1] * r[3 * k + 1] + r[3 * k + 2] * r[3 * k + 2];
  out.rms_orientation_error_rad = std::sqrt(sum / static_cast<double>(designed.size()));
  const Eigen::VectorXd& qf = out.flight.q.back();
  out.final_orientation = dynamics::GetRootQuaternion(qf).normalized();
  out.intended_final_orientation = design.keyframe_orientations().back();
  out.final_orientation_error_rad =
      out.final_orientation.angularDistance(out.intended_final_orientation);
  std::vector<Eigen::Quaterniond> sim;
  for (const Eigen::VectorXd& q : out.flight.q) sim.push_back(dynamics::GetRootQuaternion(q));
  out.somersault_turns = SomersaultTurns(sim);
  out.intended_somersault_turns = SomersaultTurns(designed);
  out.twist_turns = TwistTurns(sim);
  out.intended_twist_turns = TwistTurns(designed);
  out.warnings = SkillSimulationWarnings(out);
  return out;
}

std::vector<std::string> SkillSimulationWarnings(const SkillSimulationResult& sim) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  constexpr double kLimit = 15.0 * kDeg;
  std::vector<std::string> w;
  auto deg = [](double rad) { return FormatFixed(rad / kDeg, 1) + "°"; };
  auto turns = [](double t) { return FormatFixed(t, 2); };
  if (sim.flight.summary.status != dynamics::FlightSimulationStatus::kSuccess)
    w.push_back("the flight simulation did not finish: " + sim.flight.summary.BriefReport());
  if (sim.final_orientation_error_rad > kLimit || sim.rms_orientation_error_rad > kLimit)
    w.push_back("the simulated flight lands " + deg(sim.final_orientation_error_rad) +
                " from the last keyframe and follows the design within " +
                deg(sim.rms_orientation_error_rad) +
                " RMS: the keyframes ask for a rotation this body does not make in the air");
  const double somersault_error = sim.somersault_turns - sim.intended_somersault_turns;
  if (std::abs(somersault_error) * 2.0 * std::numbers::pi > kLimit)
    w.push_back("the simulation somersaults " + turns(sim.somersault_turns) +
                " turns, the design " + turns(sim.intended_somersault_turns) +
                ": more or less time in a compact shape (tuck, pike) changes the somersault rate");
  const double designed = sim.intended_twist_turns, simulated = sim.twist_turns;
  if (std::abs(designed) >= 0.25 && simulated * designed < 0.0)
    w.push_back("the design twists " + turns(designed) + " turns but the simulation " +
                turns(simulated) +
                ": in the air the twist's direction follows the tilt and the arm action; if "
                "Model 1 cannot reconcile them, reverse the twist or the tilt");
  else if (std::abs(simulated - designed) > 0.25)
    w.push_back("the simulation twists " + turns(simulated) + " turns, the design " +
                turns(designed) +
                ": the tilt during the twist (or how tightly the arms wrap) is too small or too "
                "large for this twist in this time");
  return w;
}

std::string FormatSkillSimulation(const SkillSimulationResult& sim) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  return "the simulated flight (take-off momentum " + FormatFixed(sim.H_Scm_W.norm(), 1) +
         " kg·m²/s, the design's mean " + FormatFixed(sim.H_mean_W.norm(), 1) + ") turns " +
         FormatFixed(sim.somersault_turns, 3) + " somersaults (designed " +
         FormatFixed(sim.intended_somersault_turns, 3) + ") and " +
         FormatFixed(sim.twist_turns, 2) + " twists (designed " +
         FormatFixed(sim.intended_twist_turns, 2) + "), follows the design within " +
         FormatFixed(sim.rms_orientation_error_rad * kDeg, 1) + "° RMS and lands " +
         FormatFixed(sim.final_orientation_error_rad * kDeg, 1) +
         "° from the last keyframe's orientation";
}

Motion SimulatedSkillMotion(const SkillDesign& design,
                            const SkillSimulationResult& sim,
                            double rate_hz) {
  ACRO_DEMAND(rate_hz > 0);
  const std::vector<double>& t = sim.flight.t;
  Motion m;
  m.coordinate_names = MakeCoordinateNames(design.model());
  if (t.empty()) return m;
  const int intervals =
      std::max(1, static_cast<int>(std::ceil((t.back() - t.front()) * rate_hz - 1e-9)));
  m.rate_hz = intervals / std::max(t.back() - t.front(), 1e-9);
  m.time_s.resize(intervals + 1);
  m.q.resize(design.model().nq(), intervals + 1);
  for (int k = 0; k <= intervals; ++k) {
    const double tk = t.front() + (t.back() - t.front()) * k / intervals;
    // The simulation step nearest tk.
    const auto it = std::lower_bound(t.begin(), t.end(), tk);
    size_t i = static_cast<size_t>(it - t.begin());
    if (i == t.size() || (i > 0 && tk - t[i - 1] < t[i] - tk)) i = i == 0 ? 0 : i - 1;
    m.time_s(k) = t[i];
    m.q.col(k) = sim.flight.q[i];
  }
  m.fit.assign(static_cast<size_t>(intervals + 1), FrameFit{});
  return m;
}

}  // namespace acro::analysis
