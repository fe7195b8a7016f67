#include "acro/dynamics/model_builder.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::dynamics {
namespace {

MassProperties Box(double mass) {
  MassProperties m;
  m.mass_kg = mass;
  m.p_BoBcm_B = Eigen::Vector3d(0.0, 0.0, -0.2);
  m.I_BBcm_B = Eigen::Vector3d(0.05, 0.04, 0.02).asDiagonal();
  return m;
}

JointSpec Joint(const std::string& seq) {
  JointSpec j;
  j.axis_sequence = seq;
  j.p_PoJo_P = Eigen::Vector3d(0.0, 0.1, -0.4);
  return j;
}

// Runs f and returns the InputError message (empty if nothing was thrown).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Expects the message to be non-empty and to contain every part.
void ExpectMessage(const std::string& message, std::initializer_list<const char*> parts) {
  EXPECT_FALSE(message.empty()) << "no acro::InputError was thrown";
  for (const char* part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << message << " lacks " << part;
}

TEST(ModelBuilderTest, CountsCoordinatesAndIndices) {
  ModelBuilder b("trunk", Box(30.0));
  b.AddSegment("arm", "trunk", Joint("yxz"), Box(3.0));
  b.AddSegment("forearm", "arm", Joint("y"), Box(2.0));
  b.AddSegment("glove", "forearm", Joint(""), Box(0.5));
  b.AddSegment("leg", "trunk", Joint("zx"), Box(10.0));
  b.AddPoint("tip", "glove", Eigen::Vector3d(0.0, 0.0, -0.1));
  const Model<double> m = b.Build();
  EXPECT_EQ(m.num_segments(), 5);
  EXPECT_EQ(m.nq(), 7 + 3 + 1 + 2);
  EXPECT_EQ(m.nv(), 6 + 3 + 1 + 2);
  EXPECT_EQ(m.num_joint_dofs(), 6);
  EXPECT_EQ(m.segment(1).q_start, 7);
  EXPECT_EQ(m.segment(1).v_start, 6);
  EXPECT_EQ(m.segment(2).v_start, 9);
  EXPECT_EQ(m.segment(3).joint_type, JointType::kFixed);
  EXPECT_EQ(m.segment(4).v_start, 10);
  EXPECT_EQ(m.segment(4).axes[0], 2);
  EXPECT_EQ(m.segment(4).axes[1], 0);
  EXPECT_DOUBLE_EQ(m.total_mass(), 45.5);
  EXPECT_EQ(m.max_depth(), 4);
  EXPECT_EQ(m.FindSegment("leg"), 4);
  EXPECT_EQ(m.FindSegment("nope"), -1);
  EXPECT_EQ(m.FindPoint("tip"), 0);
  EXPECT_EQ(m.VelocityName(11), "leg:x");
  EXPECT_EQ(m.VelocityName(3), "trunk:wx");
  EXPECT_EQ(m.gravity_W(), Eigen::Vector3d(0.0, 0.0, -9.81));
}

TEST(ModelBuilderTest, RejectsBadInputNamingIt) {
  ModelBuilder b("trunk", Box(30.0));
  b.AddSegment("arm", "trunk", Joint("yxz"), Box(3.0));
  ExpectMessage(ErrorOf([&] { b.AddSegment("hand", "forarm", Joint("y"), Box(1.0)); }),
                {"'hand'", "unknown parent 'forarm'"});
  ExpectMessage(ErrorOf([&] { b.AddSegment("arm", "trunk", Joint("y"), Box(1.0)); }),
                {"'arm'", "duplicate"});
  ExpectMessage(ErrorOf([&] { b.AddSegment("x1", "trunk", Joint("yy"), Box(1.0)); }),
                {"'x1'", "'yy'"});
  ExpectMessage(ErrorOf([&] { b.AddSegment("x2", "trunk", Joint("xyzx"), Box(1.0)); }),
                {"more than 3"});
  ExpectMessage(ErrorOf([&] { b.AddSegment("x3", "trunk", Joint("xw"), Box(1.0)); }),
                {"other than x, y, z"});
  ExpectMessage(ErrorOf([&] { b.AddSegment("x4", "trunk", Joint("x"), Box(0.0)); }),
                {"'x4'", "mass must be positive"});
  MassProperties not_pd = Box(1.0);
  not_pd.I_BBcm_B(2, 2) = -0.01;
  ExpectMessage(ErrorOf([&] { b.AddSegment("x5", "trunk", Joint("x"), not_pd); }),
                {"not positive definite"});
  MassProperties triangle = Box(1.0);
  triangle.I_BBcm_B = Eigen::Vector3d(0.01, 0.01, 0.05).asDiagonal();
  ExpectMessage(ErrorOf([&] { b.AddSegment("x6", "trunk", Joint("x"), triangle); }),
                {"triangle inequality"});
  MassProperties asym = Box(1.0);
  asym.I_BBcm_B(0, 1) = 0.001;
  ExpectMessage(ErrorOf([&] { b.AddSegment("x7", "trunk", Joint("x"), asym); }), {"not symmetric"});
  JointSpec skewed = Joint("x");
  skewed.R_PJ(0, 1) = 0.1;
  ExpectMessage(ErrorOf([&] { b.AddSegment("x8", "trunk", skewed, Box(1.0)); }),
                {"not a rotation"});
  ExpectMessage(ErrorOf([&] { b.AddPoint("m1", "hand", Eigen::Vector3d::Zero()); }),
                {"'m1'", "unknown segment 'hand'"});
  b.AddPoint("m1", "arm", Eigen::Vector3d::Zero());
  ExpectMessage(ErrorOf([&] { b.AddPoint("m1", "trunk", Eigen::Vector3d::Zero()); }),
                {"'m1'", "duplicate"});
  // Nothing of the rejected segments was added.
  EXPECT_EQ(b.Build().num_segments(), 2);
}

TEST(ModelBuilderTest, AcceptsLimitingInertias) {
  // A thin rod (I = diag(1, 1, 0+)) is at the edge of the triangle inequality: accepted.
  ModelBuilder b("root", Box(1.0));
  MassProperties rod = Box(1.0);
  rod.I_BBcm_B = Eigen::Vector3d(0.1, 0.1, 1e-9).asDiagonal();
  EXPECT_NO_THROW(b.AddSegment("rod", "root", Joint("x"), rod));
  MassProperties plate = Box(1.0);
  plate.I_BBcm_B = Eigen::Vector3d(0.1, 0.2, 0.3).asDiagonal();
  EXPECT_NO_THROW(b.AddSegment("plate", "root", Joint("x"), plate));
}

TEST(ModelBuilderTest, CastKeepsEverything) {
  ModelBuilder b("trunk", Box(30.0));
  b.AddSegment("arm", "trunk", Joint("zy"), Box(3.0));
  const Model<double> m = b.Build();
  const Model<float> f = m.Cast<float>();
  EXPECT_EQ(f.nv(), m.nv());
  EXPECT_EQ(f.segment(1).axis_sequence, "zy");
  EXPECT_FLOAT_EQ(f.segment(1).mass, 3.0f);
  EXPECT_FLOAT_EQ(f.segment(1).X_PJ.translation().z(), -0.4f);
}

}  // namespace
}  // namespace acro::dynamics
