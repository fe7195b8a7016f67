#include "acro/base/progress.h"
#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/base/text_format.h"

#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = std::numbers::pi / 180.0;

std::filesystem::path SkillPath(const std::string& name) {
  return acro::testing::SourceDir() / "samples/skills" / name;
}

const SkillDesign& FrontExample() {
  static const SkillDesign design(ReadSkill(SkillPath("front_1_3_4_half_twist.yaml")));
  return design;
}

// Central differences of J along each coordinate of x.
Eigen::VectorXd CentralDifferences(const SkillDesign& d,
                                   const SkillTrajectory& base,
                                   SkillModel model,
                                   const Eigen::VectorXd& x,
                                   int intervals,
                                   double h) {
  Eigen::VectorXd g(x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    g[i] = (CalcSkillObjective(d, base, model, xp, intervals) -
            CalcSkillObjective(d, base, model, xm, intervals)) /
           (2.0 * h);
  }
  return g;
}

TEST(SkillOptimization, TheExampleHasTwelveKeyframesAndTheFlightTimeOfItsTakeOff) {
  const SkillDesign& d = FrontExample();
  EXPECT_EQ(d.num_keyframes(), 12);
  EXPECT_NEAR(d.flight_time_s(), 2.0 * 7.8 / 9.81, 4 * kEps);
  const Eigen::VectorXd t = d.InitialTimes();
  EXPECT_NEAR(t[1] - t[0], d.flight_time_s() / 11.0, 8 * kEps);
}

// The root translation keeps the COM on the parabola: the force residual vanishes, and the profile
// (full dynamics with the true root translation) gives the same J as the optimiser's evaluation
// (root fixed at the origin), since the moment about the COM does not depend on the translation.
TEST(SkillOptimization, ForcesVanishAndTheTwoEvaluationsOfJAgree) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKeyframeTrajectory(d, d.EvenTimes());
  const SkillMotionProfile p = CalcSkillMotionProfile(d, t, 80);
  // Force / weight is a difference of O(1) terms: a few hundred ε.
  EXPECT_LT(p.force_per_weight.cwiseAbs().maxCoeff(), 1e-12);
  const double J = CalcSkillObjective(
      d, t, SkillModel::kTiming, InitialSkillParameters(d, t, SkillModel::kTiming), 80);
  EXPECT_NEAR(p.objective, J, 1e-12 * J);
  EXPECT_GT(J, 0.0);
}

// Model 2's gradient (automatic differentiation through splines and inverse dynamics) against
// central differences.
TEST(SkillOptimization, Model2GradientMatchesCentralDifferences) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKeyframeTrajectory(d, d.EvenTimes());
  Eigen::VectorXd x = InitialSkillParameters(d, t, SkillModel::kTiming);
  // An uneven point, not the even timing.
  for (int i = 0; i < x.size(); ++i) x[i] *= 1.0 + 0.1 * std::sin(1.0 + i);
  Eigen::VectorXd g;
  CalcSkillObjective(d, t, SkillModel::kTiming, x, 40, &g);
  // h ≈ ε^(1/3)·scale: truncation and rounding errors both near 1e-10 relative.
  const Eigen::VectorXd fd = CentralDifferences(d, t, SkillModel::kTiming, x, 40, 1e-6);
  EXPECT_LT((g - fd).norm(), 1e-6 * g.norm())
      << "AD " << g.transpose() << "\nFD " << fd.transpose();
}

