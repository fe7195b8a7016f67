// Routines from their FIG codes (docs/skill-design.md, "Routines"): the composition refused where
// FIG or the athlete's reach says no, with one line naming the skill; the flights chosen so that
// one contact can give the next; the skills flown one after the other through the bed obey
// physics in every flight and join without a jump at every take-off and landing.

#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/design/routine_design.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::filesystem::path Athlete() {
  return acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
}

// The one-line message DesignRoutine throws, or "" when it does not.
std::string Refusal(const RoutineSpec& spec) {
  try {
    DesignRoutine(spec, {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RoutineDesign, FlightsRiseAheadOfASkillThatNeedsMoreThanOneContactGives) {
  const std::vector<double> T = ChooseFlightTimes({1.2, 1.45, 1.85, 1.45}, 0.25);
  ASSERT_EQ(T.size(), 4u);
  EXPECT_DOUBLE_EQ(T[3], 1.45);  // lower later: a contact takes the energy
  EXPECT_DOUBLE_EQ(T[2], 1.85);
  EXPECT_DOUBLE_EQ(T[1], 1.60);  // 1.85 − 0.25
  EXPECT_DOUBLE_EQ(T[0], 1.35);
}

TEST(RoutineDesign, ARepeatedSkillIsRefusedNamingIt) {
  const std::string why = Refusal(RoutineSpecFromCodes("40o 41/ 40o", Athlete()));
  EXPECT_NE(why.find("skill 3 (40o): repeats skill 1 (40o)"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos);
  // 40o and 40< are two skills.
  EXPECT_EQ(RoutineSpecFromCodes("40o, 40<", Athlete()).skills.size(), 2u);
}

TEST(RoutineDesign, ACodeItCannotBuildIsRefusedNamingTheSkill) {
  const std::string why = Refusal(RoutineSpecFromCodes("40o 4x2", Athlete()));
  EXPECT_NE(why.find("skill 2 (4x2): "), std::string::npos) << why;
  EXPECT_THROW(RoutineSpecFromCodes("  , ", Athlete()), InputError);
}

TEST(RoutineDesign, ASkillTheAthleteCannotReachIsRefusedNamingIt) {
  // A quadruple somersault in 1.2 s of flight (a routine file can set a skill's flight time).
  const auto dir = acro::testing::ScratchDir("routine_file");
  std::ofstream(dir / "athlete.yaml")
      << std::ifstream(Athlete()).rdbuf();  // the athlete beside the routine, found relative to it
  std::ofstream(dir / "routine.yaml") << "name: too much\n"
                                         "athlete: athlete.yaml\n"
                                         "skills:\n"
                                         "  - 40o\n"
                                         "  - code: 160000o\n"
                                         "    flight_time_s: 1.2\n";
  const RoutineSpec spec = ReadRoutineSpec(dir / "routine.yaml");
  ASSERT_EQ(spec.skills.size(), 2u);
  EXPECT_EQ(spec.name, "too much");
  EXPECT_DOUBLE_EQ(spec.skills[1].flight_time_s, 1.2);
  const std::string why = Refusal(spec);
  EXPECT_NE(why.find("routine.yaml: line 5 (160000o): not feasible: needs a somersault angular "
                     "momentum of"),
            std::string::npos)
      << why;
  // A misspelt key names its line.
  std::ofstream(dir / "typo.yaml") << "athlete: athlete.yaml\nskills:\n  - code: 40o\n"
                                      "    flight_time: 1.5\n";
  try {
    ReadRoutineSpec(dir / "typo.yaml");
    ADD_FAILURE() << "a misspelt key was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flight_time"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  }
}

// Three skills through the bed: every flight turns its skill's rotation, keeps its angular
// momentum and falls at g; phases join C¹; the pushes stay within reach; the DD adds up.
TEST(RoutineDesign, ThreeSkillsFlyThroughTheBed) {
  const RoutineDesignResult r = DesignRoutine(RoutineSpecFromCodes("40o 41/ 800<", Athlete()), {});
  ASSERT_EQ(r.skills.size(), 3u);
  const SimulatedRoutine& sim = r.simulation;
  ASSERT_EQ(sim.flights.size(), 3u);
  ASSERT_EQ(sim.contacts.size(), 4u);
  EXPECT_NEAR(r.difficulty, 0.5 + 0.6 + 1.3, 1e-9);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_EQ(r.notes[0], "3 skills: a FIG routine has 10");
  // The rotation each flight turns in the air: the nominal less what the bed does (15° + 30° for
  // singles, 30° + 45° for doubles), backward negative; the barani's half twist.
  const double air_deg[3] = {-(360 - 45), 360 - 45, -(720 - 75)};
  const double twist_deg[3] = {0, 180, 0};
  double tof = 0;
  for (size_t i = 0; i < 3; ++i) {
    const RoutineFlightTruth& f = sim.flights[i];
    EXPECT_NEAR(f.air_somersault_rad * 180 / kPi, air_deg[i], 1e-3) << f.fig_code;
    EXPECT_NEAR(std::abs(f.air_twist_rad) * 180 / kPi, twist_deg[i], 1e-3) << f.fig_code;
    // The flight lasts what its design asked for, within the feet's height at take-off and landing.
    EXPECT_NEAR(f.landing_s - f.takeoff_s, r.skills[i].flight_time_s, 0.02) << f.fig_code;
    const RoutineFlightPhysics p =
        CheckRoutineFlight(sim.model, sim.q, sim.v, sim.options.point_rate_hz, f);
    EXPECT_GT(p.num_frames, 150);
    EXPECT_LT(p.max_relative_momentum_drift, 1e-6) << f.fig_code;
    EXPECT_NEAR(p.fitted_vertical_acceleration_m_per_s2, -sim.gravity_m_per_s2, 1e-6);
    EXPECT_LT(p.max_horizontal_velocity_change_m_per_s, 1e-6);
    // Landed near the bed's centre, where every skill aims.
    EXPECT_LT((f.landing_feet_m - sim.options.bed_centre_m).head<2>().norm(), 0.05) << f.fig_code;
    tof += f.landing_s - f.takeoff_s;
  }
  EXPECT_NEAR(r.time_of_flight_s, tof, 1e-12);
  for (size_t i = 1; i < 3; ++i) {
    EXPECT_LE(std::abs(sim.contacts[i].push_rad), RoutineDesignOptions().max_push_rad);
    EXPECT_LT(std::abs(sim.contacts[i].takeoff_velocity_error_m_per_s), 1e-6);
  }
  EXPECT_LT(sim.max_boundary_position_jump_m, 1e-9);
  EXPECT_LT(sim.max_boundary_velocity_jump_m_per_s, 1e-9);
  EXPECT_LT(sim.max_boundary_orientation_jump_rad, 1e-9);
  EXPECT_LT(sim.max_boundary_angular_velocity_jump_rad_per_s, 1e-6);
  EXPECT_LT(sim.max_boundary_joint_jump_rad, 1e-9);
}

}  // namespace
}  // namespace acro::analysis
