// OpenSim .mot/.sto reading and writing, checked on OpenSim's own reference outputs.
#include "acro/capture/storage.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::capture {
namespace {

TEST(Storage, ReadsOpenSimInverseDynamicsOutput) {
  const auto path = acro::testing::RefdataFile(
      "opensim-models/Pipelines/Gait10dof18musc/OutputReference/ID/Results/subject01_walk_ID.sto");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Storage table = ReadStorage(path);
  EXPECT_EQ(table.name, "Inverse Dynamics Generalized Forces");
  EXPECT_FALSE(table.in_degrees);
  ASSERT_EQ(table.time_s.size(), 151);      // nRows=151
  ASSERT_EQ(table.labels.size() + 1, 11u);  // nColumns=11 including time
  // Values from the file's own summary (opensim-models/expected.md).
  const int tilt = table.FindColumn("pelvis_tilt_moment");
  ASSERT_GE(tilt, 0);
  EXPECT_NEAR(table.data(0, tilt), 2.021226, 1e-6);
  EXPECT_NEAR(table.data(150, table.FindColumn("ankle_angle_r_moment")), -123.114030, 1e-6);
  EXPECT_NEAR(table.time_s[0], -5e-07, 1e-12);
}

TEST(Storage, ReadsIkInDegreesAndGrfWithTrailingTabs) {
  const auto ik = acro::testing::RefdataFile(
      "opensim-models/Pipelines/Gait2354_Simbody/OutputReference/subject01_walk1_ik.mot");
  const auto grf = acro::testing::RefdataFile(
      "opensim-models/Pipelines/Gait2354_Simbody/subject01_walk1_grf.mot");
  ACRO_REQUIRE_REFDATA_FILE(ik);
  ACRO_REQUIRE_REFDATA_FILE(grf);
  const Storage angles = ReadStorage(ik);
  EXPECT_TRUE(angles.in_degrees);
  EXPECT_EQ(angles.time_s.size(), 73);
  EXPECT_EQ(angles.labels.size() + 1, 24u);
  const Storage forces = ReadStorage(grf);
  EXPECT_EQ(forces.time_s.size(), 1501);
  EXPECT_EQ(forces.labels.size() + 1, 19u);
}

TEST(Storage, WriteReadRoundTripIsExact) {
  Storage table;
  table.name = "joint angles";
  table.labels = {"hip_flexion_r", "knee_angle_r"};
  table.in_degrees = true;
  table.time_s = Eigen::VectorXd::LinSpaced(5, 0.0, 0.04);
  table.data.resize(5, 2);
  table.data << 1.0 / 3, -2.5, 10, 20, 1e-12, 3e8, std::nan(""), 4, 5, 6;
  for (StorageFlavor flavor : {StorageFlavor::kMot, StorageFlavor::kSto}) {
    const std::string text = WriteStorageToString(table, flavor);
    const Storage back = ReadStorageFromString(text, "t.mot");
    EXPECT_EQ(back.name, table.name);
    EXPECT_TRUE(back.in_degrees);
    EXPECT_EQ(back.labels, table.labels);
    EXPECT_EQ(back.time_s, table.time_s);
    EXPECT_TRUE(std::isnan(back.data(3, 0)));
    Eigen::MatrixXd a = back.data, b = table.data;
    a(3, 0) = b(3, 0) = 0;
    EXPECT_EQ(a, b);  // shortest round-trip formatting: exact
  }
  EXPECT_NE(WriteStorageToString(table, StorageFlavor::kMot).find("nRows=5\nnColumns=3\n"),
            std::string::npos);
}

TEST(Storage, RejectsMissingEndheaderAndRaggedRows) {
  EXPECT_THROW(ReadStorageFromString("name\nversion=1\ntime\ta\n0\t1\n", "a.mot"), InputError);
  try {
    ReadStorageFromString("n\nendheader\ntime\ta\tb\n0\t1\t2\n1\t2\n", "b.sto");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "b.sto: line 5: 2 columns where the labels name 3");
  }
}

}  // namespace
}  // namespace acro::capture
