#include "acro/athlete/yeadon_human.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = std::numbers::pi / 180.0;

// One row of refdata/yeadon/expected.md: whole-body values in yeadon's axes.
struct ExpectedRow {
  double mass_kg = 0;
  Eigen::Vector3d inertia_diagonal_yeadon_axes = Eigen::Vector3d::Zero();
  double com_z_m = 0;
};

// Reads the row of `set` ("Dempster", "Chandler", "Clauser") from expected.md in place:
// "| Dempster (default) | 58.2… | 9.63…, 9.99…, 0.545… | 0.0119… |".
ExpectedRow ReadExpected(const std::filesystem::path& path, const std::string& set) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| " + set, 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream row(line);
    std::string cell;
    while (std::getline(row, cell, '|')) cells.push_back(cell);
    // cells: "", name, mass, inertia, com z
    EXPECT_GE(cells.size(), 5u) << line;
    ExpectedRow out;
    out.mass_kg = std::stod(cells[2]);
    std::stringstream inertia(cells[3]);
    char comma = 0;
    inertia >> out.inertia_diagonal_yeadon_axes[0] >> comma >>
        out.inertia_diagonal_yeadon_axes[1] >> comma >> out.inertia_diagonal_yeadon_axes[2];
    out.com_z_m = std::stod(cells[4]);
    return out;
  }
  ADD_FAILURE() << "no row for " << set << " in " << path;
  return {};
}

class YeadonHumanReference : public ::testing::TestWithParam<DensitySet> {};

// The yeadon package's own asserted values for male1 (all angles zero) — reproduced in package-
// compatible mode to 1e-6 relative (the table gives 9–17 significant digits).
TEST_P(YeadonHumanReference, ReproducesThePackagesAssertedValues) {
  const auto meas_path = acro::testing::RefdataFile("yeadon/male1.txt");
  const auto expected_path = acro::testing::RefdataFile("yeadon/expected.md");
  ACRO_REQUIRE_REFDATA_FILE(meas_path);
  ACRO_REQUIRE_REFDATA_FILE(expected_path);
  std::string set(DensitySetName(GetParam()));
  set[0] = static_cast<char>(std::toupper(set[0]));
  const ExpectedRow expected = ReadExpected(expected_path, set);

  YeadonOptions options;
  options.density = GetParam();
  options.package_compatible = true;
  const YeadonHuman human = YeadonHuman::Make(ReadYeadonMeasurements(meas_path), options);
  const InertialProperties& total = human.total();
  EXPECT_NEAR(total.mass_kg, expected.mass_kg, 1e-6 * expected.mass_kg);
  EXPECT_NEAR(total.p_HoCm_H.z(), expected.com_z_m, 1e-6 * expected.com_z_m);
  // yeadon's x (left) is H's y, yeadon's y (posterior) is H's −x.
  const Eigen::Matrix3d C = YeadonAxesToBodyAxes();
  const Eigen::Matrix3d I_yeadon = C.transpose() * total.I_Cm_H * C;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(I_yeadon(k, k),
                expected.inertia_diagonal_yeadon_axes[k],
                1e-6 * expected.inertia_diagonal_yeadon_axes[k])
        << "axis " << k;
  }
  // Off-diagonal terms and lateral COM vanish (symmetric measurements): to rounding.
  const double scale = total.I_Cm_H.norm();
  EXPECT_NEAR(total.I_Cm_H(0, 1), 0.0, 100 * kEps * scale);
  EXPECT_NEAR(total.I_Cm_H(0, 2), 0.0, 100 * kEps * scale);
  EXPECT_NEAR(total.I_Cm_H(1, 2), 0.0, 100 * kEps * scale);
  EXPECT_NEAR(total.p_HoCm_H.x(), 0.0, 100 * kEps);
  EXPECT_NEAR(total.p_HoCm_H.y(), 0.0, 100 * kEps);
  EXPECT_TRUE(human.warnings().empty());
}

INSTANTIATE_TEST_SUITE_P(AllDensitySets,
                         YeadonHumanReference,
                         ::testing::Values(DensitySet::kDempster,
                                           DensitySet::kChandler,
                                           DensitySet::kClauser));

YeadonMeasurements Male1() {
  return ReadYeadonMeasurements(acro::testing::RefdataFile("yeadon/male1.txt"));
}

