#pragma once

// sin and cos of one angle at once. For double, a branch-light implementation (Cody–Waite
// reduction by π/2 in three parts, Cephes' minimax polynomials on [−π/4, π/4]; Moshier 1989,
// "Methods and Programs for Mathematical Functions", sin.c) that the compiler can inline: the
// joint angles' sines and cosines were a fifth of inverse dynamics' time through libm's sincos.
// Accuracy: within a few ulps of libm for |x| ≤ 1e5 (tested in tests/dynamics/spatial_test.cc);
// larger angles fall back to libm. Other scalar types (ceres::Jet) use their own sin and cos.

#include <cmath>

namespace acro::dynamics::internal {

/// sin and cos of x for |x| ≤ kFastSinCosLimit (callers check; see SinCos below).
inline void SinCosReduced(double x, double* s, double* c) {
  // x = k·π/2 + r, |r| ≤ π/4; π/2 in three parts so that k·part is exact for |k| < 2^26.
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kPio2Part1 = 1.57079625129699707031e0;
  constexpr double kPio2Part2 = 7.54978941586159635335e-8;
  constexpr double kPio2Part3 = 5.39030285815811905290e-15;
  // Round to nearest by adding and removing 1.5·2⁵² (exact for |x·2/π| < 2⁵¹; no libm call).
  constexpr double kRound = 6755399441055744.0;
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r = ((x - k * kPio2Part1) - k * kPio2Part2) - k * kPio2Part3;
  const double z = r * r;
  // Cephes sin.c: sin r = r + r³ P(r²), cos r = 1 − r²/2 + r⁴ Q(r²).
  const double sin_r =
      r + r * z *
              (((((1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z +
                  2.75573136213857245213e-6) *
                     z -
                 1.98412698295895385996e-4) *
                    z +
                8.33333333332211858878e-3) *
                   z -
               1.66666666666666307295e-1);
  const double cos_r = 1.0 - 0.5 * z +
                       z * z *
                           (((((-1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z -
                               2.75573141792967388112e-7) *
                                  z +
                              2.48015872888517045348e-5) *
                                 z -
                             1.38888888888730564116e-3) *
                                z +
                            4.16666666666665929218e-2);
  // Quadrant m = k mod 4 ∈ {0, 1, 2, 3}: (sin, cos) of x is (s, c), (c, −s), (−s, −c), (−c, s) of
  // r. Computed in floating point without branches or integer conversions so that a loop over
  // angles vectorises; every step is exact (small integers, products with 0 and ±1).
  // floor(y) for y = k/4 is the nearest integer to y − 3/8.
  const double m = k - 4.0 * ((k * 0.25 - 0.375 + kRound) - kRound);
  const double half = (m * 0.5 - 0.25 + kRound) - kRound;  // 0 for m < 2, 1 otherwise
  const double swap = m - 2.0 * half;                      // m mod 2
  const double sign_s = 1.0 - 2.0 * half;
  const double sign_c = sign_s * (1.0 - 2.0 * swap);
  *s = sign_s * (swap * cos_r + (1.0 - swap) * sin_r);
  *c = sign_c * (swap * sin_r + (1.0 - swap) * cos_r);
}

/// Beyond this the reduction loses accuracy and libm is used.
inline constexpr double kFastSinCosLimit = 1e5;

inline void SinCos(double x, double* s, double* c) {
  if (std::abs(x) <= kFastSinCosLimit) {
    SinCosReduced(x, s, c);
  } else {
    *s = std::sin(x);
    *c = std::cos(x);
  }
}

/// Generic scalar (e.g. ceres::Jet): the type's own sin and cos, found by argument-dependent
/// lookup.
template <typename T>
inline void SinCos(const T& x, T* s, T* c) {
  using std::cos;
  using std::sin;
  *s = sin(x);
  *c = cos(x);
}

/// SinCos of x[0..n) into s, c: a branch-free loop first, then libm for the rare large angles.
inline void SinCosArray(const double* x, int n, double* s, double* c) {
  for (int k = 0; k < n; ++k) SinCosReduced(x[k], s + k, c + k);
  for (int k = 0; k < n; ++k) {
    if (!(std::abs(x[k]) <= kFastSinCosLimit)) {
      s[k] = std::sin(x[k]);
      c[k] = std::cos(x[k]);
    }
  }
}

template <typename T>
inline void SinCosArray(const T* x, int n, T* s, T* c) {
  for (int k = 0; k < n; ++k) SinCos(x[k], s + k, c + k);
}

}  // namespace acro::dynamics::internal
