#pragma once

// Model (1)'s local trajectory form (docs/skill-design.md, "Model (1): local form"), templated on
// the scalar so that it runs in double and in ceres::Jet. Knots τ_0 < … < τ_K carry, for every
// joint angle, its value, rate and acceleration (y, y', y''), and for the root orientation the
// quaternion Q, the body angular velocity ω and its derivative ω̇. On a knot interval of length h
// with u = (t − τ_a)/h ∈ [0, 1]:
//
// - a joint angle is the quintic Hermite polynomial of its six end values (de Boor 2001, *A
//   Practical Guide to Splines*, ch. I, osculatory interpolation; the basis below), so the curve
//   is C² and each interval depends on its two knots only;
// - the orientation is q(t) = Q_a ⊗ Exp(ψ(t)) with ψ the quintic Hermite polynomial in R³ through
//   ψ = 0, ψ̇ = ω_a, ψ̈ = ω̇_a at u = 0 and ψ = Ω = Log(Q_a* ⊗ Q_b),
//   ψ̇ = J_r(Ω)⁻¹ ω_b, ψ̈ = J_r(Ω)⁻¹ (ω̇_b − J̇_r ψ̇) at u = 1 (the local-coordinate construction of
//   Park & Ravani 1997, "Smooth invariant interpolation of rotations", ACM TOG 16(3), §3, with a
//   quintic instead of their cubic so that ω̇ is matched at both ends and no global system
//   couples the intervals). The body angular velocity and acceleration are
//   ω = J_r(ψ) ψ̇,   ω̇ = J_r(ψ) ψ̈ + J̇_r ψ̇,
//   with the right Jacobian of SO(3) (Barfoot 2017, *State Estimation for Robotics*, §7.1.5;
//   Bullo & Murray 1995, "Proportional derivative control on the Euclidean group", dexp)
//   J_r(ψ) = I − α K + β K²,  K = [ψ]×,  α = (1 − cos θ)/θ²,  β = (θ − sin θ)/θ³,  θ = |ψ|,
//   and, with s = θ² and ṡ = 2 ψ·ψ̇,
//   J̇_r ψ̇ = −α_s ṡ (ψ × ψ̇) + β_s ṡ ψ × (ψ × ψ̇) + β ψ̇ × (ψ × ψ̇)   (α_s = dα/ds, β_s = dβ/ds).
//   At u = 0, J_r = I and J̇_r ψ̇ = 0, so ω and ω̇ are continuous across the knots: q is C².

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "acro/base/cubic_spline.h"
#include "acro/design/quaternion_spline.h"
#include "acro/dynamics/configuration.h"

namespace acro::analysis::internal {

/// The six quintic Hermite basis functions of u ∈ [0, 1] and their first two derivatives, for the
/// data (y_a, y'_a h, y''_a h², y_b, y'_b h, y''_b h²).
struct QuinticHermiteBasis {
  double H[3][6];  // H[r][k]: r-th derivative with respect to u of basis k
  explicit QuinticHermiteBasis(double u) {
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
    // Values.
    H[0][0] = 1 - 10 * u3 + 15 * u4 - 6 * u5;
    H[0][1] = u - 6 * u3 + 8 * u4 - 3 * u5;
    H[0][2] = 0.5 * (u2 - 3 * u3 + 3 * u4 - u5);
    H[0][3] = 10 * u3 - 15 * u4 + 6 * u5;
    H[0][4] = -4 * u3 + 7 * u4 - 3 * u5;
    H[0][5] = 0.5 * (u3 - 2 * u4 + u5);
    // First derivatives.
    H[1][0] = -30 * u2 + 60 * u3 - 30 * u4;
    H[1][1] = 1 - 18 * u2 + 32 * u3 - 15 * u4;
    H[1][2] = 0.5 * (2 * u - 9 * u2 + 12 * u3 - 5 * u4);
    H[1][3] = 30 * u2 - 60 * u3 + 30 * u4;
    H[1][4] = -12 * u2 + 28 * u3 - 15 * u4;
    H[1][5] = 0.5 * (3 * u2 - 8 * u3 + 5 * u4);
    // Second derivatives.
    H[2][0] = -60 * u + 180 * u2 - 120 * u3;
    H[2][1] = -36 * u + 96 * u2 - 60 * u3;
    H[2][2] = 0.5 * (2 - 18 * u + 36 * u2 - 20 * u3);
    H[2][3] = 60 * u - 180 * u2 + 120 * u3;
    H[2][4] = -24 * u + 84 * u2 - 60 * u3;
    H[2][5] = 0.5 * (6 * u - 24 * u2 + 20 * u3);
  }
  /// Power of h that multiplies datum k (0 for values, 1 for rates, 2 for accelerations).
  static int Power(int k) { return k % 3; }
};

/// d^r/dt^r of the quintic Hermite polynomial with end data (ya, yda, ydda, yb, ydb, yddb) in time
/// units, at the basis' u, on an interval of length h.
template <typename T, typename V>
V QuinticHermite(const QuinticHermiteBasis& B, int r, const T& h, const V* data) {
  // Σ_k H[r][k] h^(p_k − r) data_k.
  const T inv_h = T(1.0) / h;
  T scale[3];  // h^(p − r) for p = 0, 1, 2
  T hp(1.0);
  for (int i = 0; i < r; ++i) hp = hp * inv_h;
  scale[0] = hp;
  scale[1] = hp * h;
  scale[2] = hp * h * h;
  V out = data[0] * (T(B.H[r][0]) * scale[0]);
  for (int k = 1; k < 6; ++k)
    out = out + data[k] * (T(B.H[r][k]) * scale[QuinticHermiteBasis::Power(k)]);
  return out;
}

/// α, β and their derivatives with respect to s = θ² (series below θ = 0.1, where the closed forms
/// lose digits to cancellation; truncation there below 1e-12 relative).
template <typename T>
void RightJacobianCoefficients(const T& s, T* alpha, T* beta, T* alpha_s, T* beta_s) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (ScalarValue(s) < 1e-2) {
    // Taylor series in s: α = 1/2 − s/24 + s²/720 − s³/40320, β = 1/6 − s/120 + s²/5040 −
    // s³/362880.
    *alpha = T(0.5) + s * (T(-1.0 / 24) + s * (T(1.0 / 720) + s * T(-1.0 / 40320)));
    *beta = T(1.0 / 6) + s * (T(-1.0 / 120) + s * (T(1.0 / 5040) + s * T(-1.0 / 362880)));
    *alpha_s = T(-1.0 / 24) + s * (T(2.0 / 720) + s * (T(-3.0 / 40320) + s * T(4.0 / 3628800)));
    *beta_s = T(-1.0 / 120) + s * (T(2.0 / 5040) + s * (T(-3.0 / 362880) + s * T(4.0 / 39916800)));
    return;
  }
  const T th = sqrt(s);
  const T c = cos(th), sn = sin(th);
  *alpha = (T(1.0) - c) / s;
  *beta = (th - sn) / (s * th);
  // dα/ds = (dα/dθ)/(2θ), dα/dθ = sin θ/θ² − 2(1 − cos θ)/θ³; likewise for β.
  *alpha_s = sn / (T(2.0) * s * th) - (T(1.0) - c) / (s * s);
  *beta_s = (T(1.0) - c) / (T(2.0) * s * s) - T(1.5) * (th - sn) / (s * s * th);
}