TEST(SkillOptimization, Model2OnThePapersExample) {
  const SkillDesign& d = FrontExample();
  SkillOptimizationOptions o;
  o.model = SkillModel::kTiming;
  const SkillOptimizationResult r = OptimizeSkill(d, o);
  std::printf("J %g -> %g (÷%.1f), variation %.3f -> %.3f, %s\n",
              r.objective_initial,
              r.objective,
              r.objective_initial / r.objective,
              r.angular_momentum_variation_initial,
              r.angular_momentum_variation,
              r.summary.BriefReport().c_str());
  for (int i = 0; i < d.num_keyframes(); ++i)
    std::printf("  %2d %.3f -> %.3f\n", i + 1, r.times_initial_s[i], r.optimized.times_s[i]);
  EXPECT_GE(r.objective_initial / r.objective, 10.0);
  EXPECT_GE(r.angular_momentum_variation_initial / r.angular_momentum_variation, 3.0);
  const Eigen::VectorXd& t0 = r.times_initial_s;
  const Eigen::VectorXd& t1 = r.optimized.times_s;
  // Keyframes 3–8 (indices 2..7) tucked: shorter; 1–3 and 8–12 stretched: longer.
  EXPECT_LT(t1[7] - t1[2], t0[7] - t0[2]);
  EXPECT_GT(t1[2] - t1[0], t0[2] - t0[0]);
  EXPECT_GT(t1[11] - t1[7], t0[11] - t0[7]);
}

const SkillDesign& BackTuck() {
  static const SkillDesign design(ReadSkill(SkillPath("back_tuck.yaml")));
  return design;
}

// The motion t of design d is at every keyframe's pose at that keyframe's time.
void ExpectKeyframePosesAtTheirTimes(const SkillDesign& d, const SkillTrajectory& t) {
  for (int i = 0; i < d.num_keyframes(); ++i) {
    const SkillMotionState s = CalcSkillMotion(d, t, t.times_s[i]);
    const Eigen::Quaterniond q(s.q[3], s.q[4], s.q[5], s.q[6]);
    EXPECT_LT(q.angularDistance(d.keyframe_orientations()[static_cast<size_t>(i)]), 1e-7) << i;
    EXPECT_LT(
        (s.q.tail(d.num_joint_dofs()) - d.keyframe_joint_angles_rad().col(i)).cwiseAbs().maxCoeff(),
        1e-12);
  }
}

// The designed motion passes through every keyframe pose at its time.
// A run is stopped from outside (the studio's Cancel): Model 1 on the paper's example, which runs
// for minutes, stops after its third iteration and says so in one line.
TEST(SkillOptimization, ACancelledRunStopsAfterTheIterationAndSaysSo) {
  SkillOptimizationOptions options;
  options.model = SkillModel::kTrajectory;
  int iterations = 0;
  options.progress = [&](const std::string& line) {
    if (line.rfind("model 1 iteration", 0) == 0) ++iterations;
  };
  options.cancelled = [&] { return iterations >= 3; };
  try {
    OptimizeSkill(FrontExample(), options);
    ADD_FAILURE() << "a cancelled run returned";
  } catch (const Cancelled& e) {
    EXPECT_STREQ(e.what(), "optimisation: cancelled");
  }
  EXPECT_EQ(iterations, 3);
}

TEST(SkillOptimization, TheMotionPassesThroughTheKeyframes) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKeyframeTrajectory(d, d.EvenTimes());
  ExpectKeyframePosesAtTheirTimes(d, t);
}

