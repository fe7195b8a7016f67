#pragma once

// A C² interpolating spline on the unit quaternions in cumulative form (Kim, Kim & Shin 1995,
// "A general construction scheme for unit quaternion curves with simple high order derivatives",
// SIGGRAPH '95, eq. 4): through orientations Q_0..Q_n at knots t_0..t_n,
//
//   q(t) = Q_0 ⊗ exp(B̃_1(t) ω_1 / 2) ⊗ … ⊗ exp(B̃_n(t) ω_n / 2),   ω_k = log(Q_{k−1}* ⊗ Q_k),
//
// where B̃_k(t) = Σ_{j ≥ k} b_j(t) is the cumulative basis of the natural cubic spline's cardinal
// functions b_j (b_j(t_i) = δ_ij): B̃_k is the natural cubic spline through the step data
// (0 for knots before k, 1 from k on). Each factor is C², so q is C², and at t_i every
// B̃_k is 0 or 1, so q(t_i) = Q_i. With ω_k the rotation vectors in the moving (body) frame, the
// body-frame angular velocity and acceleration follow by composing the factors one at a time
// (R = R_prev R_k, u_k = B̃_k' ω_k the angular velocity of factor k about its fixed axis):
//   w ← R_kᵀ w + u_k,   ẇ ← R_kᵀ ẇ − u_k × (R_kᵀ w) + B̃_k'' ω_k.
// Consecutive keyframe orientations must differ by less than 180° (log's branch).

#include <cmath>
#include <vector>

#include "acro/base/cubic_spline.h"
#include "acro/dynamics/configuration.h"

namespace acro::analysis {

/// Rotation vector φ (|φ| ≤ π) of a unit quaternion: q = exp(φ/2), with a series near the identity
/// so that automatic differentiation stays finite there.
template <typename T>
dynamics::Vector3<T> QuaternionLog(const Eigen::Quaternion<T>& q_in) {
  using std::atan2;
  using std::sqrt;
  // Same rotation with w ≥ 0 (shortest arc).
  Eigen::Quaternion<T> q = q_in;
  if (ScalarValue(q.w()) < 0.0) q.coeffs() = -q.coeffs();
  const dynamics::Vector3<T> v = q.vec();
  const T s2 = v.squaredNorm();
  if (ScalarValue(s2) < 1e-24) {
    // 2 atan2(s, w)/s ≈ 2/w (1 − s²/(3w²)): truncation below 1e-24, under double rounding.
    return v * (T(2.0) / q.w() * (T(1.0) - s2 / (T(3.0) * q.w() * q.w())));
  }
  const T s = sqrt(s2);
  return v * (T(2.0) * atan2(s, q.w()) / s);
}

/// Orientation, body-frame angular velocity w_WB_B and its derivative at one time.
template <typename T>
struct QuaternionSample {
  Eigen::Quaternion<T> q_WB;
  dynamics::Vector3<T> w_WB_B;
  dynamics::Vector3<T> wdot_WB_B;
};

/// The cumulative-form spline through orientations at given knots.
template <typename T>
class QuaternionSpline {
 public:
  QuaternionSpline() = default;

  /// Knots t_0 < … < t_n and unit quaternions Q_0..Q_n (consecutive ones less than 180° apart).
  QuaternionSpline(std::vector<T> t, std::vector<Eigen::Quaternion<T>> Q) {
    Reset(std::move(t), std::move(Q));
  }

  void Reset(std::vector<T> t, std::vector<Eigen::Quaternion<T>> Q) {
    knots_.Reset(std::move(t));
    Q_ = std::move(Q);
    const size_t n = Q_.size();
    ACRO_DEMAND(n == knots_.knots().size());
    omega_.resize(n);
    omega_[0].setZero();
    for (size_t k = 1; k < n; ++k) omega_[k] = QuaternionLog<T>(Q_[k - 1].conjugate() * Q_[k]);
    // Moments of the cumulative basis B̃_k: the spline through the step data 1[j ≥ k].
    moments_.assign(n * n, T(0.0));
    std::vector<double> step(n);
    for (size_t k = 1; k < n; ++k) {
      for (size_t j = 0; j < n; ++j) step[j] = j >= k ? 1.0 : 0.0;
      knots_.SolveMoments(step.data(), moments_.data() + k * n);
    }
  }

  const CubicSplineKnots<T>& knots() const { return knots_; }

  /// Rotation vector ω_k between keyframes k − 1 and k (k ≥ 1).
  const dynamics::Vector3<T>& omega(int k) const { return omega_[static_cast<size_t>(k)]; }

  template <typename TT>
  QuaternionSample<T> Eval(const TT& t) const {
    const size_t n = Q_.size();
    const int interval = knots_.FindInterval(ScalarValue(t));
    QuaternionSample<T> out;
    out.q_WB = Q_[0];
    out.w_WB_B.setZero();
    out.wdot_WB_B.setZero();
    const SplineWeights<T> weights = knots_.Weights(interval, t);
    std::vector<double>& step = step_;
    step.resize(n);
    for (size_t k = 1; k < n; ++k) {
      for (size_t j = 0; j < n; ++j) step[j] = j >= k ? 1.0 : 0.0;
      const SplineSample<T> B = knots_.Combine(weights, step.data(), moments_.data() + k * n);
      const dynamics::Vector3<T> phi = omega_[k] * B.value;
      const Eigen::Quaternion<T> A = dynamics::QuaternionExp<T>(phi);
      const dynamics::Matrix3<T> Rt = A.toRotationMatrix().transpose();
      const dynamics::Vector3<T> u = omega_[k] * B.d1;
      const dynamics::Vector3<T> w_rot = Rt * out.w_WB_B;
      out.wdot_WB_B = Rt * out.wdot_WB_B - u.cross(w_rot) + omega_[k] * B.d2;
      out.w_WB_B = w_rot + u;
      out.q_WB = out.q_WB * A;
    }
    return out;
  }

 private:
  CubicSplineKnots<T> knots_;
  std::vector<Eigen::Quaternion<T>> Q_;
  std::vector<dynamics::Vector3<T>> omega_;
  std::vector<T> moments_;  // n × n: row k holds the moments of B̃_k
  mutable std::vector<double> step_;
};

}  // namespace acro::analysis
