// Simbody (Sherman, Seth & Delp 2011) as an independent oracle for inverse dynamics: the same
// model is built from Simbody mobilizers (Free for the root, a chain of Pin mobilizers with
// massless intermediate bodies for each Euler-angle joint, Weld for fixed joints), and
// SimbodyMatterSubsystem::calcResidualForceIgnoringConstraints gives τ = M u̇ + C − applied.
// This target is compiled without NDEBUG (Simbody's headers change layouts under it).

#include <gtest/gtest.h>

#include <random>

#include "acro/dynamics/inverse_dynamics.h"
#include "standard_human_fixture.h"
#include "test_models.h"

#if ACRO_HAVE_SIMBODY
// Only the headers needed: Simbody.h also pulls simmath's ContactGeometry.h, whose operator==
// is ambiguous under C++20's rewritten comparisons.
#include "SimTKcommon.h"
#include "simbody/internal/Body.h"
#include "simbody/internal/MobilizedBody_Free.h"
#include "simbody/internal/MobilizedBody_Ground.h"
#include "simbody/internal/MobilizedBody_Pin.h"
#include "simbody/internal/MobilizedBody_Weld.h"
#include "simbody/internal/MultibodySystem.h"
#include "simbody/internal/SimbodyMatterSubsystem.h"
#endif

namespace acro::dynamics {
namespace {

#if ACRO_HAVE_SIMBODY

SimTK::Vec3 ToSimTK(const Eigen::Vector3d& v) {
  return SimTK::Vec3(v.x(), v.y(), v.z());
}

SimTK::Rotation ToSimTK(const Eigen::Matrix3d& R) {
  SimTK::Mat33 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = R(r, c);
  return SimTK::Rotation(m, true);  // already orthonormal
}

// The frame whose z axis is axis `a` of its parent (a Pin rotates about z).
SimTK::Rotation ZTo(int axis) {
  if (axis == 0) return SimTK::Rotation(SimTK::Pi / 2, SimTK::YAxis);
  if (axis == 1) return SimTK::Rotation(-SimTK::Pi / 2, SimTK::XAxis);
  return SimTK::Rotation();
}

// The model as a Simbody system. Real (massive) mobilized bodies are recorded per segment.
class SimbodyModel {
 public:
  explicit SimbodyModel(const Model<double>& model) : matter_(system_) {
    for (int i = 0; i < model.num_segments(); ++i) {
      const Segment<double>& s = model.segment(i);
      // Inertia about the segment origin: I_Bo = I_Bcm + m (|c|² 1 − c cᵀ).
      const Eigen::Vector3d& c = s.p_BoBcm_B;
      const Eigen::Matrix3d I_o =
          s.I_BBcm_B + s.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
      const SimTK::Body::Rigid body(SimTK::MassProperties(
          s.mass,
          ToSimTK(c),
          SimTK::Inertia(I_o(0, 0), I_o(1, 1), I_o(2, 2), I_o(0, 1), I_o(0, 2), I_o(1, 2))));
      if (s.joint_type == JointType::kFree) {
        bodies_.push_back(SimTK::MobilizedBody::Free(
            matter_.updGround(), SimTK::Transform(), body, SimTK::Transform()));
        continue;
      }
      SimTK::MobilizedBody parent = bodies_[static_cast<size_t>(s.parent)];
      const SimTK::Transform X_PJ(ToSimTK(s.X_PJ.rotation()), ToSimTK(s.X_PJ.translation()));
      if (s.joint_type == JointType::kFixed) {
        bodies_.push_back(SimTK::MobilizedBody::Weld(parent, X_PJ, body, SimTK::Transform()));
        continue;
      }
      // Chain of pins: pin k turns intermediate frame k−1 about its axis a_k.
      for (int k = 0; k < s.num_axes; ++k) {
        const int axis = s.axes[static_cast<size_t>(k)];
        const SimTK::Transform X_PF =
            k == 0 ? X_PJ * SimTK::Transform(ZTo(axis)) : SimTK::Transform(ZTo(axis));
        const SimTK::Transform X_BM(ZTo(axis));
        const bool last = k + 1 == s.num_axes;
        SimTK::MobilizedBody::Pin pin(
            parent, X_PF, last ? SimTK::Body(body) : SimTK::Body(SimTK::Body::Massless()), X_BM);
        parent = pin;
      }
      bodies_.push_back(parent);
    }
    system_.realizeTopology();
    state_ = system_.getDefaultState();
  }

