// The dynamics templates instantiated with ceres::Jet (forward-mode automatic differentiation),
// as the optimiser in analysis/ will use them. This is the one translation unit that compiles
// them for Jets (heavy); derivatives are checked against the double algorithms and against
// central differences.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <random>

#include "acro/dynamics/flight_simulation.h"
#include "standard_human_fixture.h"
#include "test_models.h"

namespace acro::dynamics {
namespace {

constexpr int kChunk = 8;
using Jet = ceres::Jet<double, kChunk>;

// Jet vector with values x and derivative seeds: entry first + j gets ∂/∂(direction j) = 1.
VectorX<Jet> Seed(const Eigen::VectorXd& x, int first, int count) {
  VectorX<Jet> out(x.size());
  for (int i = 0; i < x.size(); ++i) out[i] = Jet(x[i]);
  for (int j = 0; j < count; ++j) out[first + j].v[j] = 1.0;
  return out;
}

Eigen::VectorXd Values(const VectorX<Jet>& x) {
  Eigen::VectorXd out(x.size());
  for (int i = 0; i < x.size(); ++i) out[i] = x[i].a;
  return out;
}

class JetTest : public ::testing::Test {
 protected:
  std::mt19937 rng_{77};
  Model<double> model_ = testing::MakeStandardHuman();
  Model<Jet> jet_model_ = model_.Cast<Jet>();
  Eigen::VectorXd q_ = testing::RandomConfiguration(model_, rng_);
  Eigen::VectorXd v_ = testing::RandomVelocity(model_, rng_, 2.0);
  Eigen::VectorXd a_ = testing::RandomVelocity(model_, rng_, 5.0);
};

// ∂ID/∂a = M(q): automatic derivatives of inverse dynamics against the composite-rigid-body
// mass matrix, and the values against the double instantiation.
TEST_F(JetTest, InverseDynamicsDerivativeInAccelerationIsMassMatrix) {
  Workspace<double> ws(model_);
  const Eigen::MatrixXd M = CalcMassMatrix(model_, ws, q_);
  const Eigen::VectorXd tau = CalcInverseDynamics(model_, ws, q_, v_, a_);
  Workspace<Jet> jws(jet_model_);
  const VectorX<Jet> q = Seed(q_, 0, 0);
  const VectorX<Jet> v = Seed(v_, 0, 0);
  for (int first = 0; first < model_.nv(); first += kChunk) {
    const int count = std::min(kChunk, model_.nv() - first);
    const VectorX<Jet> a = Seed(a_, first, count);
    const VectorX<Jet>& jtau = CalcInverseDynamics(jet_model_, jws, q, v, a);
    EXPECT_LE(testing::RelativeError(Values(jtau), tau), 1e-14);
    for (int j = 0; j < count; ++j)
      for (int r = 0; r < model_.nv(); ++r)
        EXPECT_NEAR(jtau[r].v[j], M(r, first + j), 1e-12 * M.cwiseAbs().maxCoeff());
  }
}

// ∂ID/∂δ along q ⊕ δ (the tangent space, through the quaternion exponential) against central
// differences of the double inverse dynamics.
TEST_F(JetTest, InverseDynamicsDerivativeInConfigurationMatchesDifferences) {
  Workspace<double> ws(model_);
  Workspace<Jet> jws(jet_model_);
  const VectorX<Jet> q0 = Seed(q_, 0, 0);
  const VectorX<Jet> v = Seed(v_, 0, 0);
  const VectorX<Jet> a = Seed(a_, 0, 0);
  VectorX<Jet> q(model_.nq());
  const double h = 1e-6;
  double worst = 0.0;
  for (int first = 0; first < model_.nv(); first += kChunk) {
    const int count = std::min(kChunk, model_.nv() - first);
    const VectorX<Jet> delta = Seed(Eigen::VectorXd::Zero(model_.nv()), first, count);
    IntegrateConfiguration(jet_model_, q0, delta, Jet(1.0), q);
    const VectorX<Jet> jtau = CalcInverseDynamics(jet_model_, jws, q, v, a);
    for (int j = 0; j < count; ++j) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(model_.nv(), first + j);
      const Eigen::VectorXd plus =
          CalcInverseDynamics(model_, ws, testing::Integrate(model_, q_, e, h), v_, a_);
      const Eigen::VectorXd minus =
          CalcInverseDynamics(model_, ws, testing::Integrate(model_, q_, e, -h), v_, a_);
      const Eigen::VectorXd fd = (plus - minus) / (2 * h);
      Eigen::VectorXd ad(model_.nv());
      for (int r = 0; r < model_.nv(); ++r) ad[r] = jtau[r].v[j];
      worst = std::max(worst, testing::RelativeError(ad, fd));
    }
  }
  // Central differences of torques of O(10²) with h = 1e-6: rounding ~1e-14·10²/1e-6 = 1e-6
  // relative to a floor of 1, truncation ~1e-10.
  EXPECT_LE(worst, 1e-5);
}

// Point Jacobians from automatic differentiation of point positions equal CalcPointJacobian, and
// the Jet instantiations of momentum, centre of mass, mass matrix and flight acceleration agree
// with the double ones.
TEST_F(JetTest, KinematicsAndMomentumInstantiate) {
  Workspace<double> ws(model_);
  Workspace<Jet> jws(jet_model_);
  CalcForwardKinematics(model_, ws, q_, v_);
  Matrix3X<double> J(3, model_.nv());
  VectorX<Jet> q(model_.nq());
  const VectorX<Jet> q0 = Seed(q_, 0, 0);
  const int point = model_.FindPoint("r_hand_end");
  CalcPointJacobian(model_, ws, point, J);
  for (int first = 0; first < model_.nv(); first += kChunk) {
    const int count = std::min(kChunk, model_.nv() - first);
    IntegrateConfiguration(
        jet_model_, q0, Seed(Eigen::VectorXd::Zero(model_.nv()), first, count), Jet(1.0), q);
    CalcForwardKinematics(jet_model_, jws, q);
    const Vector3<Jet> p = CalcPointPosition(jet_model_, jws, point);
    for (int j = 0; j < count; ++j)
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(p[r].v[j], J(r, first + j), 1e-14);
  }
  const VectorX<Jet> v = Seed(v_, 0, 0);
  CalcForwardKinematics(jet_model_, jws, q0, v);
  const SpatialMomentum<Jet> L = CalcCentroidalMomentum(jet_model_, jws);
  const SpatialMomentum<double> Ld = CalcCentroidalMomentum(model_, ws);
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(L.rotational()[r].a, Ld.rotational()[r], 1e-12);
    EXPECT_NEAR(L.translational()[r].a, Ld.translational()[r], 1e-12);
  }
  const MatrixX<Jet>& M = CalcMassMatrix(jet_model_, jws, q0);
  const Eigen::MatrixXd Md = CalcMassMatrix(model_, ws, q_);
  for (int r = 0; r < model_.nv(); ++r)
    for (int c = 0; c < model_.nv(); ++c) EXPECT_NEAR(M(r, c).a, Md(r, c), 1e-12);
  VectorX<Jet> a = Seed(a_, 0, 0);
  Eigen::VectorXd ad = a_;
  CalcFlightRootAcceleration(jet_model_, jws, q0, v, a);
  CalcFlightRootAcceleration(model_, ws, q_, v_, ad);
  EXPECT_LE(testing::RelativeError(Values(a), ad), 1e-13);
  CalcInverseDynamics(jet_model_, jws, q0, v, a);
  const RootResidual<Jet> res = CalcRootResidual(jet_model_, jws, Jet(1.75));
  EXPECT_LE(std::abs(res.force_per_weight[2].a), 1e-12);
  EXPECT_NEAR(CalcCenterOfMassAcceleration(jet_model_, jws, q0, v, a)[2].a, -9.81, 1e-11);
}

