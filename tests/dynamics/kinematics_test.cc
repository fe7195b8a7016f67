#include "acro/dynamics/kinematics.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "standard_human_fixture.h"
#include "test_models.h"

namespace acro::dynamics {
namespace {

using testing::Integrate;
using testing::MakeRandomTree;
using testing::RandomConfiguration;
using testing::RandomVelocity;
using testing::RotationLog;

// Central differences with step 1e-6 on O(1) quantities: truncation ε²·|f'''|/6 ≈ 1e-12 plus
// rounding 1e-16/ε ≈ 1e-10; 1e-8 leaves margin for third derivatives up to ~10⁴.
constexpr double kFdStep = 1e-6;
constexpr double kFdTol = 1e-8;

class KinematicsTest : public ::testing::Test {
 protected:
  std::mt19937 rng_{3};
  std::vector<Model<double>> Models() {
    std::vector<Model<double>> models;
    // Random trees of up to 20 segments; offsets rotate which joint gets which sequence so that
    // all 21 sequences and fixed joints appear.
    for (int k = 0; k < 4; ++k) models.push_back(MakeRandomTree(rng_, 20, 5 * k));
    models.push_back(testing::MakeStandardHuman());
    return models;
  }
};

TEST_F(KinematicsTest, PointJacobiansMatchCentralDifferences) {
  for (const Model<double>& model : Models()) {
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng_);
    Matrix3X<double> J(3, model.nv());
    double worst = 0.0;
    for (int p = 0; p < model.num_points(); ++p) {
      CalcForwardKinematics(model, ws, q);
      CalcPointJacobian(model, ws, p, J);
      for (int k = 0; k < model.nv(); ++k) {
        const Eigen::VectorXd e = Eigen::VectorXd::Unit(model.nv(), k);
        CalcForwardKinematics(model, ws, Integrate(model, q, e, kFdStep));
        const Eigen::Vector3d plus = CalcPointPosition(model, ws, p);
        CalcForwardKinematics(model, ws, Integrate(model, q, e, -kFdStep));
        const Eigen::Vector3d minus = CalcPointPosition(model, ws, p);
        const Eigen::Vector3d fd = (plus - minus) / (2 * kFdStep);
        worst = std::max(worst, (J.col(k) - fd).cwiseAbs().maxCoeff());
        EXPECT_LE((J.col(k) - fd).cwiseAbs().maxCoeff(), kFdTol)
            << "point " << model.point(p).name << ", velocity " << model.VelocityName(k);
      }
    }
    std::printf("point Jacobians vs central differences (%d points): worst %.3g\n",
                model.num_points(),
                worst);
  }
}

TEST_F(KinematicsTest, SegmentJacobiansMatchCentralDifferences) {
  for (const Model<double>& model : Models()) {
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng_);
    Matrix6X<double> J(6, model.nv());
    double worst = 0.0;
    for (int b = 0; b < model.num_segments(); ++b) {
      CalcForwardKinematics(model, ws, q);
      CalcSegmentJacobian(model, ws, b, J);
      for (int k = 0; k < model.nv(); ++k) {
        const Eigen::VectorXd e = Eigen::VectorXd::Unit(model.nv(), k);
        CalcForwardKinematics(model, ws, Integrate(model, q, e, kFdStep));
        const RigidTransform<double> plus = ws.X_WB[static_cast<size_t>(b)];
        CalcForwardKinematics(model, ws, Integrate(model, q, e, -kFdStep));
        const RigidTransform<double> minus = ws.X_WB[static_cast<size_t>(b)];
        // ω_W: R₊ R₋ᵀ = exp([2ε ω]×) + O(ε³); v_Bo: central difference of p_WoBo.
        Vector6<double> fd;
        fd << RotationLog(plus.rotation() * minus.rotation().transpose()) / (2 * kFdStep),
            (plus.translation() - minus.translation()) / (2 * kFdStep);
        worst = std::max(worst, (J.col(k) - fd).cwiseAbs().maxCoeff());
        EXPECT_LE((J.col(k) - fd).cwiseAbs().maxCoeff(), kFdTol)
            << "segment " << model.segment(b).name << ", velocity " << model.VelocityName(k);
      }
    }
    std::printf("segment Jacobians vs central differences (%d segments): worst %.3g\n",
                model.num_segments(),
                worst);
  }
}

