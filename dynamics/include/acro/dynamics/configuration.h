#pragma once

// Generalised coordinates and velocities (docs/notation.md):
//   q = [p_WoBo_W (3), quaternion of R_WB stored (w, x, y, z) (4), joint angles (n)]
//   v = [v_WBo_W (3), w_WB_B (3), joint rates (n)]
// The root's linear velocity is the velocity of the root origin Bo in W, expressed in W, so that
// ṗ = v[0:3]; the root's angular velocity is expressed in the root frame B. Joint rates are the
// time derivatives of the joint angles. q̇ = N(q)·v with the quaternion block
// q̇_quat = ½ q ⊗ (0, w_WB_B) (Hamilton product).

#include <Eigen/Geometry>
#include <cmath>

#include "acro/dynamics/model.h"

namespace acro::dynamics {

/// The root's share of q (position 3, quaternion 4) and of v (linear 3, angular 3): joint angle k
/// is q[kRootNq + k], its rate v[kRootNv + k].
inline constexpr int kRootNq = 7;
inline constexpr int kRootNv = 6;

/// Quaternion of the root, R_WB, from q (q stores w, x, y, z; Eigen stores x, y, z, w).
template <typename Derived>
Eigen::Quaternion<typename Derived::Scalar> GetRootQuaternion(const Eigen::MatrixBase<Derived>& q) {
  return Eigen::Quaternion<typename Derived::Scalar>(q[3], q[4], q[5], q[6]);
}

/// Writes the root quaternion into q as (w, x, y, z).
template <typename T>
void SetRootQuaternion(const Eigen::Quaternion<T>& q_WB, VectorXRef<T> q) {
  q[3] = q_WB.w();
  q[4] = q_WB.x();
  q[5] = q_WB.y();
  q[6] = q_WB.z();
}

/// R_WB of the quaternion (w, x, y, z), normalised on the way: the homogeneous form with
/// s = 2/|q|² gives the rotation of q/|q| for any nonzero q, so that an optimiser's slightly
/// non-unit quaternion still yields a proper rotation (Shoemake 1985).
template <typename T>
Matrix3<T> QuaternionToRotation(const T& w, const T& x, const T& y, const T& z) {
  const T two = T(2) / (w * w + x * x + y * y + z * z);
  const T xx = x * x, yy = y * y, zz = z * z;
  const T xy = x * y, xz = x * z, yz = y * z;
  const T wx = w * x, wy = w * y, wz = w * z;
  Matrix3<T> R;
  R << T(1) - two * (yy + zz), two * (xy - wz), two * (xz + wy),  //
      two * (xy + wz), T(1) - two * (xx + zz), two * (yz - wx),   //
      two * (xz - wy), two * (yz + wx), T(1) - two * (xx + yy);
  return R;
}

/// The neutral configuration: root at the origin, identity orientation, all joint angles zero.
template <typename T>
VectorX<T> MakeNeutralConfiguration(const Model<T>& model) {
  VectorX<T> q = VectorX<T>::Zero(model.nq());
  q[3] = T(1);
  return q;
}

/// q̇ = N(q)·v (the quaternion block is ½ q ⊗ (0, w_WB_B)). qdot must have nq entries.
template <typename T>
void CalcConfigurationDerivative(const Model<T>& model,
                                 const VectorXcRef<T>& q,
                                 const VectorXcRef<T>& v,
                                 VectorXRef<T> qdot) {
  ACRO_DEMAND(q.size() == model.nq() && v.size() == model.nv() && qdot.size() == model.nq());
  qdot.template head<3>() = v.template head<3>();
  const T half(0.5);
  const T w = q[3], x = q[4], y = q[5], z = q[6];
  const T wx = v[3], wy = v[4], wz = v[5];
  qdot[3] = -half * (x * wx + y * wy + z * wz);
  qdot[4] = half * (w * wx + y * wz - z * wy);
  qdot[5] = half * (w * wy + z * wx - x * wz);
  qdot[6] = half * (w * wz + x * wy - y * wx);
  qdot.tail(model.num_joint_dofs()) = v.tail(model.num_joint_dofs());
}

/// The matrix N(q) (nq × nv) of q̇ = N(q)·v.
template <typename T>
void CalcConfigurationDerivativeMatrix(const Model<T>& model,
                                       const VectorXcRef<T>& q,
                                       MatrixXRef<T> N) {
  ACRO_DEMAND(q.size() == model.nq() && N.rows() == model.nq() && N.cols() == model.nv());
  N.setZero();
  N.template topLeftCorner<3, 3>().setIdentity();
  const T half(0.5);
  const T w = q[3], x = q[4], y = q[5], z = q[6];
  Eigen::Matrix<T, 4, 3> Q;
  Q << -x, -y, -z,  //
      w, -z, y,     //
      z, w, -x,     //
      -y, x, w;
  N.template block<4, 3>(3, 3) = half * Q;
  const int n = model.num_joint_dofs();
  N.bottomRightCorner(n, n).setIdentity();
}

/// v from q̇ (the inverse of N on unit quaternions): w_WB_B = 2·vec(q* ⊗ q̇).
template <typename T>
void CalcVelocityFromConfigurationDerivative(const Model<T>& model,
                                             const VectorXcRef<T>& q,
                                             const VectorXcRef<T>& qdot,
                                             VectorXRef<T> v) {
  ACRO_DEMAND(q.size() == model.nq() && qdot.size() == model.nq() && v.size() == model.nv());
  v.template head<3>() = qdot.template head<3>();
  const T two(2);
  const Vector3<T> e(q[4], q[5], q[6]);
  const Vector3<T> edot(qdot[4], qdot[5], qdot[6]);
  v.template segment<3>(3) = two * (q[3] * edot - qdot[3] * e - e.cross(edot));
  v.tail(model.num_joint_dofs()) = qdot.tail(model.num_joint_dofs());
}

/// Unit quaternion exp(θ/2 · n) for a rotation vector φ = θ n (stored w, x, y, z), with a series
/// near φ = 0 so that automatic differentiation stays finite there.
template <typename T>
Eigen::Quaternion<T> QuaternionExp(const Vector3<T>& phi) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta2 = phi.squaredNorm();
  T c, s_over_theta;
  if (theta2 < T(1e-12)) {
    // cos(θ/2) ≈ 1 − θ²/8, sin(θ/2)/θ ≈ ½ − θ²/48: truncation below 1e-25, under double rounding.
    c = T(1) - theta2 / T(8);
    s_over_theta = T(0.5) - theta2 / T(48);
  } else {
    const T theta = sqrt(theta2);
    c = cos(theta / T(2));
    s_over_theta = sin(theta / T(2)) / theta;
  }
  return Eigen::Quaternion<T>(
      c, s_over_theta * phi.x(), s_over_theta * phi.y(), s_over_theta * phi.z());
}

