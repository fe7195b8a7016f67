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

template <typename T>
FlightSimulationResult<T> SimulateFlight(const Model<T>& model,
                                         const FlightSimulationOptions& options,
                                         const Eigen::Matrix<T, 7, 1>& q_root0,
                                         const Vector6<T>& v_root0,
                                         const JointTrajectory<T>& joints) {
  using State = Eigen::Matrix<T, 13, 1>;  // [q_root (7); v_root (6)]
  FlightSimulationResult<T> result;
  FlightSimulationSummary& summary = result.summary;
  if (!options.IsValid(&summary.message)) {
    summary.status = FlightSimulationStatus::kInvalidOptions;
    return result;
  }
  ACRO_DEMAND(static_cast<bool>(joints));

  Workspace<T> ws(model);
  const int nj = model.num_joint_dofs();
  VectorX<T> q = MakeNeutralConfiguration(model);
  VectorX<T> v = VectorX<T>::Zero(model.nv());
  VectorX<T> a = VectorX<T>::Zero(model.nv());

  // Loads the root state and the prescribed joints at time t into q, v, a.
  auto load = [&](double t, const State& y) {
    q.template head<7>() = y.template head<7>();
    v.template head<6>() = y.template tail<6>();
    joints(T(t), q.tail(nj), v.tail(nj), a.tail(nj));
  };
  // dy/dt: q̇_root = N(q) v_root (configuration.h), v̇_root from CalcFlightRootAcceleration.
  auto derivative = [&](double t, const State& y, State& dy) {
    load(t, y);
    CalcFlightRootAcceleration(model, ws, q, v, a);
    dy.template head<3>() = y.template segment<3>(7);
    const T half(0.5);
    const T w = y[3], x = y[4], yq = y[5], z = y[6];
    const T wx = y[10], wy = y[11], wz = y[12];
    dy[3] = -half * (x * wx + yq * wy + z * wz);
    dy[4] = half * (w * wx + yq * wz - z * wy);
    dy[5] = half * (w * wy + z * wx - x * wz);
    dy[6] = half * (w * wz + x * wy - yq * wx);
    dy.template tail<6>() = a.template head<6>();
  };
  // One classical RK4 step (Hairer, Nørsett & Wanner 1993, §II.1), then the quaternion
  // is projected back on the unit sphere.
  State k1, k2, k3, k4, tmp;
  auto rk4 = [&](double t, const State& y, double h, State& out) {
    const T th(h);
    derivative(t, y, k1);
    tmp = y + (T(0.5) * th) * k1;
    derivative(t + 0.5 * h, tmp, k2);
    tmp = y + (T(0.5) * th) * k2;
    derivative(t + 0.5 * h, tmp, k3);
    tmp = y + th * k3;
    derivative(t + h, tmp, k4);
    out = y + (th / T(6)) * (k1 + T(2) * k2 + T(2) * k3 + k4);
    using std::sqrt;
    const T norm = sqrt(out.template segment<4>(3).squaredNorm());
    out.template segment<4>(3) /= norm;
  };
  auto store = [&](double t, const State& y) {
    load(t, y);
    result.t.push_back(T(t));
    result.q.push_back(q);
    result.v.push_back(v);
  };

  State y;
  y << q_root0, v_root0;
  {
    using std::sqrt;
    y.template segment<4>(3) /= sqrt(y.template segment<4>(3).squaredNorm());
  }
  double t = 0.0;
  double h = std::min(options.step_s, options.duration_s);
  double next_output = options.output_interval_s > 0.0 ? options.output_interval_s : 0.0;
  store(t, y);
  State y_full, y_half, y_two;
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
      rk4(t, y, step, y_full);
      y = y_full;
      t += step;
    } else {
      // Step doubling: one step of h against two of h/2; RK4's local error is then estimated by
      // |y_two − y_full| / 15 (Richardson, HNW §II.4).
      rk4(t, y, step, y_full);
      rk4(t, y, 0.5 * step, y_half);
      rk4(t + 0.5 * step, y_half, 0.5 * step, y_two);
      const double err = internal::ToDouble(T((y_two - y_full).cwiseAbs().maxCoeff())) / 15.0;
      const double factor =
          err > 0.0 ? std::clamp(0.9 * std::pow(options.tolerance / err, 0.2), 0.2, 4.0) : 4.0;
      if (err > options.tolerance) {
        ++summary.num_rejected_steps;
        if (step <= options.min_step_s) {
          summary.status = FlightSimulationStatus::kStepTooSmall;
          summary.message = "step fell below min_step_s at t = " + std::to_string(t) + " s";
          summary.final_time_s = t;
          return result;
        }
        h = std::max(step * factor, options.min_step_s);
        continue;
      }
      y = y_two;
      t += step;
      // Only grow h from a full step; a step cut short by an output time keeps the old h.
      if (step >= h * (1.0 - 1e-12)) h = std::min(step * factor, options.max_step_s);
    }
    ++summary.num_steps;
    if (options.output_interval_s <= 0.0) {
      store(t, y);
    } else if (t >= next_output - time_eps || t >= options.duration_s - time_eps) {
      store(t, y);
      next_output += options.output_interval_s;
    }
  }
  if (options.output_interval_s > 0.0 && result.t.size() > 0 &&
      internal::ToDouble(result.t.back()) < t - time_eps)
    store(t, y);
  summary.status = FlightSimulationStatus::kSuccess;
  summary.final_time_s = t;
  return result;
}

}  // namespace acro::dynamics
