// Which way is up (issue "real-data fidelity", item 3): the sample routine (Z up, a trampoline
// routine: upside down in every somersault) turned so that +Y, then −X, is up is recognised from
// its head and foot markers and turned back exactly; a Z-up file is left alone; the Pose2Sim
// balancing trial, which Pose2Sim writes Y up, is recognised as such; --up forces or refuses.

#include "acro/reconstruct/up_axis.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

const capture::Trial& Sample() {
  static const capture::Trial trial = capture::ReadTrial(
      acro::testing::SourceDir() / "samples/trials/trampoline_routine/trampoline_routine.c3d");
  return trial;
}

// The largest difference between two trials' points (gaps in the same places).
double Largest(const capture::Trial& a, const capture::Trial& b) {
  return (a.positions - b.positions)
      .array()
      .isNaN()
      .select(0, (a.positions - b.positions).array().abs())
      .maxCoeff();
}

TEST(UpAxis, ATurnedRoutineIsFoundAndTurnedBack) {
  for (const auto& [axis, sign, name] : {std::tuple{1, 1, "+Y"}, {0, -1, "-X"}}) {
    UpAxis truth;
    truth.axis = axis;
    truth.sign = sign;
    capture::Trial turned = Sample();
    capture::RotateTrial(RotationToZUp(truth).transpose(), &turned);  // Z up → `name` up
    const UpAxis found = DetectUpAxis(turned);
    ASSERT_TRUE(found.found) << name;
    EXPECT_EQ(found.Name(), name);
    std::printf("%s: upright in %.0f %% of %d frames\n", name, 100 * found.agreement, found.frames);
    // Upright in 47 % of the frames (the rest: somersaults, the lean of take-offs and landings),
    // the same whichever axis it was turned to.
    EXPECT_NEAR(found.agreement, 0.466, 0.001) << name;
    const std::string line = OrientTrialUp(&turned, "auto");
    EXPECT_NE(line.find("trampoline_routine.c3d"), std::string::npos) << line;
    EXPECT_NE(line.find(std::string(name) + " up"), std::string::npos) << line;
    EXPECT_LT(Largest(turned, Sample()), 1e-12) << name;
  }
}

TEST(UpAxis, AZUpFileIsLeftAlone) {
  capture::Trial trial = Sample();
  UpAxis found;
  EXPECT_EQ(OrientTrialUp(&trial, "auto", &found), "");
  EXPECT_TRUE(found.found);
  EXPECT_EQ(found.Name(), "+Z");
  EXPECT_EQ(Largest(trial, Sample()), 0.0);
  // Forced: --up y turns it even so (the user knows the file).
  EXPECT_NE(OrientTrialUp(&trial, "y").find("+Y up (as --up says)"), std::string::npos);
  EXPECT_GT(Largest(trial, Sample()), 1.0);
  try {
    OrientTrialUp(&trial, "w");
    ADD_FAILURE() << "--up w was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--up"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'w'"), std::string::npos) << e.what();
  }
}

TEST(UpAxis, PoseTwoSimWritesYUp) {
  const std::filesystem::path file = acro::testing::RefdataFile(
      "pose2sim-demo/balancing-trial/pose-3d/S00_P00_T01_BalancingTrial_0-100.trc");
  ACRO_REQUIRE_REFDATA_FILE(file);
  const capture::Trial trial = capture::ReadTrial(file);
  const UpAxis found = DetectUpAxis(trial);
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.Name(), "+Y");
  EXPECT_EQ(found.agreement, 1.0);  // a person standing on one leg
  EXPECT_EQ(found.frames, trial.num_frames);
}

}  // namespace
}  // namespace acro::analysis
