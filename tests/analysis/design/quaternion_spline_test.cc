#include "acro/design/quaternion_spline.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

const std::vector<double> kT = {0.0, 0.13, 0.4, 0.55, 0.9, 1.2, 1.6};
const std::vector<double> kY = {0.0, 1.0, -0.5, 2.0, 2.1, 0.3, -1.0};

std::vector<Eigen::Quaterniond> RandomOrientations(size_t n) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Quaterniond> q = {Eigen::Quaterniond::Identity()};
  // Steps of at most about 100° so that consecutive keyframes are within the log's branch.
  for (size_t i = 1; i < n; ++i)
    q.push_back(q.back() *
                dynamics::QuaternionExp<double>(Eigen::Vector3d(u(rng), u(rng), u(rng))));
  return q;
}

TEST(QuaternionSpline, InterpolatesTheKeyframeOrientations) {
  const std::vector<Eigen::Quaterniond> Q = RandomOrientations(kT.size());
  const QuaternionSpline<double> s(kT, Q);
  for (size_t i = 0; i < kT.size(); ++i) {
    const Eigen::Quaterniond q = s.Eval(kT[i]).q_WB;
    EXPECT_LT(q.angularDistance(Q[i]), 1e-7) << i;  // acos near 1 loses half the digits: √ε
    EXPECT_NEAR(q.norm(), 1.0, 16 * kEps);
  }
}

// w_WB_B = 2 vec(q* ⊗ q̇) and ẇ against central differences of the orientation and of w.
TEST(QuaternionSpline, AngularVelocityAndAccelerationMatchDifferences) {
  const QuaternionSpline<double> s(kT, RandomOrientations(kT.size()));
  const double h = 1e-5;
  for (double t : {0.05, 0.31, 0.7, 1.0, 1.5}) {
    const QuaternionSample<double> c = s.Eval(t);
    const Eigen::Quaterniond qp = s.Eval(t + h).q_WB, qm = s.Eval(t - h).q_WB;
    const Eigen::Vector4d qdot = (qp.coeffs() - qm.coeffs()) / (2 * h);
    const Eigen::Quaterniond qd(qdot[3], qdot[0], qdot[1], qdot[2]);
    const Eigen::Vector3d w_fd = 2.0 * (c.q_WB.conjugate() * qd).vec();
    EXPECT_LT((c.w_WB_B - w_fd).norm(), 1e-6 * (1.0 + c.w_WB_B.norm())) << t;
    const Eigen::Vector3d wdot_fd = (s.Eval(t + h).w_WB_B - s.Eval(t - h).w_WB_B) / (2 * h);
    EXPECT_LT((c.wdot_WB_B - wdot_fd).norm(), 1e-5 * (1.0 + c.wdot_WB_B.norm())) << t;
  }
}

// C² at the knots: orientation, angular velocity and acceleration agree from both sides.
TEST(QuaternionSpline, IsContinuousInAngularAccelerationAtTheKnots) {
  const QuaternionSpline<double> s(kT, RandomOrientations(kT.size()));
  const double d = 1e-9;
  for (size_t i = 1; i + 1 < kT.size(); ++i) {
    const QuaternionSample<double> a = s.Eval(kT[i] - d), b = s.Eval(kT[i] + d);
    EXPECT_LT(a.q_WB.angularDistance(b.q_WB), 1e-7);
    EXPECT_LT((a.w_WB_B - b.w_WB_B).norm(), 1e-6);
    // ẇ varies at most ~1e3 rad/s³ × 2e-9 s across the gap.
    EXPECT_LT((a.wdot_WB_B - b.wdot_WB_B).norm(), 1e-5);
  }
}

// A rotation about a fixed axis with angles on a spline is the scalar spline of the angle.
TEST(QuaternionSpline, ReducesToTheScalarSplineForOneAxis) {
  std::vector<Eigen::Quaterniond> Q;
  for (double a : kY) Q.emplace_back(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()));
  const QuaternionSpline<double> s(kT, Q);
  const CubicSpline<double> angle(kT, kY);
  for (double t : {0.05, 0.31, 0.7, 1.0, 1.5}) {
    const QuaternionSample<double> c = s.Eval(t);
    const Eigen::Quaterniond expected(
        Eigen::AngleAxisd(angle.Eval(t).value, Eigen::Vector3d::UnitY()));
    EXPECT_LT(c.q_WB.angularDistance(expected), 1e-7);
    EXPECT_NEAR(c.w_WB_B.y(), angle.Eval(t).d1, 1e-12);
    EXPECT_NEAR(c.wdot_WB_B.y(), angle.Eval(t).d2, 1e-11);
    EXPECT_NEAR(c.w_WB_B.x(), 0.0, 1e-14);
  }
}

TEST(QuaternionLog, InvertsTheExponential) {
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.3, -1.2, 0.8),
                                     Eigen::Vector3d(1e-9, 0, 2e-9),
                                     Eigen::Vector3d(0, 3.0, 0)}) {
    EXPECT_LT((QuaternionLog(dynamics::QuaternionExp<double>(phi)) - phi).norm(),
              16 * kEps * (1 + phi.norm()));
  }
}

}  // namespace
}  // namespace acro::analysis
