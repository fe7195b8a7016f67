#pragma once

// The rotation of a free flight from its conserved angular momentum, for the many flights a
// shooting method simulates. In flight the only external force is gravity, which acts at the
// centre of mass Scm, so the angular momentum about Scm, H_Scm_W, is constant. With the root
// frame B at rest, the joints' motion alone has a momentum about Scm, H_j; turning B at ω adds
// I_Scm ω, I_Scm the whole body's inertia about Scm (the root's linear velocity adds nothing
// about Scm). So, in B,
//   ω_WB_B = I_Scm_B⁻¹ (R_WBᵀ H_Scm_W − H_j_B),                         (1)
// where I_Scm_B and H_j_B depend on the joint angles and rates only: for prescribed joints they
// are functions of time, sampled once per joint motion (SampleJointMotion) and reused for any
// momentum and initial orientation; the orientation then follows q̇ = ½ q ⊗ (0, ω_B), integrated
// by RK4 (SimulateFlightRotation). This is the same motion as SimulateFlight's Newton–Euler root
// accelerations (flight_simulation.h) up to the integration error (tests/dynamics/
// flight_rotation_test.cc holds them together), at a fraction of the cost: two joint-motion
// samples per step instead of four inverse dynamics, and none for a new momentum.

#include <vector>

#include <Eigen/Geometry>

#include "acro/dynamics/flight_simulation.h"

namespace acro::dynamics {

/// I_Scm_B⁻¹ and H_j_B of (1) at the times k·step_s/2, k = 0 … 2·num_steps: the step's ends and
/// middles, where RK4 evaluates.
struct JointMotionSamples {
  double step_s = 0.0;
  int num_steps = 0;
  std::vector<Matrix3<double>> I_Scm_B_inverse;
  std::vector<Vector3<double>> H_joints_Scm_B;
};

/// Samples the joint motion `joints` over num_steps fixed steps of duration_s / num_steps.
JointMotionSamples SampleJointMotion(const Model<double>& model,
                                     double duration_s,
                                     int num_steps,
                                     const JointTrajectory<double>& joints);

/// The root orientation q_WB at the times k·step_s, k = 0 … num_steps, from q_WB0 at t = 0 and the
/// constant angular momentum about the centre of mass H_Scm_W: classical RK4 on (1), the
/// quaternion renormalised after every step as in SimulateFlight.
std::vector<Eigen::Quaterniond> SimulateFlightRotation(const JointMotionSamples& samples,
                                                       const Eigen::Quaterniond& q_WB0,
                                                       const Vector3<double>& H_Scm_W);

}  // namespace acro::dynamics