/// J_r(ψ) and J̇_r ψ̇ (see the file comment).
template <typename T>
void RightJacobianAndRate(const dynamics::Vector3<T>& psi,
                          const dynamics::Vector3<T>& psi_dot,
                          dynamics::Matrix3<T>* Jr,
                          dynamics::Vector3<T>* Jr_dot_psi_dot) {
  T alpha, beta, alpha_s, beta_s;
  const T s = psi.squaredNorm();
  RightJacobianCoefficients(s, &alpha, &beta, &alpha_s, &beta_s);
  dynamics::Matrix3<T> K;
  K << T(0.0), -psi.z(), psi.y(),  //
      psi.z(), T(0.0), -psi.x(),   //
      -psi.y(), psi.x(), T(0.0);
  *Jr = dynamics::Matrix3<T>::Identity() - alpha * K + beta * K * K;
  const T s_dot = T(2.0) * psi.dot(psi_dot);
  const dynamics::Vector3<T> c = psi.cross(psi_dot);
  *Jr_dot_psi_dot = -alpha_s * s_dot * c + beta_s * s_dot * psi.cross(c) + beta * psi_dot.cross(c);
}

/// Orientation data at one knot.
template <typename T>
struct OrientationKnot {
  Eigen::Quaternion<T> Q;
  dynamics::Vector3<T> w;     ///< body angular velocity
  dynamics::Vector3<T> wdot;  ///< its derivative
};

/// The orientation, body angular velocity and acceleration on the interval [a, b] of length h at
/// the basis' u (see the file comment).
template <typename T>
QuaternionSample<T> EvalOrientationHermite(const QuinticHermiteBasis& B,
                                           const T& h,
                                           const OrientationKnot<T>& a,
                                           const OrientationKnot<T>& b) {
  using Vec3 = dynamics::Vector3<T>;
  // End conditions of ψ at u = 1.
  const Vec3 Omega = QuaternionLog<T>(Eigen::Quaternion<T>(a.Q.conjugate() * b.Q));
  dynamics::Matrix3<T> Jr_end;
  Vec3 unused;
  RightJacobianAndRate<T>(Omega, Vec3::Zero(), &Jr_end, &unused);
  const dynamics::Matrix3<T> Jr_end_inv = Jr_end.inverse();
  const Vec3 psi_dot_end = Jr_end_inv * b.w;
  Vec3 rate_end;
  RightJacobianAndRate<T>(Omega, psi_dot_end, &Jr_end, &rate_end);
  const Vec3 psi_ddot_end = Jr_end_inv * (b.wdot - rate_end);
  // ψ and its time derivatives at u.
  const Vec3 data[6] = {Vec3::Zero(), a.w, a.wdot, Omega, psi_dot_end, psi_ddot_end};
  const Vec3 psi = QuinticHermite<T, Vec3>(B, 0, h, data);
  const Vec3 psi_dot = QuinticHermite<T, Vec3>(B, 1, h, data);
  const Vec3 psi_ddot = QuinticHermite<T, Vec3>(B, 2, h, data);
  dynamics::Matrix3<T> Jr;
  Vec3 rate;
  RightJacobianAndRate<T>(psi, psi_dot, &Jr, &rate);
  QuaternionSample<T> out;
  out.q_WB = a.Q * dynamics::QuaternionExp<T>(psi);
  out.w_WB_B = Jr * psi_dot;
  out.wdot_WB_B = Jr * psi_ddot + rate;
  return out;
}

}  // namespace acro::analysis::internal
