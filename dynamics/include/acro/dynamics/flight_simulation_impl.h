#pragma once

// Template definitions for flight_simulation.h (included at its end).

#include <algorithm>
#include <cmath>

#include "acro/dynamics/flight_simulation.h"

namespace acro::dynamics {
namespace internal {

inline double ToDouble(double x) {
  return x;
}
/// The value part of an automatic-differentiation scalar such as ceres::Jet.
template <typename J>
auto ToDouble(const J& x) -> decltype(static_cast<double>(x.a)) {
  return x.a;
}

}  // namespace internal

template <typename T>
Vector6<T> CalcRootVelocityFromMomentum(const Model<T>& model,
                                        Workspace<T>& ws,
                                        const VectorXcRef<T>& q,
                                        const VectorXcRef<T>& v,
                                        const Vector3<T>& v_WScm_W,
                                        const Vector3<T>& H_Scm_W) {
  ACRO_DEMAND(q.size() == model.nq() && v.size() == model.nv());
  // Momentum of the joint motion alone (root at rest), about Bo in W.
  VectorX<T> v_joints = v;
  v_joints.template head<6>().setZero();
  CalcForwardKinematics(model, ws, q, v_joints);
  const Vector3<T> p_WoScm_W = CalcCenterOfMassPosition(model, ws);
  const Vector3<T>& p_WoBo_W = ws.X_WB[0].translation();
  const SpatialMomentum<T> L_joints = CalcCentroidalMomentum(model, ws);
  // Target momentum about Bo: h_Bo = h_Scm + p_BoScm × l (RBDA ch. 2, spatial momentum), minus the
  // joints' share.
  const Vector3<T> l_target = model.total_mass() * v_WScm_W;
  const Vector3<T> p_BoScm_W = p_WoScm_W - p_WoBo_W;
  const Vector3<T> dh_W = (H_Scm_W + p_BoScm_W.cross(l_target)) -
                          (L_joints.rotational() + p_BoScm_W.cross(L_joints.translational()));
  const Vector3<T> dl_W = l_target - L_joints.translational();
  // The root's spatial velocity ΔV (about Bo in B) adds Ic·ΔV, Ic the whole-body composite inertia.
  const int n = model.num_segments();
  for (int i = 0; i < n; ++i) ws.Ic_Bo_B[static_cast<size_t>(i)] = model.segment(i).M_Bo_B;
  for (int i = n - 1; i > 0; --i) {
    const size_t ui = static_cast<size_t>(i);
    ws.Ic_Bo_B[static_cast<size_t>(model.segment(i).parent)] += ws.X_PB[ui].Apply(ws.Ic_Bo_B[ui]);
  }
  const Matrix3<T>& R = ws.X_WB[0].rotation();
  Vector6<T> rhs;
  rhs << R.transpose() * dh_W, R.transpose() * dl_W;
  const Vector6<T> dV = ws.Ic_Bo_B[0].ToMatrix().ldlt().solve(rhs);
  Vector6<T> v_root;
  v_root << R * dV.template tail<3>(), dV.template head<3>();
  return v_root;
}

namespace internal {

// The root's state [q_root (7); v_root (6)] integrated under gravity alone with the joints
// prescribed: its derivative, one RK4 step, and the samples kept.
template <typename T>
class FlightIntegrator {
 public:
  using State = Eigen::Matrix<T, 13, 1>;

  FlightIntegrator(const Model<T>& model,
                   const JointTrajectory<T>& joints,
                   FlightSimulationResult<T>* result)
      : model_(model),
        joints_(joints),
        result_(result),
        ws_(model),
        nj_(model.num_joint_dofs()),
        q_(MakeNeutralConfiguration(model)),
        v_(VectorX<T>::Zero(model.nv())),
        a_(VectorX<T>::Zero(model.nv())) {}

  // One classical RK4 step (Hairer, Nørsett & Wanner 1993, §II.1), then the quaternion is
  // projected back on the unit sphere.
  void Rk4(double t, const State& y, double h, State& out) {
    const T th(h);
    Derivative(t, y, k1_);
    tmp_ = y + (T(0.5) * th) * k1_;
    Derivative(t + 0.5 * h, tmp_, k2_);
    tmp_ = y + (T(0.5) * th) * k2_;
    Derivative(t + 0.5 * h, tmp_, k3_);
    tmp_ = y + th * k3_;
    Derivative(t + h, tmp_, k4_);
    out = y + (th / T(6)) * (k1_ + T(2) * k2_ + T(2) * k3_ + k4_);
    using std::sqrt;
    const T norm = sqrt(out.template segment<4>(3).squaredNorm());
    out.template segment<4>(3) /= norm;
  }

  void Store(double t, const State& y) {
    Load(t, y);
    result_->t.push_back(T(t));
    result_->q.push_back(q_);
    result_->v.push_back(v_);
  }

 private:
  // Loads the root state and the prescribed joints at time t into q, v, a.
  void Load(double t, const State& y) {
    q_.template head<7>() = y.template head<7>();
    v_.template head<6>() = y.template tail<6>();
    joints_(T(t), q_.tail(nj_), v_.tail(nj_), a_.tail(nj_));
  }

