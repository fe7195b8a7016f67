#include "acro/analysis/timing_optimization.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

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
                                   int model,
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

TEST(TimingOptimization, TheExampleHasTwelveKeyframesAndTheFlightTimeOfItsTakeOff) {
  const SkillDesign& d = FrontExample();
  EXPECT_EQ(d.num_keyframes(), 12);
  EXPECT_NEAR(d.flight_time_s(), 2.0 * 7.8 / 9.81, 4 * kEps);
  const Eigen::VectorXd t = d.InitialTimes();
  EXPECT_NEAR(t[1] - t[0], d.flight_time_s() / 11.0, 8 * kEps);
}

// The root translation keeps the COM on the parabola: the force residual vanishes, and the profile
// (full dynamics with the true root translation) gives the same J as the optimiser's evaluation
// (root fixed at the origin), since the moment about the COM does not depend on the translation.
TEST(TimingOptimization, ForcesVanishAndTheTwoEvaluationsOfJAgree) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKeyframeTrajectory(d, d.EvenTimes());
  const SkillMotionProfile p = CalcSkillMotionProfile(d, t, 80);
  // Force / weight is a difference of O(1) terms: a few hundred ε.
  EXPECT_LT(p.force_per_weight.cwiseAbs().maxCoeff(), 1e-12);
  const double J = CalcSkillObjective(d, t, 2, InitialSkillParameters(d, t, 2), 80);
  EXPECT_NEAR(p.objective, J, 1e-12 * J);
  EXPECT_GT(J, 0.0);
}

// Model 2's gradient (automatic differentiation through splines and inverse dynamics) against
// central differences.
TEST(TimingOptimization, Model2GradientMatchesCentralDifferences) {
  const SkillDesign& d = FrontExample();
  const SkillTrajectory t = MakeKeyframeTrajectory(d, d.EvenTimes());
  Eigen::VectorXd x = InitialSkillParameters(d, t, 2);
  // An uneven point, not the even timing.
  for (int i = 0; i < x.size(); ++i) x[i] *= 1.0 + 0.1 * std::sin(1.0 + i);
  Eigen::VectorXd g;
  CalcSkillObjective(d, t, 2, x, 40, &g);
  // h ≈ ε^(1/3)·scale: truncation and rounding errors both near 1e-10 relative.
  const Eigen::VectorXd fd = CentralDifferences(d, t, 2, x, 40, 1e-6);
  EXPECT_LT((g - fd).norm(), 1e-6 * g.norm())
      << "AD " << g.transpose() << "\nFD " << fd.transpose();
}

TEST(TimingOptimization, Model2OnThePapersExample) {
  const SkillDesign& d = FrontExample();
  TimingOptimizationOptions o;
  o.model = 2;
  const TimingOptimizationResult r = OptimizeSkillTiming(d, o);
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
  const SkillSimulationResult sim = SimulateSkill(d, r.optimized);
  std::printf("simulated final orientation error %.1f deg, somersaults %.3f (designed %.3f)\n",
              sim.final_orientation_error_rad / kDeg,
              sim.somersault_turns,
              sim.intended_somersault_turns);
}

}  // namespace
}  // namespace acro::analysis
