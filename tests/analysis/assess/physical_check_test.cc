// The physical-correctness check against physics: a flight simulated by the dynamics engine (so
// exactly torque-free) must pass with residuals near zero, the segment-by-segment Newton–Euler
// balance must agree with the recursive inverse dynamics, and a model whose segment masses are
// wrong for the motion must fail, with the least-squares mass suggestion finding the segment.

#include "acro/assess/physical_check.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/flight_simulation.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kRate = 200.0;
constexpr double kHeight = 1.65;

/// Smooth 0 → 1 between t0 and t1 (the septic smoothstep, continuous up to the jerk as a real
/// motion is), with its first two derivatives.
void SmoothStep(double t, double t0, double t1, double* u, double* du, double* ddu) {
  const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  const double d = 1.0 / (t1 - t0);
  const double s2 = s * s, s3 = s2 * s;
  *u = s2 * s2 * (35 - 84 * s + 70 * s2 - 20 * s3);
  *du = 140 * s3 * (1 - s) * (1 - s) * (1 - s) * d;
  *ddu = 420 * s2 * (1 - s) * (1 - s) * (1 - 2 * s) * d * d;
}

AthleteBody MakeBody() {
  return MakeDeLevaBody(kHeight, 58.0, Sex::kFemale);
}

/// A back tuck with an asymmetric leg action (the right hip closes more than the left), simulated
/// torque-free at kRate.
Motion SimulateTuck(const dynamics::Model<double>& model) {
  const std::vector<std::string> names = MakeCoordinateNames(model);
  auto index = [&](const std::string& name) {
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin()) - 7;
  };
  struct Ramp {
    int joint;
    double deg;
  };
  const std::vector<Ramp> tuck = {{index("r_hip_flexion"), -120},
                                  {index("l_hip_flexion"), -90},
                                  {index("r_knee_flexion"), 120},
                                  {index("l_knee_flexion"), 110},
                                  {index("r_shoulder_flexion"), -60},
                                  {index("l_shoulder_flexion"), -40},
                                  {index("lumbar_flexion"), 20}};
  const int n = model.num_joint_dofs();
  dynamics::JointTrajectory<double> joints = [&, n](const double& t,
                                                    dynamics::VectorXRef<double> qj,
                                                    dynamics::VectorXRef<double> vj,
                                                    dynamics::VectorXRef<double> aj) {
    qj.setZero();
    vj.setZero();
    aj.setZero();
    double u, du, ddu, o, dout, ddo;
    SmoothStep(t, 0.15, 0.45, &u, &du, &ddu);
    SmoothStep(t, 0.9, 1.2, &o, &dout, &ddo);
    for (const Ramp& r : tuck) {
      const double span = r.deg * kDeg;
      qj[r.joint] = span * (u - o);
      vj[r.joint] = span * (du - dout);
      aj[r.joint] = span * (ddu - ddo);
    }
  };
  Eigen::Matrix<double, 7, 1> q_root0;
  q_root0 << 0.1, -0.2, 1.1, 1, 0, 0, 0;
  Eigen::VectorXd q0 = dynamics::MakeNeutralConfiguration(model);
  q0.head<7>() = q_root0;
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(model.nv());
  dynamics::Workspace<double> ws(model);
  const dynamics::Vector6<double> v_root0 = dynamics::CalcRootVelocityFromMomentum<double>(
      model, ws, q0, v0, Eigen::Vector3d(0.2, 0.05, 6.9), Eigen::Vector3d(0, -60, 3));
  dynamics::FlightSimulationOptions options;
  options.duration_s = 1.4;
  options.step_s = 1e-3;
  options.output_interval_s = 1.0 / kRate;
  const auto sim = dynamics::SimulateFlight<double>(model, options, q_root0, v_root0, joints);
  EXPECT_EQ(sim.summary.status, dynamics::FlightSimulationStatus::kSuccess);
  Motion motion;
  motion.coordinate_names = names;
  motion.rate_hz = kRate;
  const int frames = static_cast<int>(sim.q.size());
  motion.time_s.resize(frames);
  motion.q.resize(model.nq(), frames);
  motion.fit.resize(static_cast<size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    motion.time_s[i] = sim.t[static_cast<size_t>(i)];
    motion.q.col(i) = sim.q[static_cast<size_t>(i)];
    motion.fit[static_cast<size_t>(i)].valid = true;
  }
  return motion;
}

std::vector<Flight> WholeMotionIsOneFlight(const Motion& motion) {
  Flight f;
  f.takeoff_frame = 0;
  f.landing_frame = motion.num_frames();
  return {f};
}

