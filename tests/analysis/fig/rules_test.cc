// Rule files: the shipped ones load and cite a source; a typo or an impossible value is one line
// naming the file, the line and the key.
#include "acro/fig/rules.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::fig {
namespace {

TEST(Rules, EveryShippedRuleFileLoadsAndCitesItsSource) {
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(acro::testing::SourceDir() / "rules")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    const RoutineRules r = LoadRules(e.path());
    EXPECT_FALSE(r.name.empty());
    EXPECT_GT(r.source.size(), 40u);
    std::string why;
    EXPECT_TRUE(r.IsValid(&why)) << why;
    ++files;
  }
  EXPECT_GE(files, 4);
  const RoutineRules senior = LoadRules(acro::testing::SourceDir() / "rules/fig-2025-senior.yaml");
  EXPECT_EQ(senior.elements, 10);
  EXPECT_TRUE(senior.different_elements);
  EXPECT_DOUBLE_EQ(senior.time_of_flight_step, 0.005);
  ASSERT_EQ(senior.zones.zones.size(), 3u);
  EXPECT_DOUBLE_EQ(senior.zones.zones[0].x_max, 1.075);
  const RoutineRules age =
      LoadRules(acro::testing::SourceDir() / "rules/fig-wagc-13-16-first-routine.yaml");
  ASSERT_EQ(age.requirements.size(), 4u);
  EXPECT_EQ(age.requirements[2].min_quarter_somersaults, 8);
  EXPECT_EQ(age.max_elements_below_270, 1);
  const RoutineRules league =
      LoadRules(acro::testing::SourceDir() / "rules/bg-league-2-voluntary.yaml");
  ASSERT_TRUE(league.max_difficulty);
  EXPECT_DOUBLE_EQ(*league.max_difficulty, 7.5);
}

std::string Problem(const std::string& text) {
  try {
    ParseRules(text, "club.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Rules, MistakesAreOneLineNamingFileLineAndKey) {
  const std::string head = "name: club\nsource: our club's own rules, 2026\n";
  struct Case {
    std::string text, must_contain;
  };
  const Case cases[] = {
      {head + "routine:\n  elementz: 10\n", "elementz"},
      {head + "routine:\n  elements: 0\n", "line 4"},
      {head + "routine:\n  elements: 10\n  max_difficulty: -1\n", "max_difficulty"},
      {head + "routine:\n  elements: 8\n  max_elements_below_270: 9\n", "max_elements_below_270"},
      {head + "routine:\n  difficulty: some\n", "'some' is not a difficulty rule"},
      {head + "requirements:\n  - {name: x, direction: sideways}\n", "sideways"},
      {head + "requirements:\n  - {name: x, landing: seat}\n", "'seat' is not a position"},
      {head + "requirements:\n  - {name: x, twists: 2}\n", "twists"},
      {head + "time_of_flight: {truncate_to: 0}\n", "truncate_to"},
      {head + "horizontal_displacement:\n  source: s\n  zones:\n    - {name: A, x_m: [1, -1], y_m: "
              "[-0.5, 0.5], deduction: 0}\n"
              "  outside: {name: out, deduction: 0.3}\n",
       "[1, -1] is empty"},
      {head + "horizontal_displacement:\n  source: s\n  zones:\n    - {name: A, x_m: [-1, 1], y_m: "
              "[-0.5, 0.5], deduction: 5}\n"
              "  outside: {name: out, deduction: 0.3}\n",
       "deduction"},
      {head + "execution:\n  knees_bnt: [[15, 0.1]]\n", "unknown fault"},
      {head + "execution:\n  knees_bent: [[45, 0.1], [15, 0.2]]\n", "thresholds must rise"},
      {head + "execution:\n  late_opening: [[0.1, 0.1], [0.3, 0.2]]\n", "thresholds must fall"},
      {head + "execution:\n  travel: [[0.3, 0.9]]\n", "a deduction of 0 to 0.5"},
      {"name: club\nsource: \"\"\n", "say where the rules come from"},
      {"- a list\n", "a rule file is a map"},
  };
  for (const Case& c : cases) {
    const std::string p = Problem(c.text);
    EXPECT_NE(p.find("club.yaml"), std::string::npos) << c.text << "\n→ " << p;
    EXPECT_NE(p.find(c.must_contain), std::string::npos) << c.text << "\n→ " << p;
    EXPECT_EQ(p.find('\n'), std::string::npos) << p;
  }
}

// A club's own thresholds replace one fault's steps and keep the others.
TEST(Rules, AClubsExecutionThresholdsReplaceTheDefaultOnes) {
  const RoutineRules r = ParseRules(
      "name: club\nsource: our club's own rules, 2026\nexecution:\n  knees_bent: [[10, 0.1], [30, "
      "0.2]]\n",
      "club.yaml");
  const FaultRule* knees = r.execution.Find("knees_bent");
  ASSERT_NE(knees, nullptr);
  EXPECT_DOUBLE_EQ(knees->DeductionFor(9.9), 0.0);
  EXPECT_DOUBLE_EQ(knees->DeductionFor(12), 0.1);
  EXPECT_DOUBLE_EQ(knees->DeductionFor(31), 0.2);
  EXPECT_TRUE(knees->Exceeds(16, 5));
  EXPECT_FALSE(knees->Exceeds(14, 5));  // past 10° but within the 5° of uncertainty
  const FaultRule* opening = r.execution.Find("late_opening");
  ASSERT_NE(opening, nullptr);
  EXPECT_DOUBLE_EQ(opening->DeductionFor(0.4), 0.0);
  EXPECT_DOUBLE_EQ(opening->DeductionFor(0.2), 0.1);
  EXPECT_DOUBLE_EQ(opening->DeductionFor(0.1), 0.2);
  EXPECT_TRUE(opening->Exceeds(0.1, 0.02));
  EXPECT_FALSE(opening->Exceeds(0.29, 0.02));
}

}  // namespace
}  // namespace acro::fig
