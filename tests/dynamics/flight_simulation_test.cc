#include "acro/dynamics/flight_simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "standard_human_fixture.h"
#include "test_models.h"

namespace acro::dynamics {
namespace {

constexpr double kTuckTime = 1.5;  // s: tuck and open again

// A tuck and open over 1.5 s: s(t) = (1 − cos 2πt/T)/2 goes 0 → 1 → 0 and every moving joint
// follows q_j = q_tuck,j · s(t). The arms move asymmetrically (the right one further and sideways)
// so that the motion is fully three-dimensional.
JointTrajectory<double> TuckAndOpen(const Model<double>& model) {
  Eigen::VectorXd tuck = Eigen::VectorXd::Zero(model.num_joint_dofs());
  auto set = [&](const std::string& segment, int axis, double angle) {
    tuck[model.segment(model.FindSegment(segment)).v_start - 6 + axis] = angle;
  };
  set("thorax", 0, 0.5);  // lumbar flexion
  set("head", 0, 0.3);
  for (const std::string s : {"r_", "l_"}) {
    set(s + "thigh", 0, -2.2);  // hip flexion (thigh forward: negative about y for a z-down thigh)
    set(s + "shank", 0, 2.3);   // knee flexion
    set(s + "foot", 0, 0.3);
    set(s + "forearm", 0, -1.5);
  }
  set("r_upper_arm", 0, -1.4);
  set("r_upper_arm", 1, -0.6);
  set("r_upper_arm", 2, 0.4);
  set("l_upper_arm", 0, -0.9);
  set("r_hand", 1, 0.3);
  return [tuck](const double& t, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
    const double w = 2.0 * M_PI / kTuckTime;
    q = tuck * (0.5 * (1.0 - std::cos(w * t)));
    v = tuck * (0.5 * w * std::sin(w * t));
    a = tuck * (0.5 * w * w * std::cos(w * t));
  };
}

struct MomentumErrors {
  double linear = 0.0;   // max_t |L(t) − m(v0 + g t)| / max_t |m(v0 + g t)|
  double angular = 0.0;  // max_t |H(t) − H(0)| / |H(0)|
  double com = 0.0;      // max_t |p(t) − (p0 + v0 t + ½ g t²)| / max_t |v0 t + ½ g t²|
};

// Momentum and centre of mass along a simulated flight against the ballistic closed forms.
MomentumErrors CheckMomentum(const Model<double>& model, const FlightSimulationResult<double>& r) {
  Workspace<double> ws(model);
  CalcForwardKinematics(model, ws, r.q[0], r.v[0]);
  const SpatialMomentum<double> L0 = CalcCentroidalMomentum(model, ws);
  const Eigen::Vector3d p0 = CalcCenterOfMassPosition(model, ws);
  const Eigen::Vector3d v0 = L0.translational() / model.total_mass();
  const Eigen::Vector3d g = model.gravity_W();
  MomentumErrors e;
  double L_scale = 0.0, p_scale = 0.0;
  for (size_t k = 0; k < r.t.size(); ++k) {
    const double t = r.t[k];
    CalcForwardKinematics(model, ws, r.q[k], r.v[k]);
    const SpatialMomentum<double> L = CalcCentroidalMomentum(model, ws);
    const Eigen::Vector3d L_exact = model.total_mass() * (v0 + g * t);
    const Eigen::Vector3d dp_exact = v0 * t + 0.5 * g * t * t;
    L_scale = std::max(L_scale, L_exact.norm());
    p_scale = std::max(p_scale, dp_exact.norm());
    e.linear = std::max(e.linear, (L.translational() - L_exact).norm());
    e.angular = std::max(e.angular, (L.rotational() - L0.rotational()).norm());
    e.com = std::max(e.com, (CalcCenterOfMassPosition(model, ws) - p0 - dp_exact).norm());
  }
  e.linear /= L_scale;
  e.angular /= L0.rotational().norm();
  e.com /= p_scale;
  return e;
}

// Take-off: centre of mass rising at 7 m/s and drifting forward, angular momentum mostly about
// the somersault axis with some tilt, with the joints at their t = 0 state.
Vector6<double> TakeOff(const Model<double>& model,
                        const Eigen::Matrix<double, 7, 1>& q_root,
                        const JointTrajectory<double>& joints,
                        const Eigen::Vector3d& v_com,
                        const Eigen::Vector3d& H) {
  Workspace<double> ws(model);
  Eigen::VectorXd q = MakeNeutralConfiguration(model);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv()), a = v;
  q.head<7>() = q_root;
  const int n = model.num_joint_dofs();
  joints(0.0, q.tail(n), v.tail(n), a.tail(n));
  return CalcRootVelocityFromMomentum(model, ws, q, v, v_com, H);
}

class FlightSimulationTest : public ::testing::Test {
 protected:
  Model<double> human_ = testing::MakeStandardHuman();
  Eigen::Matrix<double, 7, 1> q_root_ =
      (Eigen::Matrix<double, 7, 1>() << 0, 0, 1.1, 1, 0, 0, 0).finished();
};

TEST_F(FlightSimulationTest, TuckAndOpenConservesMomentum) {
  const JointTrajectory<double> joints = TuckAndOpen(human_);
  const Vector6<double> v_root = TakeOff(
      human_, q_root_, joints, Eigen::Vector3d(0.4, 0.05, 7.0), Eigen::Vector3d(-3.0, 45.0, 6.0));
  for (const bool adaptive : {false, true}) {
    FlightSimulationOptions options;
    options.duration_s = kTuckTime;
    options.step_s = 2.5e-4;
    options.adaptive = adaptive;
    options.tolerance = 1e-12;
    options.output_interval_s = adaptive ? 0.01 : 0.0;
    const FlightSimulationResult<double> r =
        SimulateFlight(human_, options, q_root_, v_root, joints);
    ASSERT_EQ(r.summary.status, FlightSimulationStatus::kSuccess) << r.summary.BriefReport();
    EXPECT_NEAR(r.t.back(), kTuckTime, 1e-12);
    const MomentumErrors e = CheckMomentum(human_, r);
    std::printf("tuck and open (%s, %d steps): linear %.3g, angular %.3g, COM %.3g (relative)\n",
                adaptive ? "adaptive" : "fixed 0.25 ms",
                r.summary.num_steps,
                e.linear,
                e.angular,
                e.com);
    EXPECT_LE(e.linear, 1e-8);
    EXPECT_LE(e.angular, 1e-8);
    EXPECT_LE(e.com, 1e-8);
    // The joints did move: half-way they are tucked.
    const size_t mid = r.t.size() / 2;
    EXPECT_GT(std::abs(r.q[mid][human_.segment(human_.FindSegment("r_shank")).q_start]), 2.0);
  }
}

// With the joints fixed the body is rigid; spun about the left–right axis (a principal axis of the
// left–right symmetric pose), it keeps its somersault rate and turns at ω t (Euler's equations
// with ω along a principal axis: ω̇ = 0).
TEST_F(FlightSimulationTest, FixedPoseKeepsSomersaultRate) {
  // The two hip-flexion angles in joint order, to keep the pose left–right symmetric.
  const int r_hip = human_.segment(human_.FindSegment("r_thigh")).v_start - 6;
  const int l_hip = human_.segment(human_.FindSegment("l_thigh")).v_start - 6;
  const JointTrajectory<double> pose =
      [r_hip, l_hip](
          const double&, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
        q.setZero();
        q[r_hip] = -1.4;
        q[l_hip] = -1.4;
        v.setZero();
        a.setZero();
      };
  const double rate = 6.0;  // rad/s about y
  Vector6<double> v_root;
  v_root << 0.5, 0.0, 6.0, 0.0, rate, 0.0;
  // The root's linear velocity must be that of a rigid body spinning about its centre of mass;
  // take the centre-of-mass velocity (0.5, 0, 6) and the angular momentum I·ω from the pose.
  Workspace<double> ws(human_);
  Eigen::VectorXd q = MakeNeutralConfiguration(human_);
  q.head<7>() = q_root_;
  q[7 + r_hip] = -1.4;
  q[7 + l_hip] = -1.4;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(human_.nv());
  v.segment<3>(3) = Eigen::Vector3d(0.0, rate, 0.0);
  CalcForwardKinematics(human_, ws, q, v);
  const Eigen::Vector3d H = CalcCentroidalMomentum(human_, ws).rotational();
  v_root = CalcRootVelocityFromMomentum(human_, ws, q, v, Eigen::Vector3d(0.5, 0.0, 6.0), H);
  EXPECT_LE((v_root.tail<3>() - Eigen::Vector3d(0.0, rate, 0.0)).norm(), 1e-12 * rate);

  FlightSimulationOptions options;
  options.duration_s = 1.2;
  options.step_s = 1e-3;
  const FlightSimulationResult<double> r = SimulateFlight(human_, options, q_root_, v_root, pose);
  ASSERT_EQ(r.summary.status, FlightSimulationStatus::kSuccess);
  double rate_error = 0.0, angle_error = 0.0;
  const Eigen::Quaterniond q0 = GetRootQuaternion(r.q[0]);
  for (size_t k = 0; k < r.t.size(); ++k) {
    rate_error =
        std::max(rate_error, (r.v[k].segment<3>(3) - Eigen::Vector3d(0, rate, 0)).norm() / rate);
    const Eigen::Quaterniond expected =
        q0 * Eigen::Quaterniond(Eigen::AngleAxisd(rate * r.t[k], Eigen::Vector3d::UnitY()));
    angle_error = std::max(angle_error, expected.angularDistance(GetRootQuaternion(r.q[k])));
  }
  std::printf(
      "fixed pike: somersault rate error %.3g (relative), angle error %.3g rad after %.2f turns\n",
      rate_error,
      angle_error,
      rate * options.duration_s / (2 * M_PI));
  // ω stays exactly on the axis up to rounding of the solve (a few hundred ulps of ω).
  EXPECT_LE(rate_error, 1e-12);
  EXPECT_LE(angle_error, 1e-10);
  EXPECT_LE(CheckMomentum(human_, r).angular, 1e-10);
}

// A straight body with angular momentum tilted from the somersault axis twists while it
// somersaults (torque-free precession); three somersaults and two twists pass without any
// singularity: the quaternion stays unit, momentum stays conserved, the state stays finite.
TEST_F(FlightSimulationTest, ThreeSomersaultsTwoTwistsWithoutSingularity) {
  const JointTrajectory<double> straight =
      [](const double&, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
        q.setZero();
        v.setZero();
        a.setZero();
      };
  Vector6<double> v_root;
  Workspace<double> ws(human_);
  Eigen::VectorXd q = MakeNeutralConfiguration(human_);
  q.head<7>() = q_root_;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(human_.nv());
  v.segment<3>(3) = Eigen::Vector3d(0.0, 14.0, 7.0);  // somersault about y, twist about z
  CalcForwardKinematics(human_, ws, q, v);
  const Eigen::Vector3d H = CalcCentroidalMomentum(human_, ws).rotational();
  v_root = CalcRootVelocityFromMomentum(human_, ws, q, v, Eigen::Vector3d(0.0, 0.0, 7.5), H);

  FlightSimulationOptions options;
  options.duration_s = 1.55;
  options.adaptive = true;
  options.tolerance = 1e-12;
  options.step_s = 1e-3;
  options.output_interval_s = 0.002;
  const FlightSimulationResult<double> r =
      SimulateFlight(human_, options, q_root_, v_root, straight);
  ASSERT_EQ(r.summary.status, FlightSimulationStatus::kSuccess) << r.summary.BriefReport();

  // Somersault: the turning of the body's long axis about the (fixed) angular momentum, unwrapped.
  // Twist: the body's rotation about its own long axis, ∫ ω_z dt (trapezoidal on the samples).
  const Eigen::Vector3d h = H.normalized();
  const Eigen::Vector3d e1 = h.unitOrthogonal(), e2 = h.cross(e1);
  double somersault = 0.0, twist = 0.0, prev_angle = 0.0, norm_error = 0.0;
  for (size_t k = 0; k < r.t.size(); ++k) {
    const Eigen::Quaterniond quat = GetRootQuaternion(r.q[k]);
    ASSERT_TRUE(r.q[k].allFinite() && r.v[k].allFinite());
    norm_error = std::max(norm_error, std::abs(quat.norm() - 1.0));
    const Eigen::Vector3d z = quat.toRotationMatrix().col(2);
    const double angle = std::atan2(z.dot(e2), z.dot(e1));
    if (k > 0) {
      somersault += std::remainder(angle - prev_angle, 2 * M_PI);
      twist += 0.5 * (r.v[k][5] + r.v[k - 1][5]) * (r.t[k] - r.t[k - 1]);
    }
    prev_angle = angle;
  }
  const MomentumErrors e = CheckMomentum(human_, r);
  std::printf(
      "twisting somersault: %.2f somersaults, %.2f twists, |q|-1 ≤ %.2g, angular momentum %.3g\n",
      std::abs(somersault) / (2 * M_PI),
      std::abs(twist) / (2 * M_PI),
      norm_error,
      e.angular);
  EXPECT_GE(std::abs(somersault), 3 * 2 * M_PI);
  EXPECT_GE(std::abs(twist), 2 * 2 * M_PI);
  EXPECT_LE(norm_error, 1e-14);
  EXPECT_LE(e.angular, 1e-8);
  EXPECT_LE(e.linear, 1e-8);
}

TEST_F(FlightSimulationTest, InvalidOptionsAreReported) {
  FlightSimulationOptions options;
  options.step_s = -1.0;
  std::string why;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_NE(why.find("step_s"), std::string::npos);
  Vector6<double> v_root = Vector6<double>::Zero();
  const JointTrajectory<double> still =
      [](const double&, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
        q.setZero();
        v.setZero();
        a.setZero();
      };
  const FlightSimulationResult<double> r = SimulateFlight(human_, options, q_root_, v_root, still);
  EXPECT_EQ(r.summary.status, FlightSimulationStatus::kInvalidOptions);
  EXPECT_NE(r.summary.BriefReport().find("step_s"), std::string::npos);
  EXPECT_TRUE(r.t.empty());
}

// The adaptive integrator reaches the fixed-step answer with fewer steps on a smooth flight.
TEST_F(FlightSimulationTest, AdaptiveMatchesFineFixedStep) {
  const JointTrajectory<double> joints = TuckAndOpen(human_);
  const Vector6<double> v_root = TakeOff(
      human_, q_root_, joints, Eigen::Vector3d(0.0, 0.0, 7.0), Eigen::Vector3d(0.0, 50.0, 0.0));
  FlightSimulationOptions fixed;
  fixed.duration_s = kTuckTime;
  fixed.step_s = 1e-4;
  FlightSimulationOptions adaptive = fixed;
  adaptive.adaptive = true;
  adaptive.step_s = 1e-2;
  adaptive.tolerance = 1e-11;
  const FlightSimulationResult<double> a =
      SimulateFlight(human_, adaptive, q_root_, v_root, joints);
  const FlightSimulationResult<double> f = SimulateFlight(human_, fixed, q_root_, v_root, joints);
  ASSERT_EQ(a.summary.status, FlightSimulationStatus::kSuccess);
  EXPECT_LT(a.summary.num_steps, f.summary.num_steps / 5);
  // Both within ~1e-9 of the exact flow (RK4 global error C·h⁴ with h = 1e-4; tolerance 1e-11
  // per step): 1e-8 on positions and rates of O(1–10).
  EXPECT_LE((a.q.back().head<7>() - f.q.back().head<7>()).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LE((a.v.back().head<6>() - f.v.back().head<6>()).cwiseAbs().maxCoeff(), 1e-7);
}

}  // namespace
}  // namespace acro::dynamics