  // M(q) in Acrolab's convention from Simbody's calcM: with u = P v (u_ω = R w_WB_B, u_v =
  // v_WBo_W), M = Pᵀ M_Simbody P.
  Eigen::MatrixXd MassMatrix(const Model<double>& model, const Eigen::VectorXd& q) {
    const int n = model.num_joint_dofs();
    SimTK::Vector& sq = state_.updQ();
    for (int k = 0; k < 4; ++k) sq[k] = q[3 + k];
    for (int k = 0; k < 3; ++k) sq[4 + k] = q[k];
    for (int k = 0; k < n; ++k) sq[7 + k] = q[7 + k];
    system_.realize(state_, SimTK::Stage::Position);
    SimTK::Matrix Ms;
    matter_.calcM(state_, Ms);
    Eigen::MatrixXd M_sb(6 + n, 6 + n);
    for (int r = 0; r < 6 + n; ++r)
      for (int c = 0; c < 6 + n; ++c) M_sb(r, c) = Ms(r, c);
    Eigen::MatrixXd P = Eigen::MatrixXd::Identity(6 + n, 6 + n);
    P.topLeftCorner<6, 6>().setZero();
    P.block<3, 3>(0, 3) = GetRootQuaternion(q).toRotationMatrix();
    P.block<3, 3>(3, 0).setIdentity();
    return P.transpose() * M_sb * P;
  }

  // τ in Acrolab's convention from Simbody's residual forces at (q, v, a) under gravity and the
  // wrenches F_ext_Bo_W.
  Eigen::VectorXd InverseDynamics(const Model<double>& model,
                                  const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& v,
                                  const Eigen::VectorXd& a,
                                  const std::vector<SpatialForce<double>>* F_ext) {
    const int n = model.num_joint_dofs();
    EXPECT_EQ(state_.getNQ(), 7 + n);
    EXPECT_EQ(state_.getNU(), 6 + n);
    // Free mobilizer: q = [quaternion w x y z; p_FM], u = [w_FM_F; v_FM_F] (F = Ground).
    SimTK::Vector& sq = state_.updQ();
    for (int k = 0; k < 4; ++k) sq[k] = q[3 + k];
    for (int k = 0; k < 3; ++k) sq[4 + k] = q[k];
    for (int k = 0; k < n; ++k) sq[7 + k] = q[7 + k];
    const Eigen::Matrix3d R = GetRootQuaternion(q).toRotationMatrix();
    const Eigen::Vector3d w_W = R * v.segment<3>(3);
    SimTK::Vector& su = state_.updU();
    SimTK::Vector udot(6 + n);
    const Eigen::Vector3d wdot_W = R * a.segment<3>(3);  // d/dt(R w_B) = R ẇ_B since ω × ω = 0
    for (int k = 0; k < 3; ++k) {
      su[k] = w_W[k];
      su[3 + k] = v[k];
      udot[k] = wdot_W[k];
      udot[3 + k] = a[k];
    }
    for (int k = 0; k < n; ++k) {
      su[6 + k] = v[6 + k];
      udot[6 + k] = a[6 + k];
    }
    system_.realize(state_, SimTK::Stage::Velocity);
    // Gravity on every massive body at its centre of mass, plus the applied wrenches, as spatial
    // forces about the body origin in Ground.
    SimTK::Vector_<SimTK::SpatialVec> body_forces(
        matter_.getNumBodies(), SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0)));
    const SimTK::Vec3 g = ToSimTK(model.gravity_W());
    for (int i = 0; i < model.num_segments(); ++i) {
      const Segment<double>& s = model.segment(i);
      const SimTK::MobilizedBody& mb = bodies_[static_cast<size_t>(i)];
      const SimTK::Vec3 c_G = mb.getBodyRotation(state_) * ToSimTK(s.p_BoBcm_B);
      SimTK::SpatialVec f(c_G % (s.mass * g), s.mass * g);
      if (F_ext != nullptr) {
        const SpatialForce<double>& F = (*F_ext)[static_cast<size_t>(i)];
        f += SimTK::SpatialVec(ToSimTK(F.rotational()), ToSimTK(F.translational()));
      }
      body_forces[mb.getMobilizedBodyIndex()] += f;
    }
    SimTK::Vector residual;
    matter_.calcResidualForceIgnoringConstraints(
        state_, SimTK::Vector(), body_forces, udot, residual);
    Eigen::VectorXd tau(6 + n);
    tau.head<3>() = Eigen::Vector3d(residual[3], residual[4], residual[5]);
    // The moment is the generalised force of w_WB_W in Simbody and of w_WB_B here: τ_B = Rᵀ τ_W.
    tau.segment<3>(3) = R.transpose() * Eigen::Vector3d(residual[0], residual[1], residual[2]);
    for (int k = 0; k < n; ++k) tau[6 + k] = residual[6 + k];
    return tau;
  }