TEST(PhysicalCheck, SimulatedFlightPassesWithNearZeroResiduals) {
  const dynamics::Model<double> model = MakeStandardHumanModel(MakeBody());
  const Motion motion = SimulateTuck(model);
  const PhysicalCheck check =
      CheckPhysics(model, motion, WholeMotionIsOneFlight(motion), kHeight, 0.0);
  ASSERT_EQ(check.flights.size(), 1u);
  const FlightCheck& f = check.flights[0];
  EXPECT_TRUE(check.pass) << check.verdict;
  // Central differences at 200 Hz of an exact flight: the residual is the truncation error only.
  EXPECT_LT(f.peak_force_bw, 2e-3);
  EXPECT_LT(f.peak_moment_bwh, 5e-4);
  EXPECT_LT(f.momentum_variation, 0.01);
  EXPECT_NEAR(f.fitted_gravity_m_per_s2, 9.81, 0.01);
  EXPECT_GT(f.mean_angular_momentum, 55.0);
}

TEST(PhysicalCheck, SegmentBySegmentBalanceEqualsRecursiveInverseDynamics) {
  const dynamics::Model<double> model = MakeStandardHumanModel(MakeBody());
  Motion motion = SimulateTuck(model);
  // Make the motion non-physical (a wrong root acceleration) so there is a residual to compare.
  for (int i = 0; i < motion.num_frames(); ++i)
    motion.q(0, i) += 0.05 * std::sin(2 * std::numbers::pi * 1.5 * motion.time_s[i]);
  const FrameDynamics rnea = CalcFrameDynamics(model, motion, kHeight);
  const Eigen::Vector3d P(0.3, -0.1, 2.0);
  const Eigen::MatrixXd W = CalcSegmentWrenches(model, motion, P);
  const double weight = model.total_mass() * 9.81;
  double worst_force = 0, worst_moment = 0, scale = 0;
  for (int i = 5; i + 5 < motion.num_frames(); ++i) {
    Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
    for (int s = 0; s < model.num_segments(); ++s) sum += W.block<6, 1>(6 * s, i);
    const Eigen::Vector3d f = sum.tail<3>() / weight;
    // Moment about the COM = moment about P − (COM − P) × force.
    const Eigen::Vector3d n =
        (sum.head<3>() - (rnea.com_W.col(i) - P).cross(sum.tail<3>())) / (weight * kHeight);
    worst_force = std::max(worst_force, (f - rnea.force_bw.col(i)).norm());
    worst_moment = std::max(worst_moment, (n - rnea.moment_bwh.col(i)).norm());
    scale = std::max(scale, rnea.force_bw.col(i).norm());
  }
  EXPECT_GT(scale, 0.3);         // the injected error is large…
  EXPECT_LT(worst_force, 3e-3);  // …and both routes see the same residual
  EXPECT_LT(worst_moment, 1e-3);
}

TEST(PhysicalCheck, DoubledSegmentMassFailsAndIsFound) {
  const AthleteBody body = MakeBody();
  const dynamics::Model<double> truth = MakeStandardHumanModel(body);
  const Motion motion = SimulateTuck(truth);
  // The athlete file's error: the right thigh twice as heavy, the others lighter so that the
  // weighed total is kept.
  AthleteBody wrong = body;
  const int thigh = wrong.Find("r_thigh");
  const double extra = wrong.segments[static_cast<size_t>(thigh)].in_H.mass_kg;
  const double total = body.total.mass_kg;
  for (BodySegment& s : wrong.segments) {
    const double factor =
        (&s - wrong.segments.data() == thigh) ? 2.0 : (total - 2 * extra) / (total - extra);
    s.in_H.mass_kg *= factor;
    s.in_H.I_Cm_H *= factor;
  }
  const dynamics::Model<double> model = MakeStandardHumanModel(wrong);
  ASSERT_NEAR(model.total_mass(), truth.total_mass(), 1e-9);
  PhysicalCheck check = CheckPhysics(model, motion, WholeMotionIsOneFlight(motion), kHeight, 0.0);
  EXPECT_FALSE(check.pass) << "peak force " << check.flights[0].peak_force_bw;
  const MassSuggestion s = SuggestSegmentMasses(model, motion, check, kHeight);
  ASSERT_EQ(s.segments[static_cast<size_t>(thigh)], "r_thigh");
  // The suggestion brings the right thigh back towards its true mass and removes most residual.
  const double true_mass = truth.segment(thigh).mass;
  EXPECT_NEAR(s.suggested_kg[thigh], true_mass, 0.25 * true_mass)
      << "current " << s.current_kg[thigh];
  EXPECT_LT(s.residual_after, 0.3 * s.residual_before);
  int most_changed = 0;
  for (int i = 0; i < s.current_kg.size(); ++i)
    if (std::abs(std::log(s.suggested_kg[i] / s.current_kg[i])) >
        std::abs(std::log(s.suggested_kg[most_changed] / s.current_kg[most_changed])))
      most_changed = i;
  EXPECT_EQ(s.segments[static_cast<size_t>(most_changed)], "r_thigh");
}

}  // namespace
}  // namespace acro::analysis
