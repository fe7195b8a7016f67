#include "acro/base/cubic_spline.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace acro {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

const std::vector<double> kT = {0.0, 0.13, 0.4, 0.55, 0.9, 1.2, 1.6};
const std::vector<double> kY = {0.0, 1.0, -0.5, 2.0, 2.1, 0.3, -1.0};

TEST(CubicSpline, InterpolatesTheKnotsWithNaturalEnds) {
  const CubicSpline<double> s(kT, kY);
  for (size_t i = 0; i < kT.size(); ++i) EXPECT_NEAR(s.Eval(kT[i]).value, kY[i], 8 * kEps);
  EXPECT_NEAR(s.Eval(kT.front()).d2, 0.0, 64 * kEps);
  EXPECT_NEAR(s.Eval(kT.back()).d2, 0.0, 64 * kEps);
}

// C²: value, slope and curvature agree from both sides of every interior knot.
TEST(CubicSpline, IsTwiceContinuouslyDifferentiable) {
  const CubicSplineKnots<double> knots(kT);
  std::vector<double> M(kT.size());
  knots.SolveMoments(kY.data(), M.data());
  for (int i = 1; i + 1 < static_cast<int>(kT.size()); ++i) {
    const SplineSample<double> left =
        knots.Eval(i - 1, kT[static_cast<size_t>(i)], kY.data(), M.data());
    const SplineSample<double> right =
        knots.Eval(i, kT[static_cast<size_t>(i)], kY.data(), M.data());
    // Each side is a sum of O(10) terms of size up to ~100 (the curvatures): 1e-12 absolute.
    EXPECT_NEAR(left.value, right.value, 1e-12);
    EXPECT_NEAR(left.d1, right.d1, 1e-12);
    EXPECT_NEAR(left.d2, right.d2, 1e-11);
  }
}

// The analytic derivatives against central differences of the spline itself.
TEST(CubicSpline, DerivativesMatchCentralDifferences) {
  const CubicSpline<double> s(kT, kY);
  const double h = 1e-5;  // truncation h² f''' ~ 1e-8, rounding ε/h ~ 1e-11
  for (double t : {0.05, 0.31, 0.7, 1.0, 1.5}) {
    EXPECT_NEAR(s.Eval(t).d1, (s.Eval(t + h).value - s.Eval(t - h).value) / (2 * h), 1e-7);
    EXPECT_NEAR(s.Eval(t).d2, (s.Eval(t + h).d1 - s.Eval(t - h).d1) / (2 * h), 1e-6);
  }
}

// A cubic's data reproduce... only when the ends agree: a natural spline reproduces straight lines
// exactly (second derivative zero everywhere).
TEST(CubicSpline, ReproducesAStraightLine) {
  std::vector<double> y;
  for (double t : kT) y.push_back(3.0 - 2.0 * t);
  const CubicSpline<double> s(kT, y);
  for (double t : {0.05, 0.31, 0.7, 1.0, 1.5}) {
    EXPECT_NEAR(s.Eval(t).value, 3.0 - 2.0 * t, 16 * kEps);
    EXPECT_NEAR(s.Eval(t).d1, -2.0, 256 * kEps);
    EXPECT_NEAR(s.Eval(t).d2, 0.0, 1024 * kEps);
  }
}

}  // namespace
}  // namespace acro
