#include "acro/dynamics/reference_human.h"

#include <gtest/gtest.h>

#include <limits>

#include "acro/base/input_error.h"
#include "acro/dynamics/inverse_dynamics.h"

namespace acro::dynamics {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

TEST(ReferenceHumanTest, HasFifteenSegmentsAnd38Dof) {
  const Model<double> human = MakeReferenceHuman();
  ASSERT_EQ(human.num_segments(), 15);
  for (int i = 0; i < 15; ++i)
    EXPECT_EQ(human.segment(i).name, kReferenceHumanSegments[static_cast<size_t>(i)]);
  EXPECT_EQ(human.nv(), 38);
  EXPECT_EQ(human.nq(), 39);
  EXPECT_EQ(human.segment(0).joint_type, JointType::kFree);
  EXPECT_NEAR(human.total_mass(), 70.0, 64 * kEps * 70.0);
  EXPECT_GE(human.FindPoint("r_knee_jc"), 0);
  EXPECT_GE(human.FindPoint("head_vertex"), 0);
}

TEST(ReferenceHumanTest, StandingPoseIsPlausibleAndSymmetric) {
  const Model<double> human = MakeReferenceHuman();
  Workspace<double> ws(human);
  CalcForwardKinematics(human, ws, MakeNeutralConfiguration(human));
  const Eigen::Vector3d com = CalcCenterOfMassPosition(human, ws);
  const double sole = CalcPointPosition(human, ws, human.FindPoint("r_heel")).z();
  const double vertex = CalcPointPosition(human, ws, human.FindPoint("head_vertex")).z();
  // Standing height within 5 % of the stature, centre of mass at 52–60 % of it (Winter 2009).
  EXPECT_NEAR(vertex - sole, 1.75, 0.05 * 1.75);
  EXPECT_GT(com.z() - sole, 0.52 * 1.75);
  EXPECT_LT(com.z() - sole, 0.60 * 1.75);
  // Left–right symmetry: the centre of mass lies in the sagittal plane.
  EXPECT_NEAR(com.y(), 0.0, 64 * kEps);
  const Eigen::Vector3d r = CalcPointPosition(human, ws, human.FindPoint("r_fingertip"));
  const Eigen::Vector3d l = CalcPointPosition(human, ws, human.FindPoint("l_fingertip"));
  EXPECT_NEAR(r.y(), -l.y(), 64 * kEps);
  EXPECT_NEAR(r.z(), l.z(), 64 * kEps);
}

TEST(ReferenceHumanTest, ScalesWithHeightAndMass) {
  ReferenceHumanParameters p;
  p.height_m = 1.60;
  p.mass_kg = 50.0;
  const Model<double> human = MakeReferenceHuman(p);
  EXPECT_NEAR(human.total_mass(), 50.0, 64 * kEps * 50.0);
  EXPECT_NEAR(
      human.segment(10).X_PJ.translation().z(), -p.segments[9].length_fraction * 1.60, 4 * kEps);
}

TEST(ReferenceHumanTest, RejectsInvalidParameters) {
  ReferenceHumanParameters p;
  p.segments[4].mass_fraction += 0.01;
  std::string why;
  EXPECT_FALSE(p.IsValid(&why));
  EXPECT_NE(why.find("sum"), std::string::npos);
  EXPECT_THROW(MakeReferenceHuman(p), InputError);
  ReferenceHumanParameters q;
  q.height_m = -1.0;
  EXPECT_FALSE(q.IsValid(&why));
  EXPECT_NE(why.find("height_m"), std::string::npos);
}

}  // namespace
}  // namespace acro::dynamics
