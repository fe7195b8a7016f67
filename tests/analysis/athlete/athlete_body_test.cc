#include "acro/athlete/athlete_body.h"

#include <numbers>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "acro/athlete/de_leva.h"
#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = std::numbers::pi / 180.0;

YeadonMeasurements Male1() {
  return ReadYeadonMeasurements(acro::testing::RefdataFile("yeadon/male1.txt"));
}

TEST(AthleteBody, YeadonGroupingKeepsEveryMassProperty) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const YeadonHuman human = YeadonHuman::Make(Male1());
  const AthleteBody body = MakeAthleteBodyFromYeadon(human);
  ASSERT_EQ(body.segments.size(), 15u);
  EXPECT_NEAR(body.total.mass_kg, human.total().mass_kg, 16 * kEps * human.total().mass_kg);
  EXPECT_LT((body.total.p_HoCm_H - human.total().p_HoCm_H).norm(), 1e3 * kEps);
  EXPECT_LT((body.total.I_Cm_H - human.total().I_Cm_H).norm(),
            1e3 * kEps * human.total().I_Cm_H.norm());
  // Chains are connected: each segment's joint is its parent's end, except the limbs' roots.
  auto seg = [&](const char* n) -> const BodySegment& {
    return body.segments[static_cast<size_t>(body.Find(n))];
  };
  EXPECT_LT((seg("l_forearm").p_HoJ_H - seg("l_upper_arm").p_HoE_H).norm(), 1e3 * kEps);
  EXPECT_LT((seg("r_shank").p_HoJ_H - seg("r_thigh").p_HoE_H).norm(), 1e3 * kEps);
  EXPECT_LT((seg("head").p_HoJ_H - seg("thorax").p_HoE_H).norm(), 1e3 * kEps);
  // The left side is at +y.
  EXPECT_GT(seg("l_thigh").p_HoJ_H.y(), 0.05);
  EXPECT_LT(seg("r_hand").in_H.p_HoCm_H.y(), -0.1);
}

// The generic posing of the 15-segment body and Yeadon's own configuration angles describe the
// same rigid rotations about the same joints: the whole-body inertia must agree.
TEST(AthleteBody, PosingAgreesWithYeadonsConfigurationAngles) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const AthleteBody rest = MakeAthleteBodyFromYeadon(YeadonHuman::Make(Male1()));
  BodyPose tuck;
  tuck.angles_rad = {{"hip_flexion", 140 * kDeg},
                     {"knee_flexion", 145 * kDeg},
                     {"shoulder_flexion", 40 * kDeg},
                     {"elbow_flexion", 90 * kDeg}};
  tuck.angles_rad["l_hip_abduction"] = 20 * kDeg;
  tuck.angles_rad["r_shoulder_abduction"] = 30 * kDeg;
  const AthleteBody posed = PoseAthleteBody(rest, tuck);

  YeadonConfiguration cfg;
  cfg.Set("PJ1extension", -140 * kDeg);
  cfg.Set("PK1extension", -140 * kDeg);
  cfg.Set("J1J2flexion", 145 * kDeg);
  cfg.Set("K1K2flexion", 145 * kDeg);
  cfg.Set("CA1extension", -40 * kDeg);
  cfg.Set("CB1extension", -40 * kDeg);
  cfg.Set("A1A2extension", -90 * kDeg);
  cfg.Set("B1B2extension", -90 * kDeg);
  // Abduction: yeadon's y is posterior, so the left hip's +y-axis rotation …
  cfg.Set("PJ1adduction", -20 * kDeg);  // … of −20° swings the left thigh outwards,
  cfg.Set("CB1abduction", 30 * kDeg);   // and +30° the right arm (CB1abduction) outwards.
  const AthleteBody expected = MakeAthleteBodyFromYeadon(YeadonHuman::Make(Male1(), {}, cfg));
  EXPECT_LT((posed.total.p_HoCm_H - expected.total.p_HoCm_H).norm(), 1e4 * kEps);
  EXPECT_LT((posed.total.I_Cm_H - expected.total.I_Cm_H).norm(),
            1e4 * kEps * expected.total.I_Cm_H.norm());
}

TEST(AthleteBody, TuckPikeStraightOrderTheSomersaultInertia) {
  const AthleteBody rest = MakeDeLevaBody(1.75, 65, Sex::kFemale);
  double inertia[3];
  const char* names[3] = {"straight", "pike", "tuck"};
  for (int i = 0; i < 3; ++i) {
    BodyPose pose;
    ASSERT_TRUE(MakeNamedPose(names[i], &pose));
    inertia[i] = SomersaultInertia(PoseAthleteBody(rest, pose));
  }
  EXPECT_GT(inertia[0], inertia[1]);
  EXPECT_GT(inertia[1], inertia[2]);
  // Plausibility bounds, not a published value: rigid-segment adult models give a layout/tuck
  // somersault-inertia ratio of roughly 2–4; outside that the pose or the layout is wrong.
  EXPECT_GT(inertia[0] / inertia[2], 2.0);
  EXPECT_LT(inertia[0] / inertia[2], 4.5);
}

TEST(AthleteBody, SomersaultTiltTwistTurnTheWholeBodyRigidly) {
  const AthleteBody rest = MakeDeLevaBody(1.80, 75, Sex::kMale);
  BodyPose pose;
  pose.angles_rad = {{"somersault", 1.0}, {"twist", 0.4}, {"tilt", -0.2}};
  const AthleteBody turned = PoseAthleteBody(rest, pose);
  // The body turns about H's origin by R = R_y(somersault) R_x(tilt) R_z(twist), built here with
  // Eigen's angle-axis: COM' = R COM and I' = R I Rᵀ.
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  EXPECT_LT((turned.total.p_HoCm_H - R * rest.total.p_HoCm_H).norm(), 1e3 * kEps);
  EXPECT_LT((turned.total.I_Cm_H - R * rest.total.I_Cm_H * R.transpose()).norm(),
            1e3 * kEps * rest.total.I_Cm_H.norm());
  EXPECT_THROW(PoseAthleteBody(rest, BodyPose{{{"wrist_flexion", 0.1}}}), InputError);
  EXPECT_THROW(PoseAthleteBody(rest, BodyPose{{{"l_somersault", 0.1}}}), InputError);
  EXPECT_TRUE(IsBodyPoseAngle("r_knee_flexion"));
  EXPECT_FALSE(IsBodyPoseAngle("x_knee_flexion"));
}

}  // namespace
}  // namespace acro::analysis