 private:
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  std::vector<SimTK::MobilizedBody> bodies_;
  SimTK::State state_;
};

struct Agreement {
  double root = 0.0;
  double joints = 0.0;
};

// Worst relative disagreement of the root wrench (6) and of the joint torques over random states.
Agreement Compare(const Model<double>& model,
                  std::mt19937& rng,
                  int num_states,
                  bool with_wrenches) {
  SimbodyModel oracle(model);
  Workspace<double> ws(model);
  Agreement worst;
  for (int trial = 0; trial < num_states; ++trial) {
    const Eigen::VectorXd q = testing::RandomConfiguration(model, rng);
    const Eigen::VectorXd v = testing::RandomVelocity(model, rng, 4.0);
    const Eigen::VectorXd a = testing::RandomVelocity(model, rng, 20.0);
    std::vector<SpatialForce<double>> F(static_cast<size_t>(model.num_segments()));
    for (auto& f : F)
      f = SpatialForce<double>(testing::RandomVector(rng, 50.0), testing::RandomVector(rng, 500.0));
    const std::vector<SpatialForce<double>>* F_ext = with_wrenches ? &F : nullptr;
    const Eigen::VectorXd mine = CalcInverseDynamics(model, ws, q, v, a, F_ext);
    const Eigen::VectorXd theirs = oracle.InverseDynamics(model, q, v, a, F_ext);
    worst.root =
        std::max(worst.root, (mine.head<6>() - theirs.head<6>()).norm() / theirs.head<6>().norm());
    const int n = model.num_joint_dofs();
    if (n > 0)
      worst.joints =
          std::max(worst.joints, (mine.tail(n) - theirs.tail(n)).norm() / theirs.tail(n).norm());
  }
  return worst;
}

TEST(SimbodyOracleTest, StandardHumanRootWrenchAndJointTorques) {
  std::mt19937 rng(2026);
  const Agreement a = Compare(testing::MakeStandardHuman(), rng, 50, false);
  std::printf(
      "human vs Simbody: root wrench %.3g, joint torques %.3g (relative)\n", a.root, a.joints);
  EXPECT_LE(a.root, 1e-8);
  EXPECT_LE(a.joints, 1e-8);
}

TEST(SimbodyOracleTest, StandardHumanWithAppliedWrenches) {
  std::mt19937 rng(2027);
  const Agreement a = Compare(testing::MakeStandardHuman(), rng, 20, true);
  std::printf(
      "human + wrenches vs Simbody: root wrench %.3g, joint torques %.3g\n", a.root, a.joints);
  EXPECT_LE(a.root, 1e-8);
  EXPECT_LE(a.joints, 1e-8);
}

TEST(SimbodyOracleTest, RandomTreesWithEveryJointSequence) {
  std::mt19937 rng(2028);
  Agreement worst;
  for (int tree = 0; tree < 6; ++tree) {
    const Agreement a = Compare(testing::MakeRandomTree(rng, 20, 4 * tree), rng, 10, tree % 2 == 1);
    worst.root = std::max(worst.root, a.root);
    worst.joints = std::max(worst.joints, a.joints);
  }
  std::printf(
      "random trees vs Simbody: root wrench %.3g, joint torques %.3g\n", worst.root, worst.joints);
  EXPECT_LE(worst.root, 1e-8);
  EXPECT_LE(worst.joints, 1e-8);
}

TEST(SimbodyOracleTest, MassMatrixOfHumanAndRandomTrees) {
  std::mt19937 rng(2029);
  double worst = 0.0;
  for (int m = 0; m < 4; ++m) {
    const Model<double> model =
        m == 0 ? testing::MakeStandardHuman() : testing::MakeRandomTree(rng, 20, 7 * m);
    SimbodyModel oracle(model);
    Workspace<double> ws(model);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd q = testing::RandomConfiguration(model, rng);
      const Eigen::MatrixXd theirs = oracle.MassMatrix(model, q);
      const Eigen::MatrixXd mine = CalcMassMatrix(model, ws, q);
      worst = std::max(worst, (mine - theirs).norm() / theirs.norm());
    }
  }
  std::printf("mass matrices vs Simbody: %.3g (relative, Frobenius)\n", worst);
  EXPECT_LE(worst, 1e-12);
}

#else

TEST(SimbodyOracleTest, StandardHumanRootWrenchAndJointTorques) {
  GTEST_SKIP() << "Simbody not found at configure time (libsimbody-dev): oracle comparison skipped";
}

#endif

}  // namespace
}  // namespace acro::dynamics
