// Gap filling: splines reproduce straight lines exactly and smooth motion closely, rigid-body fill
// reproduces a marker moving with three partners exactly, ends and overlong gaps stay open.
#include "acro/reconstruct/gap_filling.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace acro::analysis {
namespace {

TEST(GapFilling, SplineLinesExactlySmoothClosely) {
  const int F = 100, M = 2;
  Eigen::Matrix3Xd p(3, F * M), truth(3, F * M);
  for (int f = 0; f < F; ++f) {
    truth.col(f * M) = Eigen::Vector3d(0.01 * f, -0.02 * f, 1.0);  // a line
    truth.col(f * M + 1) = Eigen::Vector3d(std::sin(0.05 * f), std::cos(0.05 * f), 0.0);
  }
  p = truth;
  for (int f = 40; f < 55; ++f) p.col(f * M).setConstant(std::nan(""));
  for (int f = 60; f < 75; ++f) p.col(f * M + 1).setConstant(std::nan(""));
  p.col(0).setConstant(std::nan(""));  // leading gap: not filled
  const GapFillingSummary s = FillGaps(p, M, {-1, -1}, 100.0);
  EXPECT_EQ(s.filled_spline, 2);
  EXPECT_EQ(s.samples_filled, 30);
  EXPECT_TRUE(std::isnan(p(0, 0)));
  for (int f = 40; f < 55; ++f)  // natural splines reproduce straight lines: rounding only
    EXPECT_LT((p.col(f * M) - truth.col(f * M)).norm(), 1e-12);
  // A circle of 1 m radius at 5 rad/s across a 0.16 s interval: within the cubic interpolation
  // bound (5/384) h⁴ max|f⁗| = (5/384) · 0.16⁴ · 5⁴ ≈ 5.3 mm (de Boor, A Practical Guide to
  // Splines, ch. V); measured 1.2 mm.
  const double bound = 5.0 / 384.0 * std::pow(0.16, 4) * std::pow(5.0, 4);
  for (int f = 60; f < 75; ++f) EXPECT_LT((p.col(f * M + 1) - truth.col(f * M + 1)).norm(), bound);
}

TEST(GapFilling, RigidBodyFillAndLimits) {
  const int F = 200, M = 4;
  const double rate = 100.0;
  Eigen::Matrix3Xd p(3, F * M), truth(3, F * M);
  const Eigen::Vector3d local[M] = {{0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, {0.05, 0.05, 0.08}};
  for (int f = 0; f < F; ++f) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.03 * f, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Eigen::Vector3d o(0.01 * f, 0.2, 1 + 0.001 * f * f / 10);
    for (int m = 0; m < M; ++m) truth.col(f * M + m) = o + R * local[m];
  }
  p = truth;
  for (int f = 50; f < 80; ++f) p.col(f * M + 3).setConstant(std::nan(""));    // 0.3 s: rigid
  for (int f = 120; f < 160; ++f) p.col(f * M + 3).setConstant(std::nan(""));  // 0.4 s: too long
  const GapFillingSummary s = FillGaps(p, M, {0, 0, 0, 0}, rate);
  EXPECT_EQ(s.filled_rigid, 1);
  EXPECT_EQ(s.left_open, 1);
  for (int f = 50; f < 80; ++f)  // the marker is rigid with its partners: exact up to rounding
    EXPECT_LT((p.col(f * M + 3) - truth.col(f * M + 3)).norm(), 1e-12);
  for (int f = 120; f < 160; ++f) EXPECT_TRUE(std::isnan(p(0, f * M + 3)));
  // Without partners of the same segment the long gap stays open too.
  Eigen::Matrix3Xd q = truth;
  for (int f = 50; f < 80; ++f) q.col(f * M + 3).setConstant(std::nan(""));
  EXPECT_EQ(FillGaps(q, M, {0, 1, 2, 3}, rate).left_open, 1);
}

}  // namespace
}  // namespace acro::analysis
