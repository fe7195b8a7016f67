#include "acro/athlete/de_leva.h"

#include <cmath>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// de Leva 1996, Table 4, restated here from the paper (independently of the library's table):
// segment, mass % {F, M}, CM % from the origin endpoint {F, M}.
struct Published {
  const char* segment;
  double mass_percent[2];
  double com_percent[2];
};
constexpr Published kPublished[] = {
    {"head", {6.68, 6.94}, {58.94, 59.76}},
    {"upper_trunk", {15.45, 15.96}, {20.77, 29.99}},
    {"mid_trunk", {14.65, 16.33}, {45.12, 45.02}},
    {"lower_trunk", {12.47, 11.17}, {49.20, 61.15}},
    {"upper_arm", {2.55, 2.71}, {57.54, 57.72}},
    {"forearm", {1.38, 1.62}, {45.59, 45.74}},
    {"hand", {0.56, 0.61}, {74.74, 79.00}},
    {"thigh", {14.78, 14.16}, {36.12, 40.95}},
    {"shank", {4.81, 4.33}, {44.16, 44.59}},
    {"foot", {1.29, 1.37}, {40.14, 44.15}},
};

// Fraction of the way from `origin` to `other` at which `p` lies (p on that line).
double Along(const Eigen::Vector3d& p,
             const Eigen::Vector3d& origin,
             const Eigen::Vector3d& other) {
  return (p - origin).dot(other - origin) / (other - origin).squaredNorm();
}

class DeLevaBySex : public ::testing::TestWithParam<Sex> {};

