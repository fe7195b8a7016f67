// The score sheet by the routine rules: which flights are the routine, a repeat's difficulty, T's
// truncation, H per landing, requirements each needing an element of their own, interruptions and
// a league's cap — each checked on routines built here with the answer known.
#include "acro/fig/score_sheet.h"

#include "acro/base/input_error.h"

#include <gtest/gtest.h>

#include "refdata.h"

namespace acro::fig {
namespace {

PerformedFlight Flight(const std::string& code,
                       SomersaultDirection dir,
                       double tof_s,
                       BodyPosition takeoff = BodyPosition::kFeet,
                       BodyPosition landing = BodyPosition::kFeet,
                       double deduction = 0.0) {
  PerformedFlight f;
  f.skill = ParseFigCode(code, dir);
  f.takeoff = takeoff;
  f.landing = landing;
  f.time_of_flight_s = tof_s;
  f.landing_zone = HdLanding{deduction == 0.0 ? "A" : "B", deduction, 0.1, false};
  return f;
}

using D = SomersaultDirection;

// Ten different elements of a senior routine, after two in-bounces.
std::vector<PerformedFlight> TenDifferent() {
  return {Flight("00", D::kNone, 1.2),
          Flight("00", D::kNone, 1.4),  // in-bounces: not elements
          Flight("822/", D::kBackward, 1.71),
          Flight("813<", D::kForward, 1.69),
          Flight("800<", D::kBackward, 1.70),
          Flight("821/", D::kBackward, 1.68),
          Flight("44/", D::kBackward, 1.66),
          Flight("43/", D::kForward, 1.65, BodyPosition::kFeet, BodyPosition::kFeet, 0.1),
          Flight("803<", D::kForward, 1.67),
          Flight("42/", D::kBackward, 1.62),
          Flight("41<", D::kForward, 1.60),
          Flight("40<", D::kBackward, 1.5467, BodyPosition::kFeet, BodyPosition::kFeet, 0.2)};
}

TEST(ScoreSheet, TenDifferentElementsScoreDTAndH) {
  const RoutineScore s = ScoreRoutine(RoutineRules::FigSenior(), TenDifferent());
  ASSERT_EQ(s.elements.size(), 10u);
  EXPECT_EQ(s.elements.front().flight, 3);
  EXPECT_FALSE(s.interrupted) << s.interruption;
  EXPECT_TRUE(s.valid());
  int tenths = 0;
  double tof = 0;
  for (const ScoredElement& e : s.elements) {
    EXPECT_TRUE(e.difficulty_counted);
    tenths += CalcFigDifficulty(ParseFigCode(e.code)).total_tenths();  // a second route to DD
    tof += e.time_of_flight_s;
  }
  EXPECT_NEAR(s.difficulty, tenths / 10.0, 1e-12);
  EXPECT_NEAR(s.time_of_flight_sum_s, 16.5267, 1e-9);
  EXPECT_NEAR(s.time_of_flight, 16.525, 1e-9);  // truncated, not rounded (16.5267 → 16.525)
  ASSERT_TRUE(s.horizontal_displacement);
  EXPECT_NEAR(*s.horizontal_displacement, 10.0 - 0.1 - 0.2, 1e-12);
  EXPECT_NEAR(s.total_without_execution, s.difficulty + 16.525 + 9.7, 1e-9);
}

TEST(ScoreSheet, TruncationKeepsAWholeStep) {
  // Ten flights of 1.6 s sum to 16.000000000000004 or 15.999999999999998 in doubles: 16.0 either
  // way.
  EXPECT_DOUBLE_EQ(TruncateTimeOfFlight(15.999999999999998, 0.005), 16.0);
  EXPECT_DOUBLE_EQ(TruncateTimeOfFlight(16.0049, 0.005), 16.0);
  EXPECT_NEAR(TruncateTimeOfFlight(16.0051, 0.005), 16.005, 1e-12);
  EXPECT_NEAR(TruncateTimeOfFlight(7.3219, 0.005), 7.32, 1e-12);
}

TEST(ScoreSheet, ARepeatedElementGetsNoDifficulty) {
  std::vector<PerformedFlight> f = TenDifferent();
  f[6] = Flight("822/", D::kBackward, 1.66);  // element 5 repeats element 1
  const RoutineScore s = ScoreRoutine(RoutineRules::FigSenior(), f);
  ASSERT_EQ(s.elements.size(), 10u);
  EXPECT_FALSE(s.elements[4].difficulty_counted);
  EXPECT_EQ(s.elements[4].note, "repeats element 1: no difficulty");
  EXPECT_FALSE(s.valid());
  ASSERT_EQ(s.rule_breaks.size(), 1u);
  EXPECT_NE(s.rule_breaks[0].find("element 5 (822/)"), std::string::npos) << s.rule_breaks[0];
  const RoutineScore clean = ScoreRoutine(RoutineRules::FigSenior(), TenDifferent());
  EXPECT_NEAR(
      s.difficulty, clean.difficulty - CalcFigDifficulty(ParseFigCode("44/")).total(), 1e-9);
  // The same code the other way round is another element.
  f = TenDifferent();
  f[6] = Flight("40<", D::kForward, 1.66);
  EXPECT_TRUE(ScoreRoutine(RoutineRules::FigSenior(), f).valid());
}

TEST(ScoreSheet, AnInterruptedRoutineIsScoredToItsLastElement) {
  std::vector<PerformedFlight> f = TenDifferent();
  f[9] = Flight("00", D::kNone, 1.1);  // a straight jump after element 7
  const RoutineScore s = ScoreRoutine(RoutineRules::FigSenior(), f);
  ASSERT_EQ(s.elements.size(), 7u);
  EXPECT_TRUE(s.interrupted);
  EXPECT_EQ(s.interruption, "a straight jump (flight 10) after 7 element(s)");
  ASSERT_TRUE(s.horizontal_displacement);
  EXPECT_NEAR(*s.horizontal_displacement, 7.0 - 0.1, 1e-12);  // the maximum is the elements done
  double tof = 0;
  for (size_t k = 2; k < 9; ++k) tof += f[k].time_of_flight_s;
  EXPECT_NEAR(s.time_of_flight_sum_s, tof, 1e-12);
  // A trial that ends early, and a flight cut by the recording.
  f = TenDifferent();
  f.resize(8);
  EXPECT_EQ(ScoreRoutine(RoutineRules::FigSenior(), f).interruption,
            "the routine ends after 6 of 10 elements");
  f = TenDifferent();
  f[5].partial = true;
  EXPECT_EQ(ScoreRoutine(RoutineRules::FigSenior(), f).elements.size(), 3u);
}

TEST(ScoreSheet, AgeGroupRequirementsEachNeedTheirOwnElement) {
  const RoutineRules rules =
      LoadRules(acro::testing::SourceDir() / "rules/fig-wagc-13-16-first-routine.yaml");
  // A routine meeting all four, each with an element of its own.
  std::vector<PerformedFlight> f = {
      Flight("42/", D::kBackward, 1.5),
      Flight("800o", D::kBackward, 1.6),
      Flight("41<", D::kForward, 1.5),
      Flight("43/", D::kForward, 1.5),  // rudolph: 540° twist, 360° somersault
      Flight("40<", D::kBackward, 1.5),
      Flight("41/", D::kForward, 1.5),
      Flight("40/", D::kBackward, 1.5),
      Flight("30o", D::kBackward, 1.4, BodyPosition::kFeet, BodyPosition::kBack),  // to back
      Flight("10o",
             D::kForward,
             1.2,
             BodyPosition::kBack,
             BodyPosition::kFeet),  // from back (below 270°)
      Flight("40o", D::kBackward, 1.5)};
  RoutineScore s = ScoreRoutine(rules, f);
  EXPECT_TRUE(s.requirements_missing.empty()) << s.requirements_missing.front();
  EXPECT_TRUE(s.rule_breaks.empty()) << s.rule_breaks.front();
  EXPECT_DOUBLE_EQ(s.penalty, 0.0);
  EXPECT_EQ(s.elements[1].requirements,
            std::vector<std::string>{"one double front or double back somersault"});
  // Without the double: that requirement missing, 1.0 off.
  f[1] = Flight("40/", D::kForward, 1.6);
  s = ScoreRoutine(rules, f);
  ASSERT_EQ(s.requirements_missing.size(), 1u);
  EXPECT_EQ(s.requirements_missing[0], "one double front or double back somersault");
  EXPECT_DOUBLE_EQ(s.penalty, 1.0);
  // One element cannot fulfil two requirements: a 1 3/4 double with 1½ twists ("803<", 8 quarters
  // and 3 half twists) alone is either the double or the twisting one, not both.
  f[1] = Flight("803<", D::kForward, 1.6);
  f[3] = Flight("40<", D::kForward, 1.5);
  s = ScoreRoutine(rules, f);
  EXPECT_EQ(s.requirements_missing.size(), 1u);
  // Two elements below 270° where one is allowed.
  f = {Flight("42/", D::kBackward, 1.5),
       Flight("800o", D::kBackward, 1.6),
       Flight("43/", D::kForward, 1.5),
       Flight("30o", D::kBackward, 1.4, BodyPosition::kFeet, BodyPosition::kBack),
       Flight("10o", D::kForward, 1.2, BodyPosition::kBack, BodyPosition::kFeet),
       Flight("01", D::kNone, 1.1),
       Flight("40<", D::kBackward, 1.5),
       Flight("41/", D::kForward, 1.5),
       Flight("40/", D::kBackward, 1.5),
       Flight("40o", D::kBackward, 1.5)};
  s = ScoreRoutine(rules, f);
  ASSERT_EQ(s.rule_breaks.size(), 1u);
  EXPECT_EQ(s.rule_breaks[0], "2 elements below 270° of somersault (at most 1)");
}

TEST(ScoreSheet, ALeaguesCapLimitsD) {
  const RoutineRules rules =
      LoadRules(acro::testing::SourceDir() / "rules/bg-league-2-voluntary.yaml");
  const RoutineScore s = ScoreRoutine(rules, TenDifferent());
  EXPECT_TRUE(s.difficulty_capped);
  EXPECT_DOUBLE_EQ(s.difficulty, 7.5);
  EXPECT_GT(s.difficulty_uncapped, 7.5);
}

TEST(ScoreSheet, NoBedNoH) {
  std::vector<PerformedFlight> f = TenDifferent();
  f[4].landing_zone.reset();
  EXPECT_FALSE(ScoreRoutine(RoutineRules::FigSenior(), f).horizontal_displacement);
}

// An element's measured faults: only the reported ones are summed, and at most 0.5 for one element.
TEST(ScoreSheet, ExecutionDeductionsAreTheReportedFaultsUpToHalfAPoint) {
  std::vector<PerformedFlight> f = TenDifferent();
  auto fault = [](const char* key, double deduction, bool reported) {
    MeasuredFault m;
    m.fault = key;
    m.deduction = deduction;
    m.reported = reported;
    return m;
  };
  f[2].faults = {fault("knees_bent", 0.2, true), fault("arms_out", 0.0, false)};
  f[3].faults = {
      fault("knees_bent", 0.3, true), fault("legs_apart", 0.2, true), fault("travel", 0.1, true)};
  const RoutineScore s = ScoreRoutine(RoutineRules::FigSenior(), f);
  EXPECT_DOUBLE_EQ(s.elements[0].execution_deduction, 0.2);
  EXPECT_EQ(s.elements[0].faults.size(), 2u);  // the unreported one is kept, with its value
  EXPECT_DOUBLE_EQ(s.elements[1].execution_deduction, 0.5);
  EXPECT_EQ(s.faults_reported, 4);
  EXPECT_DOUBLE_EQ(s.execution_deductions, 0.7);
}

}  // namespace
}  // namespace acro::fig