// Model 1's gradient (gaps, and per knot the offsets of joint angles, orientation, joint rates and
// accelerations, angular velocity and acceleration), assembled by Ceres from the per-sample
// residual blocks and their chain-rule Jacobians, against central differences of J, on a coarse
// grid (2 Simpson intervals per knot interval) to keep the 2·(n_x) evaluations cheap.
TEST(SkillOptimization, Model1GradientMatchesCentralDifferences) {
  // The back tuck, and the full: twisting and tilted, with asymmetric arms, so that every joint's
  // subtree and the orientation's derivative ∂R/∂Q n_B are exercised away from symmetry.
  const SkillDesign full(ReadSkill(SkillPath("full.yaml")));
  for (const SkillDesign* design : {&BackTuck(), &full}) {
    const SkillDesign& d = *design;
    const SkillTrajectory base = MakeKnotTrajectory(MakeKeyframeTrajectory(d, d.EvenTimes()), 2);
    Eigen::VectorXd x = InitialSkillParameters(d, base, SkillModel::kTrajectory);
    ASSERT_EQ(x.size(), NumSkillParameters(d, SkillModel::kTrajectory, 2));
    // An uneven point with non-zero offsets everywhere (orientation offsets included, so that the
    // right Jacobian is away from the identity).
    for (int i = 0; i < x.size(); ++i)
      x[i] += (i < d.num_keyframes() - 1 ? 0.01 : 0.02) * std::sin(0.7 * i);
    Eigen::VectorXd g;
    CalcSkillObjective(d, base, SkillModel::kTrajectory, x, 2, &g);
    const Eigen::VectorXd fd = CentralDifferences(d, base, SkillModel::kTrajectory, x, 2, 1e-6);
    EXPECT_LT((g - fd).norm(), 1e-6 * g.norm()) << d.skill().name;
    EXPECT_LT((g - fd).cwiseAbs().maxCoeff(), 1e-6 * g.cwiseAbs().maxCoeff()) << d.skill().name;
  }
}

// Model 1's local form: the keyframe splines read at the knots give the same keyframe poses, the
// body angular velocity is the derivative of the orientation and the angular acceleration that of
// the velocity (central differences), and the joint rates likewise.
TEST(SkillOptimization, Model1LocalFormIsConsistentWithItsDerivatives) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKnotTrajectory(MakeKeyframeTrajectory(d, d.EvenTimes()), 2);
  ASSERT_EQ(t.num_knots(), 23);
  ExpectKeyframePosesAtTheirTimes(d, t);
  // h = 1e-5 s: truncation (h² × third derivatives of order 1e3 rad/s³) and rounding (ε/h) both
  // near 1e-7.
  const double h = 1e-5;
  double worst_w = 0.0, worst_wdot = 0.0, worst_joint = 0.0;
  for (double tt = 0.013; tt < d.flight_time_s() - 0.01; tt += 0.031) {
    const SkillMotionState s0 = CalcSkillMotion(d, t, tt);
    const SkillMotionState sp = CalcSkillMotion(d, t, tt + h);
    const SkillMotionState sm = CalcSkillMotion(d, t, tt - h);
    auto quat = [](const SkillMotionState& s) {
      return Eigen::Quaterniond(s.q[3], s.q[4], s.q[5], s.q[6]);
    };
    // w_B from R(t−h)ᵀR(t+h) = exp(2h w_B) to second order.
    const Eigen::AngleAxisd aa(quat(sm).conjugate() * quat(sp));
    const Eigen::Vector3d w_fd = aa.axis() * aa.angle() / (2.0 * h);
    worst_w = std::max(worst_w, (w_fd - s0.v.segment<3>(3)).norm());
    const Eigen::Vector3d wdot_fd = (sp.v.segment<3>(3) - sm.v.segment<3>(3)) / (2.0 * h);
    worst_wdot = std::max(worst_wdot, (wdot_fd - s0.a.segment<3>(3)).norm());
    const Eigen::VectorXd qd_fd =
        (sp.q.tail(d.num_joint_dofs()) - sm.q.tail(d.num_joint_dofs())) / (2.0 * h);
    worst_joint =
        std::max(worst_joint, (qd_fd - s0.v.tail(d.num_joint_dofs())).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_w, 1e-5);
  EXPECT_LT(worst_wdot, 1e-4);
  EXPECT_LT(worst_joint, 1e-5);
}

