#pragma once

// The sample routine analysed for its athlete, once per test program: what the scene tests place
// ghosts, comparisons and designs against.

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/capture/trial_io.h"
#include "refdata.h"

namespace acro::analysis::testing {

struct AnalysedSample {
  capture::Trial trial;
  AthleteBody body;
  TrialAnalysis analysis;
};

inline const AnalysedSample& TheSample() {
  static const AnalysedSample sample = [] {
    AnalysedSample s;
    s.trial = capture::ReadTrial(acro::testing::SourceDir() /
                                 "samples/trials/trampoline_routine/trampoline_routine.c3d");
    s.body = MakeAthleteBody(
        ReadAthleteProfile(acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml"));
    s.analysis = AnalyzeTrial(s.trial, nullptr, s.body);
    return s;
  }();
  return sample;
}

}  // namespace acro::analysis::testing
