#include "acro/dynamics/inverse_dynamics.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <limits>
#include <random>

#include "standard_human_fixture.h"
#include "test_models.h"

namespace acro::dynamics {
namespace {

using testing::Integrate;
using testing::MakeRandomTree;
using testing::RandomConfiguration;
using testing::RandomVector;
using testing::RandomVelocity;
using testing::RelativeError;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Inverse dynamics equals M(q)·a + h(q, v) for random trees of up to 20 segments with every joint
// type and axis sequence (the acceptance: 1e-9 relative).
TEST(InverseDynamicsTest, EqualsMassMatrixTimesAccelerationPlusBias) {
  std::mt19937 rng(42);
  double worst = 0.0;
  for (int tree = 0; tree < 24; ++tree) {
    const int num_segments = 1 + tree % 20;
    const Model<double> model = MakeRandomTree(rng, tree < 20 ? num_segments : 20, tree);
    Workspace<double> ws(model);
    for (int state = 0; state < 5; ++state) {
      const Eigen::VectorXd q = RandomConfiguration(model, rng);
      const Eigen::VectorXd v = RandomVelocity(model, rng, 3.0);
      const Eigen::VectorXd a = RandomVelocity(model, rng, 10.0);
      const Eigen::VectorXd tau = CalcInverseDynamics(model, ws, q, v, a);
      const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
      const Eigen::VectorXd h = CalcBiasForces(model, ws, q, v);
      const double err = (tau - (M * a + h)).norm() / tau.norm();
      worst = std::max(worst, err);
      EXPECT_LE(err, 1e-9) << "tree " << tree << " state " << state;
      // M is positive definite (its symmetry is by construction: CalcMassMatrix writes both
      // halves).
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff(), 0.0);
    }
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  std::printf("ID vs M a + h: worst relative error %.3g\n", worst);
}

// At the same configuration, inverse dynamics that reuses the poses of the previous pass (after
// CalcInverseDynamics or CalcMassMatrix) equals a full pass for other velocities and
// accelerations, and so does the root residual read from it.
TEST(InverseDynamicsTest, SameConfigurationPassEqualsFullPass) {
  std::mt19937 rng(11);
  const Model<double> model = testing::MakeStandardHuman();
  Workspace<double> ws(model), ws_full(model);
  for (int state = 0; state < 5; ++state) {
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    if (state % 2 == 0)
      CalcInverseDynamics(
          model, ws, q, RandomVelocity(model, rng, 3.0), RandomVelocity(model, rng, 10.0));
    else
      CalcMassMatrix(model, ws, q);
    for (int k = 0; k < 3; ++k) {
      const Eigen::VectorXd v = RandomVelocity(model, rng, 3.0);
      const Eigen::VectorXd a = RandomVelocity(model, rng, 10.0);
      const Eigen::VectorXd reused = CalcInverseDynamicsAtSameConfiguration(model, ws, v, a);
      const Eigen::VectorXd full = CalcInverseDynamics(model, ws_full, q, v, a);
      EXPECT_LE((reused - full).norm(), 1e-12 * full.norm()) << "state " << state;
      const RootResidual<double> r = CalcRootResidual(model, ws, 1.75);
      const RootResidual<double> rf = CalcRootResidual(model, ws_full, 1.75);
      EXPECT_LE((r.F_Scm_W.get_coeffs() - rf.F_Scm_W.get_coeffs()).norm(),
                1e-12 * rf.F_Scm_W.get_coeffs().norm());
    }
  }
}

// Changing one joint's rates and accelerations and recomputing only its subtree gives the root
// wrench of a full pass with the changed state, for every joint of random trees and the reference
// human, one after the other from the same base pass (which must stay as it was).
TEST(InverseDynamicsTest, RootWrenchWithOneJointChangedEqualsFullPass) {
  std::mt19937 rng(5);
  for (int tree = 0; tree < 6; ++tree) {
    const Model<double> model =
        tree < 5 ? MakeRandomTree(rng, 4 + 3 * tree, tree) : testing::MakeStandardHuman();
    Workspace<double> ws(model), ws_full(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::VectorXd v = RandomVelocity(model, rng, 3.0);
    const Eigen::VectorXd a = RandomVelocity(model, rng, 10.0);
    CalcInverseDynamics(model, ws, q, v, a);
    const Vector6<double> base = ws.F_Bo_B[0].get_coeffs();
    int checked = 0;
    for (int i = 1; i < model.num_segments(); ++i) {
      const Segment<double>& seg = model.segment(i);
      for (int k = 0; k < seg.num_axes; ++k) {
        Eigen::VectorXd v_new = v, a_new = a;
        v_new[seg.v_start + k] += 1.5;
        a_new[seg.v_start + k] -= 4.0;
        const SpatialForce<double> F = CalcRootWrenchWithJointChanged(model, ws, i, v_new, a_new);
        CalcInverseDynamics(model, ws_full, q, v_new, a_new);
        const Vector6<double> full = ws_full.F_Bo_B[0].get_coeffs();
        EXPECT_LE((F.get_coeffs() - full).norm(), 1e-11 * full.norm())
            << "tree " << tree << " segment " << i << " axis " << k;
        EXPECT_GT((full - base).norm(), 1e-6);  // the change is seen at the root
        ++checked;
      }
    }
    EXPECT_EQ(ws.F_Bo_B[0].get_coeffs(), base);
    EXPECT_GT(checked, 0);
  }
}

// M from the composite-rigid-body algorithm equals Σ_B m_B Jv_Bcmᵀ Jv_Bcm + Jω_Bᵀ I_Bcm Jω_B, the
// kinetic-energy form built from the segment and point Jacobians (a third, independent path).
TEST(InverseDynamicsTest, MassMatrixEqualsJacobianEnergyForm) {
  std::mt19937 rng(7);
  for (int tree = 0; tree < 4; ++tree) {
    const Model<double> model =
        tree < 3 ? MakeRandomTree(rng, 20, 7 * tree) : testing::MakeStandardHuman();
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
    Eigen::MatrixXd M_energy = Eigen::MatrixXd::Zero(model.nv(), model.nv());
    Matrix6X<double> Jb(6, model.nv());
    Matrix3X<double> Jc(3, model.nv());
    for (int b = 0; b < model.num_segments(); ++b) {
      const Segment<double>& s = model.segment(b);
      CalcSegmentJacobian(model, ws, b, Jb);
      CalcPointJacobian(model, ws, b, s.p_BoBcm_B, Jc);
      const Eigen::Matrix3d& R = ws.X_WB[static_cast<size_t>(b)].rotation();
      const Eigen::Matrix3d I_W = R * s.I_BBcm_B * R.transpose();
      M_energy +=
          s.mass * Jc.transpose() * Jc + Jb.topRows<3>().transpose() * I_W * Jb.topRows<3>();
    }
    // Entries reach m·|p|² ≈ 10²; a few hundred roundings of them.
    EXPECT_LE(RelativeError(M, M_energy), 1e-12);
  }
}

// A free rigid body on its analytic ballistic trajectory needs no root wrench: the centre of mass
// on the parabola p(t) = p0 + v0 t + ½ g t², the body spinning at constant rate about a principal
// axis (Euler's equations hold with ω̇ = 0). Also for the human with all joints frozen.
TEST(InverseDynamicsTest, BallisticRigidBodyHasZeroRootResidual) {
  std::mt19937 rng(5);
  ModelBuilder b("body", testing::RandomMass(rng));
  b.SetGravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  std::vector<Model<double>> models = {b.Build(), testing::MakeStandardHuman()};
  for (const Model<double>& model : models) {
    Workspace<double> ws(model);
    Eigen::VectorXd q = RandomConfiguration(model, rng);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
    Eigen::VectorXd a = Eigen::VectorXd::Zero(model.nv());
    // Whole-body inertia about the centre of mass in the root frame, from the composite inertia.
    CalcMassMatrix(model, ws, q);
    const SpatialInertia<double>& Ic = ws.Ic_Bo_B[0];
    const Eigen::Vector3d c = Ic.com();
    const Eigen::Matrix3d I_com = Ic.rotational_inertia() + Ic.mass() * Skew(c) * Skew(c);
    const Eigen::Vector3d axis =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I_com).eigenvectors().col(0);
    const Eigen::Vector3d w_B = 7.0 * axis;  // rad/s about a principal axis, constant
    const Eigen::Vector3d v_com0(1.0, -0.5, 6.0);
    const Eigen::Vector3d g = model.gravity_W();
    for (double t : {0.0, 0.3, 0.77}) {
      // Root pose at t: R(t) = R0 exp(ω t); p_WoBo = p_com(t) − R(t) c.
      Eigen::VectorXd qt = Integrate(
          model,
          q,
          [&] {
            Eigen::VectorXd dv = Eigen::VectorXd::Zero(model.nv());
            dv.segment<3>(3) = w_B;
            return dv;
          }(),
          t);
      const Eigen::Matrix3d R = GetRootQuaternion(qt).toRotationMatrix();
      const Eigen::Vector3d p_com = Eigen::Vector3d(0.1, 0.2, 1.0) + v_com0 * t + 0.5 * g * t * t;
      qt.head<3>() = p_com - R * c;
      // ṗ = v_com − R (ω × c), p̈ = g − R (ω × (ω × c)).
      v.head<3>() = v_com0 + g * t - R * w_B.cross(c);
      v.segment<3>(3) = w_B;
      a.head<3>() = g - R * w_B.cross(w_B.cross(c));
      a.segment<3>(3).setZero();
      const Eigen::VectorXd tau = CalcInverseDynamics(model, ws, qt, v, a);
      // Residual relative to the body weight and weight × 1 m; rounding of O(10²) terms.
      const double weight = model.total_mass() * 9.81;
      EXPECT_LE(tau.head<6>().cwiseAbs().maxCoeff() / weight, 1e-12) << "t = " << t;
      const RootResidual<double> r = CalcRootResidual(model, ws, 1.75);
      std::printf(
          "ballistic %s, t = %.2f s: root residual / weight %.2g, moment / (weight height) %.2g\n",
          model.segment(0).name.c_str(),
          t,
          r.force_per_weight.cwiseAbs().maxCoeff(),
          r.moment_per_weight_height.cwiseAbs().maxCoeff());
      EXPECT_LE(r.force_per_weight.cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LE(r.moment_per_weight_height.cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

// The root residual at the centre of mass is the rate of change of the whole-body momentum minus
// gravity: F = m (a_Scm − g), M_Scm = dH_Scm/dt (Newton–Euler equations of the whole system).
TEST(InverseDynamicsTest, RootResidualIsMomentumRateAtCenterOfMass) {
  std::mt19937 rng(9);
  const Model<double> model = testing::MakeStandardHuman();
  Workspace<double> ws(model);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::VectorXd v = RandomVelocity(model, rng, 2.0);
    const Eigen::VectorXd a = RandomVelocity(model, rng, 5.0);
    CalcInverseDynamics(model, ws, q, v, a);
    const RootResidual<double> r = CalcRootResidual(model, ws, 1.75);
    const Eigen::Vector3d a_com = CalcCenterOfMassAcceleration(model, ws, q, v, a);
    const Eigen::Vector3d F_expected = model.total_mass() * (a_com - model.gravity_W());
    EXPECT_LE((r.F_Scm_W.translational() - F_expected).cwiseAbs().maxCoeff(),
              1e-10 * F_expected.norm());
    // dH/dt by central differences along q(t) = q ⊕ (t v + ½ t² a), v(t) = v + t a.
    const double dt = 1e-5;
    auto H_at = [&](double t) {
      CalcForwardKinematics(
          model, ws, Integrate(model, q, v * t + 0.5 * t * t * a, 1.0), v + t * a);
      return CalcCentroidalMomentum(model, ws).rotational();
    };
    const Eigen::Vector3d dH = (H_at(dt) - H_at(-dt)) / (2 * dt);
    // Central difference with step 1e-5 on momenta of O(10–100): truncation ~1e-8, rounding ~1e-9.
    EXPECT_LE((r.F_Scm_W.rotational() - dH).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, dH.norm()));
    // Normalisation by weight and weight × height.
    const double weight = model.total_mass() * 9.81;
    EXPECT_LE((r.force_per_weight - r.F_Scm_W.translational() / weight).cwiseAbs().maxCoeff(),
              4 * kEps);
    EXPECT_LE((r.moment_per_weight_height - r.F_Scm_W.rotational() / (weight * 1.75))
                  .cwiseAbs()
                  .maxCoeff(),
              4 * kEps);
  }
}

// An applied wrench F_Bo_W on segment B enters as −J_WBᵀ F (virtual power): ID with the wrench
// equals ID without it minus the Jacobian-transpose map of the wrench.
TEST(InverseDynamicsTest, ExternalWrenchesEnterThroughJacobianTranspose) {
  std::mt19937 rng(13);
  for (int tree = 0; tree < 3; ++tree) {
    const Model<double> model =
        tree < 2 ? MakeRandomTree(rng, 15, 11 * tree) : testing::MakeStandardHuman();
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::VectorXd v = RandomVelocity(model, rng, 2.0);
    const Eigen::VectorXd a = RandomVelocity(model, rng, 5.0);
    std::vector<SpatialForce<double>> F(static_cast<size_t>(model.num_segments()));
    for (auto& f : F) f = SpatialForce<double>(RandomVector(rng, 50.0), RandomVector(rng, 500.0));
    const Eigen::VectorXd tau_free = CalcInverseDynamics(model, ws, q, v, a);
    const Eigen::VectorXd tau_ext = CalcInverseDynamics(model, ws, q, v, a, &F);
    Eigen::VectorXd expected = tau_free;
    Matrix6X<double> J(6, model.nv());
    for (int b = 0; b < model.num_segments(); ++b) {
      CalcSegmentJacobian(model, ws, b, J);
      expected -= J.transpose() * F[static_cast<size_t>(b)].get_coeffs();
    }
    EXPECT_LE(RelativeError(tau_ext, expected), 1e-12);
  }
}

// Power balance: the kinetic energy, summed over segments from their velocities, changes at the
// rate vᵀ (ID(q, v, a) − ID(q, 0, 0)): the power of the generalised forces other than gravity
// (Lagrange's equations; a check of the velocity-product terms independent of the mass matrix).
TEST(InverseDynamicsTest, KineticEnergyRateIsPowerOfNonGravityForces) {
  std::mt19937 rng(21);
  for (int tree = 0; tree < 4; ++tree) {
    const Model<double> model =
        tree < 3 ? MakeRandomTree(rng, 20, 6 * tree) : testing::MakeStandardHuman();
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::VectorXd v = RandomVelocity(model, rng, 2.0);
    const Eigen::VectorXd a = RandomVelocity(model, rng, 5.0);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
    const Eigen::VectorXd tau = CalcInverseDynamics(model, ws, q, v, a);
    const Eigen::VectorXd tau_g = CalcInverseDynamics(model, ws, q, zero, zero);
    const double power = v.dot(tau - tau_g);
    // T = Σ ½ (m |v_Bcm|² + ωᵀ I_Bcm ω), all in W.
    auto kinetic_energy = [&](double t) {
      CalcForwardKinematics(
          model, ws, Integrate(model, q, v * t + 0.5 * t * t * a, 1.0), v + t * a);
      double T = 0.0;
      for (int b = 0; b < model.num_segments(); ++b) {
        const Segment<double>& s = model.segment(b);
        const SpatialMotion<double>& V = ws.V_WB_B[static_cast<size_t>(b)];
        const Eigen::Vector3d v_cm = V.translational() + V.rotational().cross(s.p_BoBcm_B);
        T += 0.5 * (s.mass * v_cm.squaredNorm() + V.rotational().dot(s.I_BBcm_B * V.rotational()));
      }
      return T;
    };
    const double dt = 1e-5;
    const double rate = (kinetic_energy(dt) - kinetic_energy(-dt)) / (2 * dt);
    // Central difference (h = 1e-5) of energies of O(10²–10³) J: truncation ~1e-8, rounding ~1e-8.
    EXPECT_LE(std::abs(rate - power), 1e-6 * std::max(1.0, std::abs(power))) << "tree " << tree;
  }
}

// The flight root acceleration leaves no root residual, and the centre of mass then falls at g.
TEST(InverseDynamicsTest, FlightRootAccelerationCancelsResidual) {
  std::mt19937 rng(17);
  const Model<double> model = testing::MakeStandardHuman();
  Workspace<double> ws(model);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    const Eigen::VectorXd v = RandomVelocity(model, rng, 3.0);
    Eigen::VectorXd a = RandomVelocity(model, rng, 10.0);
    CalcFlightRootAcceleration(model, ws, q, v, a);
    const Eigen::VectorXd tau = CalcInverseDynamics(model, ws, q, v, a);
    EXPECT_LE(tau.head<6>().cwiseAbs().maxCoeff() / (model.total_mass() * 9.81), 1e-12);
    const Eigen::Vector3d a_com = CalcCenterOfMassAcceleration(model, ws, q, v, a);
    EXPECT_LE((a_com - model.gravity_W()).cwiseAbs().maxCoeff(), 1e-11);
  }
}

}  // namespace
}  // namespace acro::dynamics

namespace acro::dynamics {
namespace {

// A workspace made for another model, or vectors of the wrong size, are programming errors that
// ACRO_DEMAND reports instead of reading out of bounds.
TEST(InverseDynamicsTest, RejectsMismatchedWorkspaceAndSizes) {
  std::mt19937 rng(3);
  const Model<double> human = testing::MakeStandardHuman();
  const Model<double> tree = MakeRandomTree(rng, 5, 0);
  Workspace<double> ws_tree(tree);
  const Eigen::VectorXd q = MakeNeutralConfiguration(human);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(human.nv());
  EXPECT_THROW(CalcInverseDynamics(human, ws_tree, q, v, v), std::logic_error);
  EXPECT_THROW(CalcForwardKinematics(human, ws_tree, q), std::logic_error);
  Workspace<double> ws(human);
  EXPECT_THROW(CalcInverseDynamics(human, ws, q, v, Eigen::VectorXd::Zero(3)), std::logic_error);
  EXPECT_NO_THROW(CalcInverseDynamics(human, ws, q, v, v));
  // The passes that build on an earlier one refuse a workspace without it.
  Workspace<double> fresh(human);
  EXPECT_THROW(CalcInverseDynamicsAtSameConfiguration(human, fresh, v, v), std::logic_error);
  EXPECT_THROW(CalcRootWrenchWithJointChanged(human, fresh, 1, v, v), std::logic_error);
  CalcForwardKinematics(human, fresh, q);
  EXPECT_NO_THROW(CalcInverseDynamicsAtSameConfiguration(human, fresh, v, v));
  CalcForwardKinematics(human, fresh, q);  // V, A and F are no longer a pass's
  EXPECT_THROW(CalcRootWrenchWithJointChanged(human, fresh, 1, v, v), std::logic_error);
  std::vector<SpatialForce<double>> F_ext(static_cast<size_t>(human.num_segments()),
                                          SpatialForce<double>::Zero());
  CalcInverseDynamics(human, fresh, q, v, v, &F_ext);  // applied wrenches
  EXPECT_THROW(CalcRootWrenchWithJointChanged(human, fresh, 1, v, v), std::logic_error);
  CalcInverseDynamics(human, fresh, q, v, v);
  EXPECT_NO_THROW(CalcRootWrenchWithJointChanged(human, fresh, 1, v, v));
  // A scaled quaternion describes the same orientation.
  std::mt19937 rng2(4);
  const Eigen::VectorXd qr = RandomConfiguration(human, rng2);
  const Eigen::VectorXd vr = RandomVelocity(human, rng2, 2.0);
  const Eigen::VectorXd tau = CalcInverseDynamics(human, ws, qr, vr, vr);
  Eigen::VectorXd q_scaled = qr;
  q_scaled.segment<4>(3) *= 1.7;
  EXPECT_LE(RelativeError(CalcInverseDynamics(human, ws, q_scaled, vr, vr), tau), 1e-14);
  // World poses not computed by a plain inverse dynamics are not silently read.
  EXPECT_THROW(CalcCenterOfMassPosition(human, ws), std::logic_error);
  CalcForwardKinematics(human, ws, q);
  EXPECT_NO_THROW(CalcCenterOfMassPosition(human, ws));
}

}  // namespace
}  // namespace acro::dynamics
