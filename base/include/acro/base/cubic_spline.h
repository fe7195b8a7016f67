#pragma once

// Natural C² cubic splines through knots (t_i, y_i): the keyframes of a skill, the samples around
// a marker gap; , templated on the scalar so that the
// same code runs in double and in ceres::Jet (derivatives with respect to the knot times t_i and
// the values y_i). Every channel of a skill (a joint angle, a cumulative basis function of the
// quaternion spline) shares the knots, so the tridiagonal system is factorised once per set of
// knots and solved for each channel.
//
// On [t_i, t_{i+1}] with h = t_{i+1} − t_i, a = (t_{i+1} − t)/h, b = (t − t_i)/h and the second
// derivatives M_i (de Boor 2001, *A Practical Guide to Splines*, ch. IV; Press et al.,
// *Numerical Recipes*, 3rd ed., eqs. 3.3.3–3.3.7):
//   s(t)   = a y_i + b y_{i+1} + ((a³ − a) M_i + (b³ − b) M_{i+1}) h² / 6
//   s'(t)  = (y_{i+1} − y_i)/h − (3a² − 1) h M_i / 6 + (3b² − 1) h M_{i+1} / 6
//   s''(t) = a M_i + b M_{i+1}
// and continuity of s' at the interior knots gives
//   h_{i−1} M_{i−1} + 2 (h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 ((y_{i+1} − y_i)/h_i − (y_i −
//   y_{i−1})/h_{i−1}),
// with the natural end conditions M_0 = M_n = 0 (zero acceleration at take-off and landing).

#include <type_traits>
#include <vector>

#include "acro/base/demand.h"

namespace acro {

/// The value part of a scalar: itself for arithmetic types, `.a` for a ceres::Jet.
template <typename T>
double ScalarValue(const T& x) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(x);
  else
    return x.a;
}

/// Value, first and second derivative of a spline channel at one time.
template <typename T>
struct SplineSample {
  T value{0.0};
  T d1{0.0};
  T d2{0.0};
};

/// Per-time coefficients of a spline evaluation (see CubicSplineKnots::Weights).
template <typename T>
struct SplineWeights {
  int interval = 0;
  T a{0.0}, b{0.0}, ca{0.0}, cb{0.0}, da{0.0}, db{0.0}, inv_h{0.0};
};

/// The knots of a natural cubic spline and the factorisation of its moment equations.
template <typename T>
class CubicSplineKnots {
 public:
  CubicSplineKnots() = default;

  /// Knots t_0 < t_1 < … < t_n (n ≥ 1).
  explicit CubicSplineKnots(std::vector<T> t) { Reset(std::move(t)); }

  void Reset(std::vector<T> t) {
    t_ = std::move(t);
    const size_t n = t_.size();
    ACRO_DEMAND(n >= 2);
    h_.resize(n - 1);
    for (size_t i = 0; i + 1 < n; ++i) h_[i] = t_[i + 1] - t_[i];
    // Thomas algorithm forward elimination on the interior unknowns M_1..M_{n−2}:
    // diag d_i = 2(h_{i−1} + h_i), sub h_{i−1}, super h_i.
    const size_t m = n >= 2 ? n - 2 : 0;
    c_prime_.assign(m, T(0.0));
    inv_denominator_.assign(m, T(0.0));
    for (size_t k = 0; k < m; ++k) {
      const size_t i = k + 1;
      T denom = T(2.0) * (h_[i - 1] + h_[i]);
      if (k > 0) denom -= h_[i - 1] * c_prime_[k - 1];
      inv_denominator_[k] = T(1.0) / denom;
      c_prime_[k] = h_[i] * inv_denominator_[k];
    }
  }

  int num_knots() const { return static_cast<int>(t_.size()); }
  const std::vector<T>& knots() const { return t_; }