TEST_F(KinematicsTest, VelocitiesAgreeWithJacobiansAndDifferences) {
  for (const Model<double>& model : Models()) {
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng_);
    const Eigen::VectorXd v = RandomVelocity(model, rng_, 2.0);
    CalcForwardKinematics(model, ws, q, v);
    Matrix3X<double> Jp(3, model.nv());
    Matrix6X<double> Jb(6, model.nv());
    for (int p = 0; p < model.num_points(); ++p) {
      CalcPointJacobian(model, ws, p, Jp);
      EXPECT_LE((CalcPointVelocity(model, ws, p) - Jp * v).cwiseAbs().maxCoeff(), 1e-12);
    }
    for (int b = 0; b < model.num_segments(); ++b) {
      CalcSegmentJacobian(model, ws, b, Jb);
      EXPECT_LE((CalcSegmentSpatialVelocity(ws, b).get_coeffs() - Jb * v).cwiseAbs().maxCoeff(),
                1e-12);
    }
    // Centre-of-mass velocity against the difference of its position along q ⊕ v t.
    const Eigen::Vector3d v_com = CalcCenterOfMassVelocity(model, ws);
    CalcForwardKinematics(model, ws, Integrate(model, q, v, kFdStep));
    const Eigen::Vector3d plus = CalcCenterOfMassPosition(model, ws);
    CalcForwardKinematics(model, ws, Integrate(model, q, v, -kFdStep));
    const Eigen::Vector3d minus = CalcCenterOfMassPosition(model, ws);
    EXPECT_LE((v_com - (plus - minus) / (2 * kFdStep)).cwiseAbs().maxCoeff(), kFdTol);
    // Centre-of-mass Jacobian: J v = v_com, and column by column against central differences.
    CalcForwardKinematics(model, ws, q);
    Matrix3X<double> Jc(3, model.nv());
    CalcCenterOfMassJacobian(model, ws, Jc);
    EXPECT_LE((Jc * v - v_com).cwiseAbs().maxCoeff(), 1e-12);
    for (int k = 0; k < model.nv(); ++k) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(model.nv(), k);
      CalcForwardKinematics(model, ws, Integrate(model, q, e, kFdStep));
      const Eigen::Vector3d p_plus = CalcCenterOfMassPosition(model, ws);
      CalcForwardKinematics(model, ws, Integrate(model, q, e, -kFdStep));
      const Eigen::Vector3d p_minus = CalcCenterOfMassPosition(model, ws);
      EXPECT_LE((Jc.col(k) - (p_plus - p_minus) / (2 * kFdStep)).cwiseAbs().maxCoeff(), kFdTol);
    }
  }
}

TEST_F(KinematicsTest, CenterOfMassAccelerationMatchesDifferences) {
  for (const Model<double>& model : Models()) {
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng_);
    const Eigen::VectorXd v = RandomVelocity(model, rng_, 2.0);
    const Eigen::VectorXd a = RandomVelocity(model, rng_, 5.0);
    const Eigen::Vector3d a_com = CalcCenterOfMassAcceleration(model, ws, q, v, a);
    // Along q(t) = q ⊕ (t v + ½ t² a), v(t) = v + t a (exact to O(t²) on the group).
    auto v_com_at = [&](double t) {
      CalcForwardKinematics(
          model, ws, Integrate(model, q, v * t + 0.5 * t * t * a, 1.0), v + t * a);
      return CalcCenterOfMassVelocity(model, ws);
    };
    const Eigen::Vector3d fd = (v_com_at(kFdStep) - v_com_at(-kFdStep)) / (2 * kFdStep);
    // Accelerations reach ~10²: the same bound scaled.
    EXPECT_LE((a_com - fd).cwiseAbs().maxCoeff(), 100 * kFdTol);
  }
}