TEST_P(DeLevaBySex, SegmentMassesAndCentresOfMassFollowThePublishedTable) {
  const Sex sex = GetParam();
  const int k = sex == Sex::kFemale ? 0 : 1;
  const double mass = 65.0, height = 1.68;
  const AthleteBody body = MakeDeLevaBody(height, mass, sex);
  ASSERT_EQ(body.segments.size(), 15u);
  auto seg = [&](const char* name) -> const BodySegment& {
    return body.segments[static_cast<size_t>(body.Find(name))];
  };
  auto published = [&](const char* name) -> const Published& {
    for (const Published& p : kPublished)
      if (std::string(p.segment) == name) return p;
    ADD_FAILURE() << name;
    return kPublished[0];
  };
  // Limb segments: mass fraction and the centre of mass along proximal joint → distal end.
  for (const char* side : {"l_", "r_"}) {
    for (const char* limb : {"upper_arm", "forearm", "hand", "thigh", "shank"}) {
      const BodySegment& s = seg((std::string(side) + limb).c_str());
      const Published& p = published(limb);
      EXPECT_NEAR(s.in_H.mass_kg / mass, p.mass_percent[k] / 100.0, 4 * kEps) << limb;
      EXPECT_NEAR(Along(s.in_H.p_HoCm_H, s.p_HoJ_H, s.p_HoE_H), p.com_percent[k] / 100.0, 64 * kEps)
          << limb;
    }
    // Foot: HEEL → TTIP along +x, TTIP is the segment's end.
    const BodySegment& foot = seg((std::string(side) + "foot").c_str());
    const double L_foot = DeLevaRowOf("foot").length_mm[static_cast<size_t>(k)] / 1000.0 * height /
                          (DeLevaReferenceStatureMm(sex) / 1000.0);
    const Eigen::Vector3d heel = foot.p_HoE_H - Eigen::Vector3d(L_foot, 0, 0);
    EXPECT_NEAR(foot.in_H.mass_kg / mass, published("foot").mass_percent[k] / 100.0, 4 * kEps);
    EXPECT_NEAR(Along(foot.in_H.p_HoCm_H, heel, foot.p_HoE_H),
                published("foot").com_percent[k] / 100.0,
                64 * kEps);
  }
  // Pelvis = lower trunk, measured from OMPH (the pelvis' end) towards MIDH (its joint).
  const BodySegment& pelvis = seg("pelvis");
  EXPECT_NEAR(
      pelvis.in_H.mass_kg / mass, published("lower_trunk").mass_percent[k] / 100.0, 4 * kEps);
  EXPECT_NEAR(Along(pelvis.in_H.p_HoCm_H, pelvis.p_HoE_H, pelvis.p_HoJ_H),
              published("lower_trunk").com_percent[k] / 100.0,
              64 * kEps);
  // Thorax = upper + mid trunk: masses add, the centre of mass is their mass-weighted mean.
  const BodySegment& thorax = seg("thorax");
  const double m_u = published("upper_trunk").mass_percent[k],
               m_m = published("mid_trunk").mass_percent[k];
  EXPECT_NEAR(thorax.in_H.mass_kg / mass, (m_u + m_m) / 100.0, 4 * kEps);
  const double scale = height / (DeLevaReferenceStatureMm(sex) / 1000.0);
  const double L_u = DeLevaRowOf("upper_trunk").length_mm[static_cast<size_t>(k)] / 1000.0 * scale;
  const double L_m = DeLevaRowOf("mid_trunk").length_mm[static_cast<size_t>(k)] / 1000.0 * scale;
  const double supr = thorax.p_HoE_H.z();
  const double z_u = supr - published("upper_trunk").com_percent[k] / 100.0 * L_u;
  const double z_m = supr - L_u - published("mid_trunk").com_percent[k] / 100.0 * L_m;
  EXPECT_NEAR(thorax.in_H.p_HoCm_H.z(), (m_u * z_u + m_m * z_m) / (m_u + m_m), 64 * kEps);
  // Head: from the vertex (the head segment's end) down its table length.
  const BodySegment& head = seg("head");
  const double L_head = DeLevaRowOf("head").length_mm[static_cast<size_t>(k)] / 1000.0 * scale;
  EXPECT_NEAR(head.in_H.mass_kg / mass, published("head").mass_percent[k] / 100.0, 4 * kEps);
  EXPECT_NEAR((head.p_HoE_H.z() - head.in_H.p_HoCm_H.z()) / L_head,
              published("head").com_percent[k] / 100.0,
              64 * kEps);
  // Whole body: the table's fractions sum to 100 % (male) and 99.99 % (female, rounding).
  EXPECT_NEAR(body.total.mass_kg / mass, sex == Sex::kMale ? 1.0 : 0.9999, 64 * kEps);
  // Standing height: vertex above the sole.
  const double sole = seg("l_foot").p_HoE_H.z();
  EXPECT_NEAR(head.p_HoE_H.z() - sole, height, 64 * kEps);
  // Left-right symmetry: no lateral centre of mass, no products of inertia with y.
  EXPECT_NEAR(body.total.p_HoCm_H.y(), 0.0, 64 * kEps);
  EXPECT_NEAR(body.total.I_Cm_H(0, 1), 0.0, 1e3 * kEps);
}

INSTANTIATE_TEST_SUITE_P(BothSexes, DeLevaBySex, ::testing::Values(Sex::kFemale, Sex::kMale));

TEST(DeLeva, MeasuredLengthsReplaceScaledOnes) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65, Sex::kFemale, {{"thigh", 0.40}});
  const BodySegment& thigh = body.segments[static_cast<size_t>(body.Find("r_thigh"))];
  EXPECT_NEAR((thigh.p_HoE_H - thigh.p_HoJ_H).norm(), 0.40, 8 * kEps);
  // Inertia about the thigh's transverse axis: m (r L)² with r = 36.4 % (female).
  const double m = 0.1478 * 65;
  EXPECT_NEAR(thigh.in_H.I_Cm_H(1, 1), m * std::pow(0.364 * 0.40, 2), 1e3 * kEps);
}

TEST(DeLeva, BadInputsAreNamed) {
  EXPECT_THROW(MakeDeLevaBody(0.0, 65, Sex::kMale), InputError);
  EXPECT_THROW(MakeDeLevaBody(1.7, -1, Sex::kMale), InputError);
  try {
    MakeDeLevaBody(1.7, 60, Sex::kMale, {{"tibia", 0.4}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("segment_lengths_m.tibia"), std::string::npos);
  }
}

}  // namespace
}  // namespace acro::analysis
