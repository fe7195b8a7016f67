// The execution assistant against faults an athlete makes, put into the sample routine by its
// generator (tools/sample_routine.h, SampleFault): the faulty postures are simulated like the
// clean ones (the flight's physics, the bed, markers with noise), written as a trial, and analysed
// from the markers alone. Each fault must be found on its element with the value put in (5°, 3 cm,
// 0.02 s), and no fault on any other element (docs/scoring.md, "Execution").
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/assess/execution.h"
#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_body.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/fig/rules.h"
#include "acro/fig/score_sheet.h"
#include "acro/fig/trampoline.h"
#include "refdata.h"
#include "sample_routine.h"

namespace acro::analysis {
namespace {

using Kind = samples::SampleFault::Kind;
constexpr double kDeg = std::numbers::pi / 180;

std::filesystem::path AthletePath() {
  return acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
}

// One injected fault and what the assistant must say about it.
struct Expected {
  samples::SampleFault fault;
  std::string name;  // the MeasuredFault's `fault`
  double value = 0;  // what it must measure
  double tolerance = 0;
  bool reported = true;  // past its rule's first threshold beyond the uncertainty
};

struct Analysed {
  samples::SampleRoutine routine;
  TrialAnalysis analysis;
};

Analysed Analyse(const std::vector<Expected>& expected) {
  samples::SampleRoutineOptions options;
  for (const Expected& e : expected) options.faults.push_back(e.fault);
  Analysed out{samples::MakeSampleRoutine(AthletePath(), "sample_athlete.yaml", options), {}};
  out.analysis =
      AnalyzeTrial(out.routine.trial, nullptr, MakeAthleteBody(ReadAthleteProfile(AthletePath())));
  return out;
}

// Every flight (the straight jump before the first somersault too: an in-bounce on the score
// sheet, but a jump the coach looks at): the injected fault measured within its tolerance and
// reported (or not) as expected; nothing else reported on it, and nothing at all on the flights
// left clean.
void ExpectFoundWhereTheyAre(const Analysed& a, const std::vector<Expected>& expected) {
  const std::vector<std::string> codes = {"00", "40o", "40<", "41/", "42/", "800o"};
  ASSERT_EQ(a.analysis.jumps.size(), codes.size());
  for (size_t j = 0; j < codes.size(); ++j) {
    const JumpMetrics& jump = a.analysis.jumps[j];
    SCOPED_TRACE("flight " + std::to_string(j + 1) + " " + jump.fig_code);
    EXPECT_EQ(jump.fig_code, codes[j]);
    const Expected* injected = nullptr;
    for (const Expected& e : expected)
      if (e.fault.skill == int(j) && !e.name.empty()) injected = &e;
    bool found = false;
    for (const fig::MeasuredFault& f : jump.execution) {
      if (injected != nullptr && f.fault == injected->name) {
        found = true;
        std::printf("flight %zu %-5s %-12s injected %.3f measured %.3f %s (deduction %.1f)\n",
                    j + 1,
                    jump.fig_code.c_str(),
                    f.fault.c_str(),
                    injected->value,
                    f.value,
                    f.unit.c_str(),
                    f.deduction);
        EXPECT_NEAR(f.value, injected->value, injected->tolerance) << f.quantity;
        EXPECT_EQ(f.reported, injected->reported) << f.value << " " << f.unit;
        EXPECT_EQ(f.deduction > 0, injected->reported);
        // The worst instant lies in the element's flight.
        const Flight& flight = jump.flight;
        EXPECT_GE(f.time_s, flight.takeoff_s);
        EXPECT_LE(f.time_s, flight.landing_s);
      } else {
        EXPECT_FALSE(f.reported) << f.fault << " " << f.value << " " << f.unit;
      }
    }
    if (injected != nullptr) {
      EXPECT_TRUE(found) << injected->name;
    }
  }
}

// The legs' spread of two straight legs abducted by ±a: the ankles 2·L·sin(a) further apart
// than the hips, L hip to ankle of the generator's athlete.
double AbductionForSpread(double spread_m) {
  const samples::SampleRoutine clean_model = [] {
    samples::SampleRoutineOptions o;
    o.num_skills = 1;
    return samples::MakeSampleRoutine(AthletePath(), "sample_athlete.yaml", o);
  }();
  const dynamics::Model<double>& model = clean_model.model;
  dynamics::Workspace<double> ws(model);
  dynamics::CalcForwardKinematics(model, ws, dynamics::MakeNeutralConfiguration(model));
  auto point = [&](const char* name) {
    const auto& p = model.point(model.FindPoint(name));
    const auto& X = ws.X_WB[static_cast<size_t>(p.segment)];
    return Eigen::Vector3d(X.rotation() * p.p_BoP_B + X.translation());
  };
  const double leg = (point("r_ankle_jc") - point("r_hip_jc")).norm();
  return std::asin(spread_m / (2 * leg)) / kDeg;
}

samples::SampleFault Fault(int skill, Kind kind, double value) {
  samples::SampleFault f;
  f.skill = skill;
  f.kind = kind;
  f.value = value;
  return f;
}

// Routine A: the small faults, and an opening 0.1 s before landing.
TEST(ExecutionFaults, SmallFaultsAndALateOpening) {
  const std::vector<Expected> expected = {
      {Fault(0, Kind::kKneesBent, 20), "knees_bent", 20, 5},
      {Fault(1, Kind::kOpening, 0.1), "late_opening", 0.1, 0.02},
      {Fault(2, Kind::kKneesBent, 20), "knees_bent", 20, 5},
      {Fault(3, Kind::kArmsOut, 45), "arms_out", 45, 5},
      {Fault(4, Kind::kLegsApart, AbductionForSpread(0.20)), "legs_apart", 0.20, 0.03},
  };
  ExpectFoundWhereTheyAre(Analyse(expected), expected);
}

// Routine B: the large faults, an opening in time (0.4 s: no fault), and a tuck at 110°.
TEST(ExecutionFaults, LargeFaultsAndAnOpenTuck) {
  const std::vector<Expected> expected = {
      {Fault(0, Kind::kKneesBent, 45), "knees_bent", 45, 5},
      {Fault(1, Kind::kOpening, 0.4), "late_opening", 0.4, 0.02, false},
      {Fault(2, Kind::kKneesBent, 45), "knees_bent", 45, 5},
      {Fault(3, Kind::kLegsApart, AbductionForSpread(0.40)), "legs_apart", 0.40, 0.03},
      {Fault(5, Kind::kTuckAngle, 110), "tuck_open", 110, 5},
  };
  const Analysed a = Analyse(expected);
  ExpectFoundWhereTheyAre(a, expected);
  // The pike with its knees at 45° lies on the FIG's line between pike and tuck: said.
  EXPECT_EQ(a.analysis.jumps[2].rotation.shape_alternative, "tuck")
      << a.analysis.jumps[2].rotation.shape_reason;
  EXPECT_TRUE(a.analysis.jumps[1].rotation.shape_alternative.empty());
}

// A landing 30 cm outside zone A (the full, element 4, moved along the bed): zone B, 0.1, its
// margin the distance its outermost foot marker lies beyond zone A's line; the others in A.
TEST(ExecutionFaults, LandingOutsideZoneA) {
  samples::SampleFault f = Fault(4, Kind::kLanding, 0);
  // The full lands at (0.03, −0.14) from the centre: moved to y = 0 (far from the long lines)
  // and along x so that its toes land about 30 cm beyond zone A's short line.
  f.offset_m = Eigen::Vector2d(fig::kZoneALength_m / 2 + 0.30 - 0.03 - 0.12, 0.14);
  const Analysed a = Analyse({{f, "", 0, 0}});
  const samples::SampleRoutine& r = a.routine;
  // The truth: the foot markers at the simulated landing time.
  const capture::Trial& trial = r.trial;
  const int frame = static_cast<int>(std::lround(r.flights[4].landing_s * trial.point_rate_hz));
  double outermost = -1e9;
  for (const char* label : {"RHEE", "RTOE", "RMT5", "LHEE", "LTOE", "LMT5"}) {
    const int p = trial.FindPoint(label);
    ASSERT_GE(p, 0) << label;
    outermost = std::max(outermost, trial.position(frame, p).x() - r.options.bed_centre_m.x());
  }
  const double truth_outside = outermost - fig::kZoneALength_m / 2;
  ASSERT_NEAR(truth_outside, 0.30, 0.05);  // the injection itself
  const fig::RoutineScore& s = a.analysis.score;
  ASSERT_EQ(s.elements.size(), 5u);  // the straight jump is the in-bounce
  for (size_t j = 0; j < s.elements.size(); ++j) {
    SCOPED_TRACE("element " + std::to_string(j + 1));
    ASSERT_TRUE(s.elements[j].landing_zone.has_value());
    const fig::HdLanding& z = *s.elements[j].landing_zone;
    if (j == 3) {
      EXPECT_EQ(s.elements[j].code, "42/");
      EXPECT_EQ(z.zone, "B");
      EXPECT_DOUBLE_EQ(z.deduction, 0.1);
      EXPECT_NEAR(z.margin_m, truth_outside, 0.03);
      EXPECT_FALSE(z.uncertain);
      std::printf("landing of %s: zone %s, %.3f m outside zone A (truth %.3f m)\n",
                  s.elements[j].code.c_str(),
                  z.zone.c_str(),
                  z.margin_m,
                  truth_outside);
    } else {
      EXPECT_EQ(z.zone, "A");
    }
    for (const fig::MeasuredFault& mf : s.elements[j].faults)
      EXPECT_FALSE(mf.reported) << mf.fault << " " << mf.value;
  }
  ASSERT_TRUE(s.horizontal_displacement.has_value());
  EXPECT_NEAR(*s.horizontal_displacement, 5.0 - 0.1, 1e-9);  // at most the elements done
}

// What the assistant measures is what the recording saw (execution.cc, SeenPoints): a leg the fit
// guessed — its markers filled in (a keypoint no two cameras agreed on), or the fit far from them
// (a view gated out) — is not measured, and says so; one camera measures the legs' spread across
// its view only, and not where the spread lies along its axis. Where the markers show the spread,
// it is measured (above) — the rule drops the fit's guesses, not the athlete's faults. The
// routine: the straight jump with its legs 40 cm apart.
const Analysed& LegsApartRoutine() {
  static const Analysed a =
      Analyse({{Fault(0, Kind::kLegsApart, AbductionForSpread(0.40)), "legs_apart", 0.40, 0.03}});
  return a;
}

fig::MeasuredFault LegsApart(const TrialAnalysis& t, size_t jump, const ExecutionOptions& o) {
  for (const fig::MeasuredFault& f :
       MeasureExecution(t, jump, fig::RoutineRules::FigSenior().execution, o))
    if (f.fault == "legs_apart") return f;
  ADD_FAILURE() << "no legs_apart measure on flight " << jump + 1;
  return fig::MeasuredFault{};
}

std::vector<int> FramesOf(const TrialAnalysis& a, size_t jump) {
  std::vector<int> out;
  const Flight& f = a.jumps[jump].flight;
  for (int k = std::max(0, f.takeoff_frame); k <= f.landing_frame; ++k) out.push_back(k);
  return out;
}

Eigen::Vector3d PointAt(const dynamics::Model<double>& model,
                        dynamics::Workspace<double>& ws,
                        const Eigen::VectorXd& q,
                        const char* name) {
  dynamics::CalcForwardKinematics(model, ws, q);
  const auto& p = model.point(model.FindPoint(name));
  const auto& X = ws.X_WB[size_t(p.segment)];
  return Eigen::Vector3d(X.rotation() * p.p_BoP_B + X.translation());
}

TEST(ExecutionFaults, TheFeetsMarkersFilledInAreNotMeasured) {
  const Analysed& a = LegsApartRoutine();
  const ExecutionOptions& options = a.analysis.execution_options;
  ASSERT_FALSE(options.single_camera_centre_W.has_value());  // markers
  const fig::MeasuredFault seen = LegsApart(a.analysis, 0, options);
  EXPECT_NEAR(seen.value, 0.40, 0.03);
  EXPECT_TRUE(seen.reported);
  EXPECT_GT(seen.frames, 10);
  EXPECT_EQ(seen.frames_seen, seen.frames);
  // The feet's and shanks' markers filled in over the straight jump.
  TrialAnalysis lost = a.analysis;
  const ReconstructionResult& rec = a.analysis.reconstruction;
  const int num_markers = static_cast<int>(rec.markers.size());
  for (int m = 0; m < num_markers; ++m) {
    const std::string& segment = rec.model.segment(rec.markers[size_t(m)].segment).name;
    if (segment.find("foot") == std::string::npos && segment.find("shank") == std::string::npos)
      continue;
    for (int k : FramesOf(a.analysis, 0))
      lost.reconstruction.recorded[Eigen::Index(k) * num_markers + m] = false;
  }
  const fig::MeasuredFault f = LegsApart(lost, 0, options);
  EXPECT_FALSE(f.Measured()) << f.value;
  EXPECT_FALSE(f.reported);
  EXPECT_EQ(f.frames, seen.frames);
  EXPECT_EQ(f.frames_seen, 0);
  fig::ScoredElement e;
  e.faults = {f};
  EXPECT_NE(fig::DescribeUnmeasured(e).find("legs_apart (seen in 0 of"), std::string::npos)
      << fig::DescribeUnmeasured(e);
}

TEST(ExecutionFaults, TheFitsGuessIsNotMeasured) {
  // The barani's legs spread 40 cm in the motion while its markers keep them together.
  const Analysed& a = LegsApartRoutine();
  const ExecutionOptions& options = a.analysis.execution_options;
  const dynamics::Model<double>& model = a.analysis.reconstruction.model;
  TrialAnalysis guessed = a.analysis;
  Motion& m = guessed.reconstruction.motion;
  int column[2] = {-1, -1};
  for (int c = 0; c < int(m.coordinate_names.size()); ++c) {
    if (m.coordinate_names[size_t(c)] == "r_hip_abduction") column[0] = c;
    if (m.coordinate_names[size_t(c)] == "l_hip_abduction") column[1] = c;
  }
  ASSERT_GE(column[0], 0);
  ASSERT_GE(column[1], 0);
  const std::vector<int> frames = FramesOf(a.analysis, 3);
  const int middle = frames[frames.size() / 2];
  dynamics::Workspace<double> ws(model);
  auto ankles_apart = [&](const Eigen::VectorXd& q) {
    return (PointAt(model, ws, q, "r_ankle_jc") - PointAt(model, ws, q, "l_ankle_jc")).norm();
  };
  // The signs that part the legs (each side's abduction convention).
  const double abduction = AbductionForSpread(0.40) * kDeg;
  double best = -1, sign[2] = {1, 1};
  for (double r : {-1.0, 1.0})
    for (double l : {-1.0, 1.0}) {
      Eigen::VectorXd q = m.q.col(middle);
      q[column[0]] += r * abduction;
      q[column[1]] += l * abduction;
      if (const double d = ankles_apart(q); d > best) {
        best = d;
        sign[0] = r;
        sign[1] = l;
      }
    }
  ASSERT_GT(best - ankles_apart(m.q.col(middle)), 0.3);
  for (int k : frames)
    for (int s = 0; s < 2; ++s) m.q(column[s], k) += sign[s] * abduction;
  const fig::MeasuredFault f = LegsApart(guessed, 3, options);
  EXPECT_FALSE(f.Measured()) << f.value << " over " << f.frames_seen << " of " << f.frames;
  EXPECT_FALSE(f.reported);
  // Untouched, the barani's legs are seen together.
  const fig::MeasuredFault clean = LegsApart(a.analysis, 3, options);
  EXPECT_TRUE(clean.Measured());
  EXPECT_FALSE(clean.reported) << clean.value;
}

TEST(ExecutionFaults, OneCameraMeasuresTheSpreadAcrossItsView) {
  // One camera 10 m away: along the hips' axis (the spread edge-on), and in front.
  const Analysed& a = LegsApartRoutine();
  const ExecutionOptions& options = a.analysis.execution_options;
  const dynamics::Model<double>& model = a.analysis.reconstruction.model;
  const std::vector<int> frames = FramesOf(a.analysis, 0);
  const Eigen::VectorXd q = a.analysis.reconstruction.motion.q.col(frames[frames.size() / 2]);
  dynamics::Workspace<double> ws(model);
  const Eigen::Vector3d r_hip = PointAt(model, ws, q, "r_hip_jc");
  const Eigen::Vector3d l_hip = PointAt(model, ws, q, "l_hip_jc");
  const Eigen::Vector3d hips = r_hip - l_hip, middle = 0.5 * (r_hip + l_hip);
  const Eigen::Vector3d axis = Eigen::Vector3d(hips.x(), hips.y(), 0).normalized();
  const Eigen::Vector3d front = Eigen::Vector3d::UnitZ().cross(axis);
  ExecutionOptions side = options, ahead = options;
  side.single_camera_centre_W = middle + 10.0 * axis;
  ahead.single_camera_centre_W = middle + 10.0 * front;
  const fig::MeasuredFault edge_on = LegsApart(a.analysis, 0, side);
  EXPECT_FALSE(edge_on.Measured()) << edge_on.value << " over " << edge_on.frames_seen;
  EXPECT_FALSE(edge_on.reported);
  const fig::MeasuredFault facing = LegsApart(a.analysis, 0, ahead);
  EXPECT_NEAR(facing.value, 0.40, 0.04);
  EXPECT_TRUE(facing.reported);
  EXPECT_NE(facing.quantity.find("across the camera's view"), std::string::npos);
  std::printf(
      "legs apart 0.40 m: one camera in front %.3f m (%d/%d frames), along the hips' "
      "axis not measured (%d/%d)\n",
      facing.value,
      facing.frames_seen,
      facing.frames,
      edge_on.frames_seen,
      edge_on.frames);
}

}  // namespace
}  // namespace acro::analysis
