#include "acro/dynamics/flight_rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "standard_human_fixture.h"
#include "test_models.h"

namespace acro::dynamics {
namespace {

constexpr double kFlightTime = 1.5;  // s

// A three-dimensional joint motion: the body tucks and opens once over the flight while the arms
// swing asymmetrically (the right one further and sideways) and the hips bend sideways, the kind
// of motion that starts a twist in the air.
JointTrajectory<double> TuckOpenAndTwistAction(const Model<double>& model) {
  Eigen::VectorXd tuck = Eigen::VectorXd::Zero(model.num_joint_dofs());
  Eigen::VectorXd swing = tuck;
  auto index = [&](const std::string& segment, int axis) {
    return model.segment(model.FindSegment(segment)).v_start - 6 + axis;
  };
  tuck[index("thorax", 0)] = 0.5;
  for (const std::string s : {"r_", "l_"}) {
    tuck[index(s + "thigh", 0)] = -2.2;
    tuck[index(s + "shank", 0)] = 2.3;
    tuck[index(s + "forearm", 0)] = -1.5;
    swing[index(s + "thigh", 1)] = 0.3;
  }
  swing[index("r_upper_arm", 0)] = -1.4;
  swing[index("r_upper_arm", 1)] = -0.6;
  swing[index("l_upper_arm", 0)] = -0.9;
  return [tuck, swing](
             const double& t, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
    const double w = 2.0 * M_PI / kFlightTime, u = 3.0 * w;
    q = tuck * (0.5 * (1.0 - std::cos(w * t))) + swing * std::sin(u * t);
    v = tuck * (0.5 * w * std::sin(w * t)) + swing * (u * std::cos(u * t));
    a = tuck * (0.5 * w * w * std::cos(w * t)) - swing * (u * u * std::sin(u * t));
  };
}

class FlightRotationTest : public ::testing::Test {
 protected:
  // The largest angle (rad) between SimulateFlightRotation's orientations with n steps and
  // SimulateFlight's (Newton–Euler root accelerations, fixed-step RK4 at 0.1 ms) at the same
  // times, for the angular momentum H about the centre of mass.
  double LargestDifference(int n, const Eigen::Vector3d& H) {
    const JointTrajectory<double> joints = TuckOpenAndTwistAction(human_);
    const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
    // The reference: the Newton–Euler flight from the root velocity that gives H.
    Workspace<double> ws(human_);
    Eigen::VectorXd q = MakeNeutralConfiguration(human_);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(human_.nv()), a = v;
    q.head<7>() << 0, 0, 1.1, q0.w(), q0.x(), q0.y(), q0.z();
    const int nj = human_.num_joint_dofs();
    joints(0.0, q.tail(nj), v.tail(nj), a.tail(nj));
    const Vector6<double> v_root =
        CalcRootVelocityFromMomentum(human_, ws, q, v, Eigen::Vector3d(0.2, 0.0, 7.0), H);
    FlightSimulationOptions options;
    options.duration_s = kFlightTime;
    options.step_s = kFlightTime / 15000;
    options.output_interval_s = kFlightTime / n;
    const FlightSimulationResult<double> ne =
        SimulateFlight<double>(human_, options, q.head<7>(), v_root, joints);
    EXPECT_EQ(ne.summary.status, FlightSimulationStatus::kSuccess);

    const JointMotionSamples samples = SampleJointMotion(human_, kFlightTime, n, joints);
    const std::vector<Eigen::Quaterniond> rotation = SimulateFlightRotation(samples, q0, H);
    EXPECT_EQ(rotation.size(), size_t(n) + 1);
    EXPECT_EQ(ne.t.size(), size_t(n) + 1);
    double largest = 0.0;
    for (size_t k = 0; k < std::min(rotation.size(), ne.q.size()); ++k)
      largest = std::max(largest, rotation[k].angularDistance(GetRootQuaternion(ne.q[k])));
    return largest;
  }

  Model<double> human_ = testing::MakeStandardHuman();
};

// Against the Newton–Euler flight, a second algorithm: a double somersault with a tilted momentum
// (the contact twist of a full) while the body tucks, opens and swings its arms. The two agree
// to RK4's error, which falls as h⁴: halving the step divides the difference by about 16.
TEST_F(FlightRotationTest, AgreesWithTheNewtonEulerFlight) {
  const Eigen::Vector3d H(-3.0, 45.0, 9.0);
  const double coarse = LargestDifference(375, H);  // 4 ms
  const double fine = LargestDifference(750, H);    // 2 ms, the shooting's step
  std::printf("largest orientation difference: %.3g rad at 4 ms, %.3g rad at 2 ms (ratio %.1f)\n",
              coarse,
              fine,
              coarse / fine);
  // 2 ms over 1.5 s of a 45 kg·m²/s flight with these joint rates: RK4 leaves about 2e-7 rad.
  EXPECT_LE(fine, 1e-6);           // measured 1.8e-7
  EXPECT_GE(coarse / fine, 12.0);  // fourth order (16), less the reference's own error
  EXPECT_LE(coarse / fine, 20.0);
}

// A rigid body (the joints held still) in free rotation keeps its angular momentum in W:
// I_Scm_W ω_W = H at every step, ω_W read off the orientations by central differences (a check
// of (1) that does not use it); with no momentum the body does not turn.
TEST_F(FlightRotationTest, ARigidBodyKeepsItsMomentum) {
  const JointTrajectory<double> still =
      [](const double&, VectorXRef<double> q, VectorXRef<double> v, VectorXRef<double> a) {
        q.setZero();
        v.setZero();
        a.setZero();
      };
  const JointMotionSamples samples = SampleJointMotion(human_, 1.0, 500, still);
  const Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d H(2.0, 40.0, 5.0);
  const std::vector<Eigen::Quaterniond> turning = SimulateFlightRotation(samples, q0, H);
  const std::vector<Eigen::Quaterniond> none =
      SimulateFlightRotation(samples, q0, Eigen::Vector3d::Zero());
  double largest = 0.0;
  for (size_t k = 1; k + 1 < turning.size(); ++k) {
    const Eigen::Matrix3d R = turning[k].toRotationMatrix();
    const Eigen::Matrix3d I_W = R * samples.I_Scm_B_inverse[2 * k].inverse() * R.transpose();
    const Eigen::AngleAxisd d(turning[k + 1] * turning[k - 1].inverse());
    const Eigen::Vector3d w_W = d.axis() * d.angle() / (2 * samples.step_s);
    largest = std::max(largest, (I_W * w_W - H).norm() / H.norm());
    EXPECT_LE(none[k].angularDistance(q0), 1e-15) << k;
  }
  std::printf("rigid body: |I ω − H| / |H| ≤ %.3g (central differences of 2 ms)\n", largest);
  EXPECT_LE(largest, 1e-4);  // the central difference's own error, (ωh)²/6 ≈ 1e-4 at 2 ms
  EXPECT_GT(turning.back().angularDistance(q0), 1.0);
}

}  // namespace
}  // namespace acro::dynamics