namespace acro::fig {
namespace {

// A planned routine as codes: spaces, commas and newlines separate them; a bad code, none at all
// or more than 100 are one line naming what is wrong.
TEST(ScoreSheet, PlannedFlightsFromCodes) {
  const std::vector<PerformedFlight> f = PlannedFlights(" 40o, 41/\n800o ");
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(FormatFigCode(f[1].skill), "41/");
  EXPECT_EQ(f[1].skill.direction, SomersaultDirection::kForward);  // one half twist: forward
  EXPECT_EQ(f[2].skill.direction, SomersaultDirection::kBackward);
  const RoutineScore s = ScoreRoutine(RoutineRules::FigSenior(), f);
  EXPECT_NEAR(s.difficulty, 0.5 + 0.6 + 1.1, 1e-9);
  EXPECT_TRUE(s.interrupted);
  for (const char* bad : {"", " , ", "40o 4x1/"}) {
    try {
      PlannedFlights(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      if (std::string(bad).find("4x1/") != std::string::npos) {
        EXPECT_NE(std::string(e.what()).find("4x1/"), std::string::npos) << e.what();
      }
    }
  }
  std::string many;
  for (int k = 0; k < 101; ++k) many += "40o ";
  EXPECT_THROW(PlannedFlights(many), InputError);
}

}  // namespace
}  // namespace acro::fig