// Model 1 on the paper's example (the acceptance): J at least 1000 times below even
// timing and the angular momentum about the COM within 2 % of its mean, both on the check grid
// (8 times finer than the solver's, so the pieces cannot bend between the samples unseen), with
// every keyframe within its tolerances.
TEST(SkillOptimization, Model1OnThePapersExample) {
  const SkillDesign& d = FrontExample();
  SkillOptimizationOptions o;
  o.model = SkillModel::kTrajectory;
  const SkillOptimizationResult r = OptimizeSkill(d, o);
  std::printf(
      "J %g -> %g (÷%.0f), variation %.4f -> %.4f, joints within %.2f deg, orientation "
      "within %.2f deg, %s\n",
      r.objective_initial,
      r.objective,
      r.objective_initial / r.objective,
      r.angular_momentum_variation_initial,
      r.angular_momentum_variation,
      r.max_joint_deviation_rad / kDeg,
      r.max_orientation_deviation_rad / kDeg,
      r.summary.BriefReport().c_str());
  ASSERT_EQ(r.stages.size(), 2u);
  EXPECT_TRUE(r.summary.success) << r.summary.BriefReport();
  EXPECT_GE(r.objective_initial / r.objective, 1000.0);
  EXPECT_LE(r.angular_momentum_variation, 0.02);
  // The solver's J (its own grid) and the check grid's agree: no aliasing between the samples.
  EXPECT_NEAR(2.0 * r.summary.final_cost, r.objective, 0.02 * r.objective);
  for (int i = 0; i < d.num_keyframes(); ++i) {
    const double e2 = d.skill().keyframes[static_cast<size_t>(i)].tolerance_angle_rad;
    // Bounds are enforced by projection: exact up to rounding.
    EXPECT_LE((r.optimized.joint_angles_rad.col(i) - d.keyframe_joint_angles_rad().col(i))
                  .cwiseAbs()
                  .maxCoeff(),
              e2 * (1 + 4 * kEps));
    EXPECT_LE(r.optimized.keyframe_orientations[static_cast<size_t>(i)].angularDistance(
                  d.keyframe_orientations()[static_cast<size_t>(i)]),
              e2 + 1e-7);  // acos near 1: √ε
  }
}

// Flight simulation of the sample skills without twist, with their Model 2 timing: the final
// orientation within 15° of the last keyframe's, and the somersault count as designed.
TEST(SkillOptimization, SimulatedSinglesLandAsDesigned) {
  for (const char* name : {"back_tuck.yaml", "back_pike.yaml"}) {
    const SkillDesign d(ReadSkill(SkillPath(name)));
    const SkillOptimizationResult r = OptimizeSkill(d, SkillOptimizationOptions{});
    const SkillSimulationResult sim = SimulateSkill(d, r.optimized);
    EXPECT_EQ(sim.flight.summary.status, dynamics::FlightSimulationStatus::kSuccess);
    EXPECT_LT(sim.final_orientation_error_rad, 15 * kDeg) << name;
    EXPECT_NEAR(sim.somersault_turns, sim.intended_somersault_turns, 15.0 / 360.0) << name;
    // Drawn beside the design (the studio): the simulated motion from take-off to landing, its
    // last frame the simulation's last state, its landing orientation the one measured above.
    const Motion m = SimulatedSkillMotion(d, sim);
    ASSERT_GT(m.num_frames(), 100) << name;
    EXPECT_EQ(m.time_s(0), 0.0);
    EXPECT_NEAR(m.time_s(m.num_frames() - 1), d.flight_time_s(), 1e-3) << name;
    EXPECT_EQ(m.q.col(m.num_frames() - 1), sim.flight.q.back());
    EXPECT_LT(dynamics::GetRootQuaternion(m.q.col(m.num_frames() - 1))
                  .angularDistance(sim.final_orientation),
              1e-9);
    const std::string line = FormatSkillSimulation(sim);
    EXPECT_NE(line.find(FormatFixed(sim.somersault_turns, 3) + " somersaults (designed " +
                        FormatFixed(sim.intended_somersault_turns, 3) + ")"),
              std::string::npos)
        << line;
  }
}

