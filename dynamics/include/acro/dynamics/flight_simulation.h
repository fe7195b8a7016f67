#pragma once

// Flight simulation, the "what if" engine: the joint angles follow prescribed trajectories
// q_j(t) (with q̇_j, q̈_j), and the free root moves under gravity alone, so that the whole-body
// linear momentum follows the ballistic parabola and the angular momentum about the centre of
// mass is conserved. The root state (q_root: 7, v_root: 6) is integrated by the classical RK4
// with a fixed step or with an adaptive step (step doubling, Richardson error estimate, Hairer,
// Nørsett & Wanner 1993, §II.4). The quaternion is renormalised after every step.

#include <functional>
#include <string>
#include <vector>

#include "acro/dynamics/inverse_dynamics.h"

namespace acro::dynamics {

/// The prescribed joint motion: at time t (s), writes the joint angles, rates and accelerations
/// (each with model.num_joint_dofs() entries).
template <typename T>
using JointTrajectory = std::function<void(
    const T& t, VectorXRef<T> q_joints, VectorXRef<T> v_joints, VectorXRef<T> a_joints)>;

struct FlightSimulationOptions {
  double duration_s = 1.0;
  /// The step of fixed-step RK4, or the first step tried when adaptive.
  double step_s = 1e-3;
  bool adaptive = false;
  /// Adaptive only: bound on the estimated local error per step, in the max norm of the root state
  /// (positions in m, quaternion components, velocities in m/s and rad/s).
  double tolerance = 1e-10;
  double min_step_s = 1e-9;
  double max_step_s = 0.05;
  /// Interval between stored samples; 0 stores every step. The final time is always stored.
  double output_interval_s = 0.0;
  int max_steps = 10'000'000;

  bool IsValid(std::string* why) const;
};

enum class FlightSimulationStatus { kSuccess, kInvalidOptions, kStepTooSmall, kMaxStepsReached };

struct FlightSimulationSummary {
  FlightSimulationStatus status = FlightSimulationStatus::kInvalidOptions;
  std::string message;
  int num_steps = 0;
  int num_rejected_steps = 0;
  double final_time_s = 0.0;
  std::string BriefReport() const;
};

template <typename T>
struct FlightSimulationResult {
  std::vector<T> t;           ///< sample times (s)
  std::vector<VectorX<T>> q;  ///< full configurations at the sample times (nq)
  std::vector<VectorX<T>> v;  ///< full velocities (nv)
  FlightSimulationSummary summary;
};

/// Simulates flight from the root state (q_root0: p_WoBo_W and quaternion w x y z; v_root0:
/// v_WBo_W and w_WB_B) at t = 0 with the joints following `joints`.
template <typename T>
FlightSimulationResult<T> SimulateFlight(const Model<T>& model,
                                         const FlightSimulationOptions& options,
                                         const Eigen::Matrix<T, 7, 1>& q_root0,
                                         const Vector6<T>& v_root0,
                                         const JointTrajectory<T>& joints);

/// The root velocity v_root (v_WBo_W, w_WB_B) for which the whole body, at configuration q with
/// the joint rates in v[6:], has centre-of-mass velocity v_WScm_W and angular momentum about its
/// centre of mass H_Scm_W: the take-off conditions of a skill.
template <typename T>
Vector6<T> CalcRootVelocityFromMomentum(const Model<T>& model,
                                        Workspace<T>& ws,
                                        const VectorXcRef<T>& q,
                                        const VectorXcRef<T>& v,
                                        const Vector3<T>& v_WScm_W,
                                        const Vector3<T>& H_Scm_W);

extern template FlightSimulationResult<double> SimulateFlight<double>(
    const Model<double>&,
    const FlightSimulationOptions&,
    const Eigen::Matrix<double, 7, 1>&,
    const Vector6<double>&,
    const JointTrajectory<double>&);
extern template Vector6<double> CalcRootVelocityFromMomentum<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Vector3<double>&,
    const Vector3<double>&);

}  // namespace acro::dynamics

#include "acro/dynamics/flight_simulation_impl.h"