TEST(YeadonHuman, PackageModeDiffersInConeCentroidsAndLongAxisInertiaOnly) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonOptions package;
  package.package_compatible = true;
  const YeadonHuman a = YeadonHuman::Make(Male1(), package);
  const YeadonHuman b = YeadonHuman::Make(Male1());
  ASSERT_EQ(a.solids().size(), b.solids().size());
  for (size_t i = 0; i < a.solids().size(); ++i) {
    const YeadonSolid& sa = a.solids()[i];
    const YeadonSolid& sb = b.solids()[i];
    // Mass and the inertia about the solid's own axis do not depend on the centroid's end.
    EXPECT_NEAR(sa.in_S.mass_kg, sb.in_S.mass_kg, 8 * kEps * sa.in_S.mass_kg) << sa.label;
    EXPECT_NEAR(sa.in_S.I_Cm_H(2, 2), sb.in_S.I_Cm_H(2, 2), 8 * kEps * sa.in_S.I_Cm_H(2, 2));
    const bool cone = !sa.semi_ellipsoid && sa.t0_m == 0.0 && sa.t1_m == 0.0 && sa.r0_m != sa.r1_m;
    const double z_a = sa.in_S.p_HoCm_H.z(), z_b = sb.in_S.p_HoCm_H.z();
    if (cone) {
      // The package's centroid is the geometric one mirrored about the solid's mid-height; the
      // inertia about the centroid is the same.
      EXPECT_NEAR(z_a, sa.height_m - z_b, 16 * kEps * sa.height_m) << sa.label;
      EXPECT_LT((sa.in_S.I_Cm_H - sb.in_S.I_Cm_H).norm(), 64 * kEps * sa.in_S.I_Cm_H.norm());
    } else {
      EXPECT_NEAR(z_a, z_b, 8 * kEps * sa.height_m) << sa.label;
    }
  }
  // Geometric: a truncated cone's centroid lies on the side of its larger end.
  for (const YeadonSolid& s : b.solids()) {
    if (s.semi_ellipsoid || s.t0_m != 0.0 || s.t1_m != 0.0 || s.r0_m == s.r1_m) continue;
    const double z = s.in_S.p_HoCm_H.z();
    EXPECT_EQ(z<0.5 * s.height_m, s.r0_m> s.r1_m) << s.label;
  }
}

TEST(YeadonHuman, MeasuredMassScalesDensities) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonMeasurements m = Male1();
  const YeadonHuman plain = YeadonHuman::Make(m);
  m.total_mass_kg = 70.0;
  const YeadonHuman scaled = YeadonHuman::Make(m);
  const double ratio = 70.0 / plain.total().mass_kg;
  EXPECT_NEAR(scaled.total().mass_kg, 70.0, 16 * kEps * 70.0);
  EXPECT_NEAR(scaled.density_scale(), ratio, 4 * kEps * ratio);
  EXPECT_LT((scaled.total().p_HoCm_H - plain.total().p_HoCm_H).norm(), 1e3 * kEps);
  EXPECT_LT((scaled.total().I_Cm_H - ratio * plain.total().I_Cm_H).norm(),
            1e3 * kEps * scaled.total().I_Cm_H.norm());
}

TEST(YeadonHuman, WholeBodyRotationRotatesInertiaAndCentreOfMass) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const YeadonHuman rest = YeadonHuman::Make(Male1());
  YeadonConfiguration cfg;
  cfg.Set("somersault", 37 * kDeg);
  cfg.Set("tilt", -12 * kDeg);
  cfg.Set("twist", 71 * kDeg);
  const YeadonHuman turned = YeadonHuman::Make(Male1(), {}, cfg);
  // The whole body turns rigidly about H's origin: R = C·E123·Cᵀ.
  const Eigen::Matrix3d C = YeadonAxesToBodyAxes();
  const Eigen::Matrix3d E = (Eigen::AngleAxisd(37 * kDeg, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(-12 * kDeg, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(71 * kDeg, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  const Eigen::Matrix3d R = C * E * C.transpose();
  EXPECT_NEAR(turned.total().mass_kg, rest.total().mass_kg, 8 * kEps * rest.total().mass_kg);
  EXPECT_LT((turned.total().p_HoCm_H - R * rest.total().p_HoCm_H).norm(), 1e3 * kEps);
  EXPECT_LT((turned.total().I_Cm_H - R * rest.total().I_Cm_H * R.transpose()).norm(),
            1e3 * kEps * rest.total().I_Cm_H.norm());
}

TEST(YeadonHuman, FlexingTheHipsMovesTheLegsForwardAndShrinksTheSomersaultInertia) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const YeadonHuman straight = YeadonHuman::Make(Male1());
  YeadonConfiguration pike;
  pike.Set("PJ1extension", -90 * kDeg);  // hip flexion is a negative extension
  pike.Set("PK1extension", -90 * kDeg);
  const YeadonHuman piked = YeadonHuman::Make(Male1(), {}, pike);
  const int j2 = piked.FindSegment("J2");
  ASSERT_GE(j2, 0);
  // The shank points forward (+x in H) at hip level.
  EXPECT_GT(piked.segments()[static_cast<size_t>(j2)].in_H.p_HoCm_H.x(), 0.3);
  EXPECT_LT(std::abs(piked.segments()[static_cast<size_t>(j2)].in_H.p_HoCm_H.z()), 0.1);
  // Left-right symmetric: the somersault axis (H's y) is principal; its inertia drops.
  EXPECT_NEAR(piked.total().p_HoCm_H.y(), 0.0, 1e3 * kEps);
  EXPECT_LT(piked.total().I_Cm_H(1, 1), 0.75 * straight.total().I_Cm_H(1, 1));  // 0.68 for male1
  EXPECT_NEAR(piked.total().I_Cm_H(0, 1), 0.0, 1e3 * kEps);
}

TEST(YeadonHuman, AsymmetricMeasurementsWhenNotAveraged) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonOptions options;
  options.symmetric = false;
  const YeadonHuman human = YeadonHuman::Make(Male1(), options);
  const auto& seg = human.segments();
  // male1's right leg is heavier than its left (Lk1p 55 cm vs Lj1p 52 cm).
  EXPECT_GT(seg[static_cast<size_t>(human.FindSegment("K1"))].in_H.mass_kg,
            seg[static_cast<size_t>(human.FindSegment("J1"))].in_H.mass_kg);
  EXPECT_LT(human.total().p_HoCm_H.y(), 0.0);  // the centre of mass moves to the right (−y)
}

}  // namespace
}  // namespace acro::analysis
