#include "acro/athlete/standard_human.h"

#include <numbers>

#include <gtest/gtest.h>

#include "acro/athlete/de_leva.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = std::numbers::pi / 180.0;

// Whole-body inertia about the centre of mass from the dynamics engine: with the root spinning at
// unit rate about axis k (root at the origin, identity orientation), the centroidal angular
// momentum is column k of the centroidal inertia.
Eigen::Matrix3d CentroidalInertia(const dynamics::Model<double>& model, const Eigen::VectorXd& q) {
  dynamics::Workspace<double> ws(model);
  Eigen::Matrix3d I;
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
    v[3 + k] = 1.0;
    dynamics::CalcForwardKinematics(model, ws, q, v);
    I.col(k) = dynamics::CalcCentroidalMomentum(model, ws).rotational();
  }
  return I;
}

// Sets angle `axis` (0-based within the joint's sequence) of segment `name`.
void SetAngle(const dynamics::Model<double>& model,
              Eigen::VectorXd* q,
              const char* name,
              int axis,
              double value) {
  const int s = model.FindSegment(name);
  ASSERT_GE(s, 0) << name;
  (*q)[model.segment(s).q_start + axis] = value;
}

TEST(StandardHuman, HasTheFifteenSegmentsJointsAndPoints) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65, Sex::kFemale);
  const dynamics::Model<double> model = MakeStandardHumanModel(body);
  ASSERT_EQ(model.num_segments(), 15);
  EXPECT_EQ(model.nv(), 6 + 32);
  for (size_t i = 0; i < kStandardJoints.size(); ++i) {
    const int s = model.FindSegment(std::string(kStandardJoints[i].segment));
    ASSERT_GE(s, 0);
    EXPECT_EQ(model.segment(s).axis_sequence,
              i == 0 ? "" : std::string(kStandardJoints[i].axis_sequence));
  }
  EXPECT_NEAR(model.total_mass(), body.total.mass_kg, 16 * kEps * body.total.mass_kg);
  // Named points land where the body has them in the reference pose (root at H's origin).
  const Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(model);
  dynamics::Workspace<double> ws(model);
  dynamics::CalcForwardKinematics(model, ws, q);
  auto point = [&](const char* name) {
    const int p = model.FindPoint(name);
    EXPECT_GE(p, 0) << name;
    return dynamics::CalcPointPosition(model, ws, p);
  };
  auto seg = [&](const char* name) -> const BodySegment& {
    return body.segments[static_cast<size_t>(body.Find(name))];
  };
  EXPECT_LT((point("head_vertex") - seg("head").p_HoE_H).norm(), 64 * kEps);
  EXPECT_LT((point("l_knee_jc") - seg("l_shank").p_HoJ_H).norm(), 64 * kEps);
  EXPECT_LT((point("r_shoulder_jc") - seg("r_upper_arm").p_HoJ_H).norm(), 64 * kEps);
  EXPECT_LT((point("r_toe") - seg("r_foot").p_HoE_H).norm(), 64 * kEps);
  EXPECT_LT((point("l_thigh_com") - seg("l_thigh").in_H.p_HoCm_H).norm(), 64 * kEps);
  EXPECT_LT((dynamics::CalcCenterOfMassPosition(model, ws) - body.total.p_HoCm_H).norm(),
            64 * kEps);
}

// The engine's centroidal inertia in the tuck equals PoseAthleteBody's: the joint conventions of
// the model and of the body's posing agree (and two independent computations of the same number).
TEST(StandardHuman, TuckedModelMatchesThePosedBody) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const AthleteBody yeadon = MakeAthleteBodyFromYeadon(
      YeadonHuman::Make(ReadYeadonMeasurements(acro::testing::RefdataFile("yeadon/male1.txt"))));
  for (const AthleteBody& body : {MakeDeLevaBody(1.62, 55, Sex::kFemale), yeadon}) {
    const dynamics::Model<double> model = MakeStandardHumanModel(body);
    Eigen::VectorXd q = dynamics::MakeNeutralConfiguration(model);
    EXPECT_LT((CentroidalInertia(model, q) - body.total.I_Cm_H).norm(),
              1e3 * kEps * body.total.I_Cm_H.norm());
    for (const char* side : {"l", "r"}) {
      const std::string s(side);
      SetAngle(model, &q, (s + "_thigh").c_str(), 0, -140 * kDeg);  // hip flexion
      SetAngle(model, &q, (s + "_shank").c_str(), 0, 145 * kDeg);   // knee flexion
      SetAngle(model, &q, (s + "_upper_arm").c_str(), 0, -40 * kDeg);
      SetAngle(model, &q, (s + "_forearm").c_str(), 0, -90 * kDeg);
    }
    BodyPose tuck;
    tuck.angles_rad = {{"hip_flexion", 140 * kDeg},
                       {"knee_flexion", 145 * kDeg},
                       {"shoulder_flexion", 40 * kDeg},
                       {"elbow_flexion", 90 * kDeg}};
    const AthleteBody posed = PoseAthleteBody(body, tuck);
    EXPECT_LT((CentroidalInertia(model, q) - posed.total.I_Cm_H).norm(),
              1e3 * kEps * posed.total.I_Cm_H.norm())
        << body.model;
    // Abduction is the last hip angle ("yzx"): a straddle of 45° per leg.
    Eigen::VectorXd straddle = dynamics::MakeNeutralConfiguration(model);
    SetAngle(model, &straddle, "l_thigh", 2, 45 * kDeg);
    SetAngle(model, &straddle, "r_thigh", 2, -45 * kDeg);
    const AthleteBody spread = PoseAthleteBody(body, BodyPose{{{"hip_abduction", 45 * kDeg}}});
    EXPECT_LT((CentroidalInertia(model, straddle) - spread.total.I_Cm_H).norm(),
              1e3 * kEps * spread.total.I_Cm_H.norm());
  }
}

}  // namespace
}  // namespace acro::analysis