// Flight simulation through Jets: the derivative of the final somersault rate with respect to the
// initial one matches a central difference.
TEST_F(JetTest, FlightSimulationDerivative) {
  FlightSimulationOptions options;
  options.duration_s = 0.2;
  options.step_s = 0.01;
  const int nj = model_.num_joint_dofs();
  auto joints_d =
      [nj](const double& t, VectorXRef<double> qj, VectorXRef<double> vj, VectorXRef<double> aj) {
        for (int k = 0; k < nj; ++k) {
          qj[k] = 0.3 * std::sin(2.0 * t + k);
          vj[k] = 0.6 * std::cos(2.0 * t + k);
          aj[k] = -1.2 * std::sin(2.0 * t + k);
        }
      };
  auto joints_j = [nj](const Jet& t, VectorXRef<Jet> qj, VectorXRef<Jet> vj, VectorXRef<Jet> aj) {
    for (int k = 0; k < nj; ++k) {
      qj[k] = 0.3 * sin(2.0 * t + double(k));
      vj[k] = 0.6 * cos(2.0 * t + double(k));
      aj[k] = -1.2 * sin(2.0 * t + double(k));
    }
  };
  Eigen::Matrix<double, 7, 1> q_root;
  q_root << 0, 0, 1, 1, 0, 0, 0;
  auto final_rate = [&](double w_y) {
    Vector6<double> v_root;
    v_root << 0, 0, 5, 0, w_y, 0.5;
    return SimulateFlight(model_, options, q_root, v_root, JointTrajectory<double>(joints_d))
        .v.back()[4];
  };
  Eigen::Matrix<Jet, 7, 1> jq_root = q_root.cast<Jet>();
  Vector6<Jet> jv_root;
  jv_root << Jet(0), Jet(0), Jet(5), Jet(0), Jet(6.0, 0), Jet(0.5);
  const FlightSimulationResult<Jet> r =
      SimulateFlight(jet_model_, options, jq_root, jv_root, JointTrajectory<Jet>(joints_j));
  ASSERT_EQ(r.summary.status, FlightSimulationStatus::kSuccess);
  EXPECT_NEAR(r.v.back()[4].a, final_rate(6.0), 1e-12);
  const double fd = (final_rate(6.0 + 1e-6) - final_rate(6.0 - 1e-6)) / 2e-6;
  // Central difference with h = 1e-6 of an O(10) rate: rounding ~1e-9, truncation ~1e-12.
  EXPECT_NEAR(r.v.back()[4].v[0], fd, 1e-7);
}

}  // namespace
}  // namespace acro::dynamics
