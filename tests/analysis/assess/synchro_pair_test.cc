// A synchro pair from motion capture (docs/scoring.md, "Synchro"): the sample routine beside a copy
// of itself recorded 40 ms late — every landing 40 ms after its partner's, measured within 2 ms —
// and beside the generator's routine with a back pike for the full at element 4: the mismatch
// named and the synchronised routine ended there.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_body.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/capture/c3d.h"
#include "acro/fig/synchro.h"
#include "refdata.h"
#include "sample_routine.h"

namespace acro::analysis {
namespace {

std::filesystem::path SamplePath(const std::string& relative) {
  return acro::testing::SourceDir() / relative;
}

AthleteBody Body() {
  return MakeAthleteBody(ReadAthleteProfile(SamplePath("samples/athletes/sample_athlete.yaml")));
}

// The trial as a recording `delay_s` late would hold it: every marker at frame time t where the
// original had it at t − delay_s (linear between frames; the first frames before the recording
// began are gaps).
capture::Trial Delayed(const capture::Trial& trial, double delay_s) {
  capture::Trial out = trial;
  const int P = trial.num_points(), n = trial.num_frames;
  const double lag = delay_s * trial.point_rate_hz;
  for (int f = 0; f < n; ++f) {
    const double x = f - lag;
    const int k = static_cast<int>(std::floor(x));
    const double u = x - k;
    for (int p = 0; p < P; ++p) {
      Eigen::Vector3d v = Eigen::Vector3d::Constant(std::nan(""));
      if (k >= 0 && k + 1 < n) v = (1 - u) * trial.position(k, p) + u * trial.position(k + 1, p);
      out.position(f, p) = v;
    }
  }
  return out;
}

const TrialAnalysis& SampleAnalysis() {
  static const TrialAnalysis a = AnalyzeTrial(
      capture::ReadC3d(SamplePath("samples/trials/trampoline_routine/trampoline_routine.c3d")),
      nullptr,
      Body());
  return a;
}

TEST(SynchroPair, A40msLatePartnerIsMeasuredAtEveryLanding) {
  const capture::Trial trial =
      capture::ReadC3d(SamplePath("samples/trials/trampoline_routine/trampoline_routine.c3d"));
  const TrialAnalysis& a = SampleAnalysis();
  const TrialAnalysis b = AnalyzeTrial(Delayed(trial, 0.040), nullptr, Body());
  const fig::SynchroScore s = fig::ScoreSynchro(fig::SynchroRules{}, a.score, b.score);
  ASSERT_EQ(s.elements.size(), 5u);  // the sample's elements after its in-bounce
  for (const fig::SynchroElement& e : s.elements) {
    SCOPED_TRACE("element " + std::to_string(e.element));
    EXPECT_TRUE(e.skills_match && e.shapes_match && e.counted) << e.code_a << " " << e.code_b;
    EXPECT_NEAR(e.landing_difference_s, 0.040, 0.002);
    std::printf("element %d %s: landing B - A %.2f ms\n",
                e.element,
                e.code_a.c_str(),
                1000 * e.landing_difference_s);
  }
  EXPECT_EQ(s.ended_at_element, 0) << s.ending;
  EXPECT_NEAR(s.mean_abs_difference_s, 0.040, 0.002);
  EXPECT_NEAR(s.score, 5 * (2.0 - 0.4), 5 * 10 * 0.002);
}

TEST(SynchroPair, ADifferentSkillAtElement4EndsThePairThere) {
  samples::SampleRoutineOptions options;
  options.skill_order = {0, 1, 2, 3, 2, 5};  // the back pike again where the full was
  const samples::SampleRoutine other = samples::MakeSampleRoutine(
      SamplePath("samples/athletes/sample_athlete.yaml"), "sample_athlete.yaml", options);
  const TrialAnalysis b = AnalyzeTrial(other.trial, nullptr, Body());
  const fig::SynchroScore s =
      fig::ScoreSynchro(fig::SynchroRules{}, SampleAnalysis().score, b.score);
  ASSERT_EQ(s.elements.size(), 5u);
  EXPECT_EQ(s.ended_at_element, 4);
  EXPECT_EQ(s.elements[3].code_a, "42/");
  EXPECT_EQ(s.elements[3].code_b, "40<");
  EXPECT_FALSE(s.elements[3].skills_match);
  EXPECT_NE(s.ending.find("element 4: A 42/, B 40<"), std::string::npos) << s.ending;
  EXPECT_EQ(s.elements_counted, 3);
  for (int k = 0; k < 3; ++k) {
    // The same simulation up to there: the landings together (the generator's own clock).
    EXPECT_TRUE(s.elements[size_t(k)].skills_match);
    EXPECT_NEAR(s.elements[size_t(k)].landing_difference_s, 0.0, 0.002);
  }
  // B's own score sheet: a repeated element gets no difficulty (element 2 again).
  EXPECT_FALSE(b.score.elements[3].difficulty_counted);
}

}  // namespace
}  // namespace acro::analysis