  /// Second derivatives M (num_knots entries) of the spline through y (num_knots values).
  template <typename Y>
  void SolveMoments(const Y* y, T* M) const {
    const size_t n = t_.size();
    const size_t m = n - 2;
    M[0] = T(0.0);
    M[n - 1] = T(0.0);
    if (m == 0) return;
    // Forward sweep on the right-hand side, then back substitution.
    std::vector<T>& d = scratch_;
    d.resize(m);
    for (size_t k = 0; k < m; ++k) {
      const size_t i = k + 1;
      T rhs = T(6.0) * ((y[i + 1] - y[i]) / h_[i] - (y[i] - y[i - 1]) / h_[i - 1]);
      if (k > 0) rhs -= h_[i - 1] * d[k - 1];
      d[k] = rhs * inv_denominator_[k];
    }
    M[m] = d[m - 1];
    for (size_t k = m - 1; k-- > 0;) d[k] -= c_prime_[k] * d[k + 1];
    for (size_t k = 0; k < m; ++k) M[k + 1] = d[k];
  }

  /// The interval i with t_i ≤ t < t_{i+1}, clamped to [0, n − 2] (compares value parts only:
  /// the interval is piecewise constant in the knots).
  int FindInterval(double t) const {
    const int last = num_knots() - 2;
    int i = 0;
    while (i < last && t >= ScalarValue(t_[static_cast<size_t>(i + 1)])) ++i;
    return i;
  }

  /// The coefficients of y_i, y_{i+1}, M_i, M_{i+1} in s, s' and s'' on interval i at time t: the
  /// part of an evaluation shared by every channel.
  template <typename TT>
  SplineWeights<T> Weights(int i, const TT& t) const {
    const size_t ui = static_cast<size_t>(i);
    const T& h = h_[ui];
    SplineWeights<T> w;
    w.interval = i;
    w.inv_h = T(1.0) / h;
    w.a = (t_[ui + 1] - t) * w.inv_h;
    w.b = (t - t_[ui]) * w.inv_h;
    const T h2_6 = h * h / T(6.0);
    w.ca = (w.a * w.a * w.a - w.a) * h2_6;
    w.cb = (w.b * w.b * w.b - w.b) * h2_6;
    w.da = -(T(3.0) * w.a * w.a - T(1.0)) * h / T(6.0);
    w.db = (T(3.0) * w.b * w.b - T(1.0)) * h / T(6.0);
    return w;
  }

  /// One channel (values y, moments M) with precomputed weights.
  template <typename Y>
  SplineSample<T> Combine(const SplineWeights<T>& w, const Y* y, const T* M) const {
    const size_t ui = static_cast<size_t>(w.interval);
    const T yi = T(y[ui]);
    const T yj = T(y[ui + 1]);
    SplineSample<T> s;
    s.value = w.a * yi + w.b * yj + w.ca * M[ui] + w.cb * M[ui + 1];
    s.d1 = (yj - yi) * w.inv_h + w.da * M[ui] + w.db * M[ui + 1];
    s.d2 = w.a * M[ui] + w.b * M[ui + 1];
    return s;
  }

  /// The spline through y with moments M, on interval i, at time t.
  template <typename Y, typename TT>
  SplineSample<T> Eval(int i, const TT& t, const Y* y, const T* M) const {
    return Combine(Weights(i, t), y, M);
  }

 private:
  std::vector<T> t_;
  std::vector<T> h_;
  std::vector<T> c_prime_;
  std::vector<T> inv_denominator_;
  mutable std::vector<T> scratch_;
};

/// One channel: knots, values and moments together (a convenience for double use).
template <typename T>
class CubicSpline {
 public:
  CubicSpline() = default;
  CubicSpline(std::vector<T> t, std::vector<T> y) : knots_(std::move(t)), y_(std::move(y)) {
    ACRO_DEMAND(y_.size() == knots_.knots().size());
    M_.resize(y_.size());
    knots_.SolveMoments(y_.data(), M_.data());
  }
  SplineSample<T> Eval(const T& t) const {
    return knots_.Eval(knots_.FindInterval(ScalarValue(t)), t, y_.data(), M_.data());
  }

 private:
  CubicSplineKnots<T> knots_;
  std::vector<T> y_;
  std::vector<T> M_;
};

}  // namespace acro