// Flight simulation of Model 1's designs, with the take-off momentum fitted to the designed
// orientation: every sample skill lands within 15° of its last keyframe (the acceptance), with its
// designed somersaults.
TEST(SkillOptimization, Model1DesignsLandAsDesigned) {
  for (const char* name : {"front_1_3_4_half_twist.yaml",
                           "back_tuck.yaml",
                           "back_pike.yaml",
                           "barani.yaml",
                           "full.yaml",
                           "double_back_tuck.yaml"}) {
    const SkillDesign d(ReadSkill(SkillPath(name)));
    SkillOptimizationOptions o;
    o.model = SkillModel::kTrajectory;
    const SkillOptimizationResult r = OptimizeSkill(d, o);
    const SkillSimulationResult sim = SimulateSkill(d, r.optimized);
    EXPECT_EQ(sim.flight.summary.status, dynamics::FlightSimulationStatus::kSuccess);
    EXPECT_LT(sim.final_orientation_error_rad, 15 * kDeg) << name;
    EXPECT_NEAR(sim.somersault_turns, sim.intended_somersault_turns, 15.0 / 360.0) << name;
    EXPECT_NEAR(sim.twist_turns, sim.intended_twist_turns, 0.05) << name;
    EXPECT_TRUE(sim.warnings.empty()) << name << ": " << sim.warnings.front();
    // The fitted momentum stays close to the design's own mean (the design is consistent).
    EXPECT_LT((sim.H_Scm_W - sim.H_mean_W).norm(), 0.1 * sim.H_mean_W.norm()) << name;
  }
}

// The full with its twist reversed (positive, with the same negative tilt and arms) does not fly as
// drawn, and the simulation says so: it twists the other way.
TEST(SkillOptimization, SimulationWarnsWhenTheTwistGoesAgainstTheTilt) {
  Skill skill = ReadSkill(SkillPath("full.yaml"));
  for (SkillKeyframe& k : skill.keyframes) k.twist_rad = -k.twist_rad;
  const SkillDesign d(skill);
  const SkillOptimizationResult r = OptimizeSkill(d, SkillOptimizationOptions{});
  const SkillSimulationResult sim = SimulateSkill(d, r.optimized);
  EXPECT_NEAR(sim.intended_twist_turns, 1.0, 0.01);
  EXPECT_LT(sim.twist_turns, 0.0);
  ASSERT_FALSE(sim.warnings.empty());
  bool direction = false;
  for (const std::string& w : sim.warnings)
    direction = direction || w.find("reverse the twist or the tilt") != std::string::npos;
  EXPECT_TRUE(direction) << sim.warnings.front();
}

// Each warning from its own condition, on made-up results.
TEST(SkillOptimization, SimulationWarningsNameWhatDiffers) {
  SkillSimulationResult sim;
  sim.flight.summary.status = dynamics::FlightSimulationStatus::kSuccess;
  sim.somersault_turns = sim.intended_somersault_turns = -0.9;
  sim.twist_turns = sim.intended_twist_turns = 1.0;
  EXPECT_TRUE(SkillSimulationWarnings(sim).empty());
  sim.final_orientation_error_rad = 20 * kDeg;
  ASSERT_EQ(SkillSimulationWarnings(sim).size(), 1u);
  EXPECT_NE(SkillSimulationWarnings(sim)[0].find("lands 20.0°"), std::string::npos);
  sim.final_orientation_error_rad = 0.0;
  sim.somersault_turns = -0.8;  // 36° short
  ASSERT_EQ(SkillSimulationWarnings(sim).size(), 1u);
  EXPECT_NE(SkillSimulationWarnings(sim)[0].find("somersaults -0.80 turns"), std::string::npos);
  sim.somersault_turns = -0.9;
  sim.twist_turns = 0.6;  // the right way, 0.4 turn short
  ASSERT_EQ(SkillSimulationWarnings(sim).size(), 1u);
  EXPECT_NE(SkillSimulationWarnings(sim)[0].find("twists 0.60 turns"), std::string::npos);
  sim.twist_turns = -0.3;  // the other way
  ASSERT_EQ(SkillSimulationWarnings(sim).size(), 1u);
  EXPECT_NE(SkillSimulationWarnings(sim)[0].find("reverse the twist"), std::string::npos);
}

}  // namespace
}  // namespace acro::analysis