TEST_F(KinematicsTest, CentroidalMomentumIsMassTimesComVelocityAndJacobianSum) {
  for (const Model<double>& model : Models()) {
    Workspace<double> ws(model);
    const Eigen::VectorXd q = RandomConfiguration(model, rng_);
    const Eigen::VectorXd v = RandomVelocity(model, rng_, 2.0);
    CalcForwardKinematics(model, ws, q, v);
    const SpatialMomentum<double> L = CalcCentroidalMomentum(model, ws);
    EXPECT_LE((L.translational() - model.total_mass() * CalcCenterOfMassVelocity(model, ws))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-11);
    // Independent sum over segments: Σ (p_ScmBcm × m v_Bcm + R I_Bcm Rᵀ ω).
    const Eigen::Vector3d com = CalcCenterOfMassPosition(model, ws);
    Eigen::Vector3d H = Eigen::Vector3d::Zero();
    Matrix3X<double> J(3, model.nv());
    for (int b = 0; b < model.num_segments(); ++b) {
      const Segment<double>& s = model.segment(b);
      const RigidTransform<double>& X = ws.X_WB[static_cast<size_t>(b)];
      CalcPointJacobian(model, ws, b, s.p_BoBcm_B, J);
      const Eigen::Vector3d w = CalcSegmentSpatialVelocity(ws, b).rotational();
      H += (X * s.p_BoBcm_B - com).cross(s.mass * (J * v)) +
           X.rotation() * s.I_BBcm_B * X.rotation().transpose() * w;
    }
    EXPECT_LE((L.rotational() - H).cwiseAbs().maxCoeff(), 1e-11 * std::max(1.0, H.norm()));
  }
}

TEST(ConfigurationTest, QuaternionRatesAndIntegration) {
  std::mt19937 rng(11);
  const Model<double> model = testing::MakeStandardHuman();
  const Eigen::VectorXd q = RandomConfiguration(model, rng);
  const Eigen::VectorXd v = RandomVelocity(model, rng, 3.0);
  Eigen::VectorXd qdot(model.nq()), v_back(model.nv());
  CalcConfigurationDerivative(model, q, v, qdot);
  Eigen::MatrixXd N(model.nq(), model.nv());
  CalcConfigurationDerivativeMatrix(model, q, N);
  EXPECT_LE((N * v - qdot).cwiseAbs().maxCoeff(), 1e-15 * 8);
  CalcVelocityFromConfigurationDerivative(model, q, qdot, v_back);
  EXPECT_LE((v_back - v).cwiseAbs().maxCoeff(), 64 * 1e-16 * 3.0);
  // q ⊕ v dt differentiates to q̇ at dt = 0.
  const Eigen::VectorXd fd =
      (Integrate(model, q, v, kFdStep) - Integrate(model, q, v, -kFdStep)) / (2 * kFdStep);
  EXPECT_LE((fd - qdot).cwiseAbs().maxCoeff(), kFdTol);
  // The quaternion stays unit over large steps; the root rotation is exp of ω_B dt (body frame).
  const Eigen::VectorXd q2 = Integrate(model, q, v, 10.0);
  EXPECT_NEAR(GetRootQuaternion(q2).norm(), 1.0, 16 * 1e-16);
  const Eigen::Matrix3d R_rel = GetRootQuaternion(q).toRotationMatrix().transpose() *
                                GetRootQuaternion(q2).toRotationMatrix();
  const Eigen::Vector3d w = v.segment<3>(3);
  const double angle = std::fmod(10.0 * w.norm(), 2 * M_PI);
  EXPECT_LE(
      (R_rel - Eigen::AngleAxisd(angle, w.normalized()).toRotationMatrix()).cwiseAbs().maxCoeff(),
      1e-12);
  // R_WB from the stored (w, x, y, z) agrees with Eigen's quaternion (x, y, z, w storage).
  EXPECT_LE((QuaternionToRotation(q[3], q[4], q[5], q[6]) - GetRootQuaternion(q).toRotationMatrix())
                .cwiseAbs()
                .maxCoeff(),
            8e-16);
}

}  // namespace
}  // namespace acro::dynamics
