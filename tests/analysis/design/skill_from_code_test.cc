// Skills designed from their FIG code (docs/skill-design.md, "Skills from their code"): the
// keyframes come from a simulated flight that turns the code's rotation, Model 1 makes the spline
// motion through them physically consistent, and the flight simulation of the result lands as
// designed.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/design/skill_from_code.h"
#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::filesystem::path Athlete() {
  return acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
}

class FromCode : public ::testing::TestWithParam<const char*> {};

TEST_P(FromCode, IsDesignedConsistentAndLandsAsDesigned) {
  const std::string code = GetParam();
  const auto t0 = std::chrono::steady_clock::now();
  const SkillFromCodeResult r = DesignSkillFromCode(code, Athlete());
  const fig::FigSkill fig = fig::ParseFigCode(code);
  // The shooting turned the code's rotation: the somersault short of the nominal by the bed's
  // share (45° for singles, 75° for multiples), the code's half twists in each somersault.
  const int n = fig.quarter_somersaults / 4;
  const double bed_deg = n == 0 ? 0.0 : n == 1 ? 45.0 : 75.0;
  // (A jump has no momentum; its arms alone turn it by a few degrees.)
  EXPECT_NEAR(
      std::abs(r.air_somersault_rad), (360.0 * n - bed_deg) * kDeg, n == 0 ? 5 * kDeg : 1e-5)
      << code;
  ASSERT_EQ(r.half_twists_per_somersault.size(), fig.half_twists.size()) << code;
  for (size_t k = 0; k < fig.half_twists.size(); ++k)
    EXPECT_NEAR(r.half_twists_per_somersault[k], fig.half_twists[k], 0.05) << code << " " << k;
  EXPECT_EQ(r.difficulty.total_tenths(), fig::CalcFigDifficulty(fig).total_tenths());
  EXPECT_EQ(r.skill.fig_code, fig::FormatFigCode(fig));
  ASSERT_GE(r.skill.keyframes.size(), 3u);

  // Model 2, then Model 1: the angular momentum constant within 2 %, every keyframe within its
  // tolerances; the simulated flight lands within 15° of the landing keyframe.
  const SkillDesign design(r.skill);
  SkillOptimizationOptions o;
  o.model = SkillModel::kTrajectory;
  const SkillOptimizationResult opt = OptimizeSkill(design, o);
  const SkillSimulationResult sim = SimulateSkill(design, opt.optimized);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("| `%s` | %.2f | %.3f | %.1f | %.1f | %.1f | %.3f %% | %.1f° | %.2f s |\n",
              code.c_str(),
              r.takeoff_vertical_velocity_mps,
              r.flight_time_s,
              r.somersault_momentum,
              r.twist_momentum,
              r.difficulty.total(),
              100 * opt.angular_momentum_variation,
              sim.final_orientation_error_rad / kDeg,
              seconds);
  EXPECT_LE(opt.angular_momentum_variation, 0.02) << code;
  EXPECT_LE(opt.max_joint_deviation_rad, 5 * kDeg + 1e-9) << code;
  EXPECT_LE(opt.max_orientation_deviation_rad, 5 * kDeg + 1e-9) << code;
  EXPECT_LE(sim.final_orientation_error_rad, 15 * kDeg) << code;
  EXPECT_NEAR(sim.somersault_turns, sim.intended_somersault_turns, 15.0 / 360) << code;
  EXPECT_NEAR(sim.twist_turns, sim.intended_twist_turns, 0.25) << code;

  // The generated file reads back as the same skill.
  const auto dir = std::filesystem::temp_directory_path() / "acro_skill_from_code";
  std::filesystem::create_directories(dir);
  const auto file = dir / "skill.yaml";
  WriteSkill(file, r.skill);
  const Skill back = ReadSkill(file);
  ASSERT_EQ(back.keyframes.size(), r.skill.keyframes.size());
  EXPECT_NEAR(back.flight_time_s, r.skill.flight_time_s, 1e-12);
  EXPECT_NEAR(back.keyframes.back().twist_rad, r.skill.keyframes.back().twist_rad, 1e-9);
}

// The list (docs/skill-design.md, "Skills from their code").
INSTANTIATE_TEST_SUITE_P(Codes,
                         FromCode,
                         ::testing::Values("00",
                                           "40o",
                                           "40<",
                                           "40/",
                                           "41/",
                                           "42/",
                                           "43/",
                                           "44/",
                                           "800o",
                                           "800<",
                                           "801o",
                                           "801<",
                                           "811o",
                                           "821o",
                                           "822/",
                                           "831<",
                                           "12001o"));

TEST(SkillFromCode, CodesItCannotBuildAreOneLine) {
  for (const char* code : {"4x/", "41", "50o", "1000o/", "20001o", "8x"}) {
    try {
      DesignSkillFromCode(code, Athlete());
      ADD_FAILURE() << code << " was designed";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_NE(what.find(code), std::string::npos) << what;
    }
  }
}

TEST(SkillFromCode, AQuadrupleInOnePointTwoSecondsIsNotFeasible) {
  SkillFromCodeOptions o;
  o.flight_time_s = 1.2;
  bool refused = false;
  try {
    const SkillFromCodeResult r = DesignSkillFromCode("160000o", Athlete(), o);
    refused = !r.feasible();
    for (const std::string& why : r.not_feasible) std::printf("%s\n", why.c_str());
  } catch (const InputError& e) {
    refused = true;  // no flight at all turns it
    std::printf("%s\n", e.what());
  }
  EXPECT_TRUE(refused);
}

}  // namespace
}  // namespace acro::analysis
