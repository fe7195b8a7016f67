// Synchro pairs from two score sheets built here with the answer known: the landing-time
// difference per element on A's clock, the skills' and shapes' match, the pair scored up to the
// first element whose skills differ or the shorter routine's end, and the conversion a rule file
// sets (docs/scoring.md, "Synchro").
#include "acro/fig/synchro.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::fig {
namespace {

using D = SomersaultDirection;

// A routine of the given codes, each flight 1.5 s, landing `start_s` + 2 s × (k + 1).
RoutineScore Routine(const std::vector<std::pair<std::string, D>>& codes,
                     double start_s,
                     double extra_delay_s = 0.0) {
  std::vector<PerformedFlight> flights;
  for (size_t k = 0; k < codes.size(); ++k) {
    PerformedFlight f;
    f.skill = ParseFigCode(codes[k].first, codes[k].second);
    f.time_of_flight_s = 1.5;
    f.landing_s = start_s + 2.0 * double(k + 1) + extra_delay_s * double(k);
    flights.push_back(f);
  }
  return ScoreRoutine(RoutineRules::FigSenior(), flights);
}

const std::vector<std::pair<std::string, D>> kTen = {{"40o", D::kBackward},
                                                     {"40<", D::kBackward},
                                                     {"41/", D::kForward},
                                                     {"42/", D::kBackward},
                                                     {"800o", D::kBackward},
                                                     {"801o", D::kBackward},
                                                     {"41o", D::kForward},
                                                     {"803o", D::kForward},
                                                     {"43/", D::kForward},
                                                     {"44/", D::kBackward}};

TEST(Synchro, EqualRoutinesScoreFromTheirLandingDifferences) {
  const SynchroRules rules;  // 2.0 per element less 10 per second
  const SynchroScore s = ScoreSynchro(rules, Routine(kTen, 0.0), Routine(kTen, 0.040));
  ASSERT_EQ(s.elements.size(), 10u);
  for (const SynchroElement& e : s.elements) {
    EXPECT_TRUE(e.skills_match && e.shapes_match && e.counted);
    EXPECT_NEAR(e.landing_difference_s, 0.040, 1e-12);
    EXPECT_NEAR(e.points, 2.0 - 0.4, 1e-12);
  }
  EXPECT_EQ(s.ended_at_element, 0);
  EXPECT_TRUE(s.ending.empty());
  EXPECT_NEAR(s.score, 16.0, 1e-9);
  EXPECT_NEAR(s.mean_abs_difference_s, 0.040, 1e-12);
  // Perfectly together: the maximum. B early or late costs the same.
  EXPECT_NEAR(ScoreSynchro(rules, Routine(kTen, 0.0), Routine(kTen, 0.0)).score, 20.0, 1e-9);
  EXPECT_NEAR(ScoreSynchro(rules, Routine(kTen, 0.0), Routine(kTen, -0.040)).score, 16.0, 1e-9);
  // A difference past 0.2 s leaves the element nothing, never less.
  EXPECT_NEAR(ScoreSynchro(rules, Routine(kTen, 0.0), Routine(kTen, 0.5)).score, 0.0, 1e-12);
}

TEST(Synchro, ClockOffsetPutsBOnAsClock) {
  // B recorded 12.5 s later on its own clock: the offset brings it back.
  const SynchroScore s =
      ScoreSynchro(SynchroRules{}, Routine(kTen, 0.0), Routine(kTen, 12.5 + 0.02), -12.5);
  for (const SynchroElement& e : s.elements) EXPECT_NEAR(e.landing_difference_s, 0.02, 1e-9);
}

TEST(Synchro, DifferentSkillEndsThePairAtThatElement) {
  std::vector<std::pair<std::string, D>> b = kTen;
  b[3] = {"40<", D::kBackward};  // element 4: a back pike for the full
  const SynchroScore s = ScoreSynchro(SynchroRules{}, Routine(kTen, 0.0), Routine(b, 0.010));
  EXPECT_EQ(s.ended_at_element, 4);
  EXPECT_NE(s.ending.find("element 4"), std::string::npos) << s.ending;
  EXPECT_NE(s.ending.find("42/"), std::string::npos) << s.ending;
  EXPECT_NE(s.ending.find("40<"), std::string::npos) << s.ending;
  EXPECT_EQ(s.elements_counted, 3);
  EXPECT_FALSE(s.elements[3].skills_match);
  EXPECT_FALSE(s.elements[3].shapes_match);
  for (size_t k = 3; k < s.elements.size(); ++k) EXPECT_FALSE(s.elements[k].counted);
  EXPECT_NEAR(s.score, 3 * (2.0 - 0.1), 1e-9);
  // Same somersaults, another shape: the skills differ and the shapes too.
  b = kTen;
  b[0] = {"40<", D::kBackward};
  const SynchroScore t = ScoreSynchro(SynchroRules{}, Routine(kTen, 0.0), Routine(b, 0.0));
  EXPECT_EQ(t.ended_at_element, 1);
  EXPECT_EQ(t.elements_counted, 0);
  EXPECT_DOUBLE_EQ(t.score, 0.0);
}

TEST(Synchro, TheShorterRoutineEndsThePair) {
  const std::vector<std::pair<std::string, D>> six(kTen.begin(), kTen.begin() + 6);
  const SynchroScore s = ScoreSynchro(SynchroRules{}, Routine(kTen, 0.0), Routine(six, 0.0));
  EXPECT_EQ(s.elements_counted, 6);
  EXPECT_EQ(s.ended_at_element, 7);
  EXPECT_NE(s.ending.find("B ends after 6"), std::string::npos) << s.ending;
  EXPECT_NEAR(s.score, 12.0, 1e-9);
}

TEST(Synchro, RuleFileSetsTheConversion) {
  const RoutineRules r = ParseRules(
      "name: test\nsource: here\nsynchronisation:\n  element_points: 1.0\n  points_lost_per_s: 5\n"
      "  tolerance_s: 0.01\n  source: a national league's synchro rules\n",
      "test.yaml");
  EXPECT_DOUBLE_EQ(r.synchro.element_points, 1.0);
  EXPECT_EQ(r.synchro.source, "a national league's synchro rules");
  const SynchroScore s = ScoreSynchro(r.synchro, Routine(kTen, 0.0), Routine(kTen, 0.030));
  EXPECT_NEAR(s.score, 10 * (1.0 - 5 * 0.020), 1e-9);
  EXPECT_EQ(s.source, r.synchro.source);
  // Unknown keys, impossible values and a missing source are one line naming them.
  for (const char* bad : {"  element_point: 1\n  source: x\n",
                          "  element_points: -1\n  source: x\n",
                          "  points_lost_per_s: 1e9\n  source: x\n",
                          "  tolerance_s: 0.1\n"}) {
    SCOPED_TRACE(bad);
    try {
      ParseRules(std::string("name: t\nsource: s\nsynchronisation:\n") + bad, "bad.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.yaml"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace acro::fig