/// q_out = q ⊕ v·dt: the root moves by v_WBo_W·dt and turns by exp(w_WB_B·dt) in its own frame
/// (q_WB ⊗ exp(½ w dt)), the joint angles move by their rates·dt. Exact for constant v.
template <typename T>
void IntegrateConfiguration(const Model<T>& model,
                            const VectorXcRef<T>& q,
                            const VectorXcRef<T>& v,
                            const T& dt,
                            VectorXRef<T> q_out) {
  ACRO_DEMAND(q.size() == model.nq() && v.size() == model.nv() && q_out.size() == model.nq());
  const Eigen::Quaternion<T> q_WB = GetRootQuaternion(q);
  const Vector3<T> phi = v.template segment<3>(3) * dt;
  const Eigen::Quaternion<T> q_new = q_WB * QuaternionExp<T>(phi);
  q_out.template head<3>() = q.template head<3>() + v.template head<3>() * dt;
  SetRootQuaternion<T>(q_new, q_out);
  const int n = model.num_joint_dofs();
  q_out.tail(n) = q.tail(n) + v.tail(n) * dt;
}

// Explicit instantiations for double live in src/configuration.cc.
extern template VectorX<double> MakeNeutralConfiguration<double>(const Model<double>&);
extern template void CalcConfigurationDerivative<double>(const Model<double>&,
                                                         const VectorXcRef<double>&,
                                                         const VectorXcRef<double>&,
                                                         VectorXRef<double>);
extern template void CalcConfigurationDerivativeMatrix<double>(const Model<double>&,
                                                               const VectorXcRef<double>&,
                                                               MatrixXRef<double>);
extern template void CalcVelocityFromConfigurationDerivative<double>(const Model<double>&,
                                                                     const VectorXcRef<double>&,
                                                                     const VectorXcRef<double>&,
                                                                     VectorXRef<double>);
extern template void IntegrateConfiguration<double>(const Model<double>&,
                                                    const VectorXcRef<double>&,
                                                    const VectorXcRef<double>&,
                                                    const double&,
                                                    VectorXRef<double>);

}  // namespace acro::dynamics