  // dy/dt: q̇_root = N(q) v_root (configuration.h), v̇_root from CalcFlightRootAcceleration.
  void Derivative(double t, const State& y, State& dy) {
    Load(t, y);
    CalcFlightRootAcceleration(model_, ws_, q_, v_, a_);
    dy.template head<3>() = y.template segment<3>(7);
    const T half(0.5);
    const T w = y[3], x = y[4], yq = y[5], z = y[6];
    const T wx = y[10], wy = y[11], wz = y[12];
    dy[3] = -half * (x * wx + yq * wy + z * wz);
    dy[4] = half * (w * wx + yq * wz - z * wy);
    dy[5] = half * (w * wy + z * wx - x * wz);
    dy[6] = half * (w * wz + x * wy - yq * wx);
    dy.template tail<6>() = a_.template head<6>();
  }

  const Model<T>& model_;
  const JointTrajectory<T>& joints_;
  FlightSimulationResult<T>* result_;
  Workspace<T> ws_;
  const int nj_;
  VectorX<T> q_, v_, a_;
  State k1_, k2_, k3_, k4_, tmp_;
};

// One adaptive step from (t, y) of at most `step`: step doubling, one step of h against two of
// h/2, RK4's local error then estimated by |y_two − y_full| / 15 (Richardson, HNW §II.4). Returns
// whether it was taken (t, y advanced, h grown when the step was a full one); rejected, h is cut
// — and the simulation ends when it would fall below min_step_s.
template <typename T>
bool AdaptiveStep(FlightIntegrator<T>& integrator,
                  const FlightSimulationOptions& options,
                  double step,
                  double& t,
                  typename FlightIntegrator<T>::State& y,
                  double& h,
                  FlightSimulationSummary& summary) {
  typename FlightIntegrator<T>::State y_full, y_half, y_two;
  integrator.Rk4(t, y, step, y_full);
  integrator.Rk4(t, y, 0.5 * step, y_half);
  integrator.Rk4(t + 0.5 * step, y_half, 0.5 * step, y_two);
  const double err = ToDouble(T((y_two - y_full).cwiseAbs().maxCoeff())) / 15.0;
  const double factor =
      err > 0.0 ? std::clamp(0.9 * std::pow(options.tolerance / err, 0.2), 0.2, 4.0) : 4.0;
  if (err > options.tolerance) {
    ++summary.num_rejected_steps;
    if (step <= options.min_step_s) {
      summary.status = FlightSimulationStatus::kStepTooSmall;
      summary.message = "step fell below min_step_s at t = " + std::to_string(t) + " s";
      summary.final_time_s = t;
      return false;
    }
    h = std::max(step * factor, options.min_step_s);
    return false;
  }
  y = y_two;
  t += step;
  // Only grow h from a full step; a step cut short by an output time keeps the old h.
  if (step >= h * (1.0 - 1e-12)) h = std::min(step * factor, options.max_step_s);
  return true;
}

}  // namespace internal

template <typename T>
FlightSimulationResult<T> SimulateFlight(const Model<T>& model,
                                         const FlightSimulationOptions& options,
                                         const Eigen::Matrix<T, 7, 1>& q_root0,
                                         const Vector6<T>& v_root0,
                                         const JointTrajectory<T>& joints) {
  using State = typename internal::FlightIntegrator<T>::State;
  FlightSimulationResult<T> result;
  FlightSimulationSummary& summary = result.summary;
  if (!options.IsValid(&summary.message)) {
    summary.status = FlightSimulationStatus::kInvalidOptions;
    return result;
  }
  ACRO_DEMAND(static_cast<bool>(joints));
  internal::FlightIntegrator<T> integrator(model, joints, &result);

  State y;
  y << q_root0, v_root0;
  {
    using std::sqrt;
    y.template segment<4>(3) /= sqrt(y.template segment<4>(3).squaredNorm());
  }
  double t = 0.0;
  double h = std::min(options.step_s, options.duration_s);
  double next_output = options.output_interval_s > 0.0 ? options.output_interval_s : 0.0;
  integrator.Store(t, y);
  State y_full;
  // Times closer than this to a target count as reached (rounding of the accumulated t).
  const double time_eps = 1e-12 * std::max(1.0, options.duration_s);
  while (t < options.duration_s - time_eps) {
    if (summary.num_steps >= options.max_steps) {
      summary.status = FlightSimulationStatus::kMaxStepsReached;
      summary.message = "reached max_steps = " + std::to_string(options.max_steps);
      summary.final_time_s = t;
      return result;
    }
    // Do not step past the end or the next output time.
    double step = std::min(h, options.duration_s - t);
    if (options.output_interval_s > 0.0) step = std::min(step, next_output - t);
    if (!options.adaptive) {
      integrator.Rk4(t, y, step, y_full);
      y = y_full;
      t += step;
    } else if (!internal::AdaptiveStep(integrator, options, step, t, y, h, summary)) {
      if (summary.status == FlightSimulationStatus::kStepTooSmall) return result;
      continue;
    }
    ++summary.num_steps;
    if (options.output_interval_s <= 0.0) {
      integrator.Store(t, y);
    } else if (t >= next_output - time_eps || t >= options.duration_s - time_eps) {
      integrator.Store(t, y);
      next_output += options.output_interval_s;
    }
  }
  if (options.output_interval_s > 0.0 && result.t.size() > 0 &&
      internal::ToDouble(result.t.back()) < t - time_eps)
    integrator.Store(t, y);
  summary.status = FlightSimulationStatus::kSuccess;
  summary.final_time_s = t;
  return result;
}

}  // namespace acro::dynamics
