#include "acro/dynamics/spatial.h"

#include "acro/dynamics/fast_math.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "test_models.h"

namespace acro::dynamics {
namespace {

using testing::RandomQuaternion;
using testing::RandomVector;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// A force cannot be added to (or subtracted from) a motion, nor a momentum to a force: the strong
// types have no such operators.
template <typename A, typename B>
concept Addable = requires(A a, B b) {
  a + b;
};
template <typename A, typename B>
concept Subtractable = requires(A a, B b) {
  a - b;
};
static_assert(Addable<SpatialMotion<double>, SpatialMotion<double>>);
static_assert(Addable<SpatialForce<double>, SpatialForce<double>>);
static_assert(!Addable<SpatialMotion<double>, SpatialForce<double>>);
static_assert(!Addable<SpatialForce<double>, SpatialMotion<double>>);
static_assert(!Subtractable<SpatialMotion<double>, SpatialForce<double>>);
static_assert(!Addable<SpatialForce<double>, SpatialMomentum<double>>);
static_assert(!std::is_convertible_v<SpatialForce<double>, SpatialMotion<double>>);
static_assert(!std::is_convertible_v<Vector6<double>, SpatialMotion<double>>);

// The 6×6 Plücker matrix of X_AB acting on motions (RBDA ch. 2, with E = R_ABᵀ, r = p_AoBo),
// built here independently of RigidTransform's formulas.
Matrix6<double> MotionMatrix(const RigidTransform<double>& X_AB) {
  Matrix6<double> X = Matrix6<double>::Zero();
  const Eigen::Matrix3d& R = X_AB.rotation();
  X.topLeftCorner<3, 3>() = R;
  X.bottomRightCorner<3, 3>() = R;
  X.bottomLeftCorner<3, 3>() = Skew(X_AB.translation()) * R;
  return X;
}

class SpatialTest : public ::testing::Test {
 protected:
  std::mt19937 rng_{20261122};
  RigidTransform<double> RandomTransform() {
    return RigidTransform<double>(RandomQuaternion(rng_).toRotationMatrix(),
                                  RandomVector(rng_, 2.0));
  }
};

TEST_F(SpatialTest, TransformsMatchPluckerMatrices) {
  for (int trial = 0; trial < 20; ++trial) {
    const RigidTransform<double> X = RandomTransform();
    const Matrix6<double> Xm = MotionMatrix(X);
    // Forces transform by X* = X⁻ᵀ (RBDA ch. 2).
    const Matrix6<double> Xf = Xm.inverse().transpose();
    const SpatialMotion<double> m(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
    const SpatialForce<double> f(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
    // Tolerance: products of O(1) entries with |p| ≤ 3.5, a few dozen roundings.
    const double tol = 64 * kEps * 4.0;
    EXPECT_LE((X.Apply(m).get_coeffs() - Xm * m.get_coeffs()).cwiseAbs().maxCoeff(), tol);
    EXPECT_LE(
        (X.ApplyInverse(m).get_coeffs() - Xm.inverse() * m.get_coeffs()).cwiseAbs().maxCoeff(),
        tol);
    EXPECT_LE((X.Apply(f).get_coeffs() - Xf * f.get_coeffs()).cwiseAbs().maxCoeff(), tol);
    EXPECT_LE(
        (X.ApplyInverse(f).get_coeffs() - Xf.inverse() * f.get_coeffs()).cwiseAbs().maxCoeff(),
        tol);
    // Power is invariant under a change of frame (RBDA ch. 2).
    EXPECT_NEAR(X.Apply(m).Dot(X.Apply(f)), m.Dot(f), tol);
    // Composition and inverse.
    const RigidTransform<double> Y = RandomTransform();
    EXPECT_LE((MotionMatrix(X * Y) - Xm * MotionMatrix(Y)).cwiseAbs().maxCoeff(), tol);
    EXPECT_LE((MotionMatrix(X.Inverse()) - Xm.inverse()).cwiseAbs().maxCoeff(), tol);
  }
}

TEST_F(SpatialTest, InertiaTransformIsCongruence) {
  for (int trial = 0; trial < 20; ++trial) {
    const MassProperties mp = testing::RandomMass(rng_);
    const SpatialInertia<double> I_B =
        SpatialInertia<double>::FromMassComInertia(mp.mass_kg, mp.p_BoBcm_B, mp.I_BBcm_B);
    const RigidTransform<double> X_AB = RandomTransform();
    // I_A = X_BA* I_B X_BA with X_BA = X_AB⁻¹ as a motion transform (RBDA ch. 2).
    const Matrix6<double> X_BA = MotionMatrix(X_AB.Inverse());
    const Matrix6<double> expected = X_BA.transpose() * I_B.ToMatrix() * X_BA;
    // Entries up to m·|p|² ≈ 10·12: relative rounding of a few dozen operations.
    EXPECT_LE((X_AB.Apply(I_B).ToMatrix() - expected).cwiseAbs().maxCoeff(),
              256 * kEps * expected.cwiseAbs().maxCoeff());
    // The inertia times a motion matches the matrix product.
    const SpatialMotion<double> m(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
    EXPECT_LE(((I_B * m).get_coeffs() - I_B.ToMatrix() * m.get_coeffs()).cwiseAbs().maxCoeff(),
              64 * kEps * I_B.ToMatrix().cwiseAbs().maxCoeff());
  }
}

TEST_F(SpatialTest, CrossProductsMatchRbdaMatrices) {
  const SpatialMotion<double> m(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
  const SpatialMotion<double> n(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
  const SpatialForce<double> f(RandomVector(rng_, 1.0), RandomVector(rng_, 1.0));
  // crm(m) = [ω× 0; v× ω×] (RBDA ch. 2), crf(m) = −crm(m)ᵀ.
  Matrix6<double> crm = Matrix6<double>::Zero();
  crm.topLeftCorner<3, 3>() = Skew(m.rotational());
  crm.bottomRightCorner<3, 3>() = Skew(m.rotational());
  crm.bottomLeftCorner<3, 3>() = Skew(m.translational());
  EXPECT_LE((m.Cross(n).get_coeffs() - crm * n.get_coeffs()).cwiseAbs().maxCoeff(), 16 * kEps);
  EXPECT_LE((m.CrossForce(f).get_coeffs() + crm.transpose() * f.get_coeffs()).cwiseAbs().maxCoeff(),
            16 * kEps);
}

}  // namespace
}  // namespace acro::dynamics

namespace acro::dynamics {
namespace {

// The inlined sin/cos of the joint angles (fast_math.h) agrees with libm: a few ulps of 1 over
// the angles a body reaches (many turns), and libm itself beyond the fast range.
TEST(FastMathTest, SinCosMatchesLibm) {
  std::mt19937 rng(99);
  double worst = 0.0;
  for (double range : {1.0, 4.0, 100.0, 1e4, 1e5}) {
    std::uniform_real_distribution<double> u(-range, range);
    for (int i = 0; i < 200000; ++i) {
      const double x = u(rng);
      double s, c;
      internal::SinCos(x, &s, &c);
      worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
    }
  }
  // Quadrant boundaries and exact values.
  for (double x :
       {0.0, -0.0, M_PI / 4, M_PI / 2, M_PI, 3 * M_PI / 2, -M_PI / 2, 1e-300, 2e5, -3e7}) {
    double s, c;
    internal::SinCos(x, &s, &c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  }
  std::printf("fast sincos: worst absolute difference to libm %.3g\n", worst);
  // Reduction error (|k|·ulp of π/2's last part) plus the polynomial's ~1 ulp: 8 ulps of 1.
  EXPECT_LE(worst, 8 * kEps);
  // The array form, including a large angle handled by libm.
  const double xs[4] = {0.3, -2.0, 7e5, 1e6 + 0.5};
  double s[4], c[4];
  internal::SinCosArray(xs, 4, s, c);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(s[k], std::sin(xs[k]), 8 * kEps);
    EXPECT_NEAR(c[k], std::cos(xs[k]), 8 * kEps);
  }
}

}  // namespace
}  // namespace acro::dynamics
