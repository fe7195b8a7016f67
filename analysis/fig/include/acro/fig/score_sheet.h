#pragma once

// The score sheet of one routine by the Code of Points (docs/scoring.md): which flights make the
// routine, each element's difficulty (a repeat gets none), time of flight and landing zone, and the
// routine's D, T (truncated as the Code says) and H, the special requirements met and missed, and
// where the routine was interrupted. Works from measured flights, whatever measured them.

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "acro/fig/rules.h"
#include "acro/fig/skill.h"
#include "acro/fig/trampoline.h"

namespace acro::fig {

/// One execution quantity measured on an element (analysis/assess's execution assistant): the
/// worst value over the element, when, and what the rules suggest for it — always with the
/// measurement, never as a bare number.
struct MeasuredFault {
  std::string fault;     ///< the rule's key (FaultRule::fault)
  std::string quantity;  ///< what was measured, in words ("knee flexion")
  std::string unit;      ///< "deg", "m", "s"
  double value = 0;
  double uncertainty = 0;  ///< of this input's measurement of it
  /// The rule's first threshold (where a deduction begins; NaN when the rule has no steps), and
  /// whether smaller values are worse (the opening's time before landing).
  double threshold = std::numeric_limits<double>::quiet_NaN();
  bool smaller_is_worse = false;
  /// How far it is toward a deduction: the value over the first threshold (1 where the first
  /// deduction begins; the threshold over the value when smaller is worse, +inf for a value at or
  /// below 0 then); NaN without a threshold or a finite value. One axis for degrees, metres and
  /// seconds (the report's execution chart, the studio's worst measurement).
  double ThresholdRatio() const;
  double time_s = 0;  ///< where it is worst (trial time)
  int frame = -1;
  /// Past the rules' first threshold by more than the uncertainty: a fault, whatever the noise.
  bool reported = false;
  double deduction = 0;  ///< suggested by the rules when reported, else 0
  /// The element's frames it was measured over, and of those the frames where the points it needs
  /// were seen (not filled in by the fit: a keypoint no two cameras agreed on, a marker's gap);
  /// 0 and 0 for a quantity of the whole flight (travel, height, the shape's hold). Seen in too
  /// few frames, it is not measured: `value` is NaN and it is never reported.
  int frames = 0;
  int frames_seen = 0;
  bool Measured() const { return std::isfinite(value); }
};

/// One flight as measured, in the order performed.
struct PerformedFlight {
  FigSkill skill;  ///< with its direction
  BodyPosition takeoff = BodyPosition::kFeet;
  BodyPosition landing = BodyPosition::kFeet;
  double time_of_flight_s = 0;
  /// When it landed (the trial's clock, s; synchro pairs compare them).
  double landing_s = 0;
  /// Where it landed, when the bed is known.
  std::optional<HdLanding> landing_zone;
  /// Cut by the start or the end of the recording.
  bool partial = false;
  /// The execution assistant's measurements (empty when not measured).
  std::vector<MeasuredFault> faults;
};

struct ScoredElement {
  int element = 0;  ///< 1-based in the routine
  int flight = 0;   ///< 1-based in the trial (jumps.json's index)
  std::string code;
  std::string name;  ///< the skill's usual name, or empty
  FigDifficulty difficulty;
  bool difficulty_counted = true;
  std::string note;  ///< why not ("repeats element 2"), or empty
  double time_of_flight_s = 0;
  double landing_s = 0;  ///< the trial's clock
  std::optional<HdLanding> landing_zone;
  /// The special requirements this element fulfils (names), in the rules' order.
  std::vector<std::string> requirements;
  /// Every execution quantity measured, reported or not, and the suggested deduction: the reported
  /// faults' sum, at most 0.5 (a judge's most for one element).
  std::vector<MeasuredFault> faults;
  double execution_deduction = 0;
};

struct RoutineScore {
  std::string rules_name;
  std::string rules_source;
  std::string zones_source;
  int expected_elements = 10;
  std::vector<ScoredElement> elements;
  /// Ended before its last element (a straight jump, a flight cut by the recording, or the end of
  /// the trial): scored to its last complete element, as the Code says.
  bool interrupted = false;
  std::string interruption;  ///< one line, or empty
  /// D: the counted difficulty (after a cap); the uncapped sum beside it.
  double difficulty = 0;
  double difficulty_uncapped = 0;
  bool difficulty_capped = false;
  /// T: the sum of the elements' flights (s), and the points (truncated to the rules' step).
  double time_of_flight_sum_s = 0;
  double time_of_flight = 0;
  /// H: 1 point per completed element less each landing's deduction; none when a landing's zone
  /// is unknown (no bed).
  std::optional<double> horizontal_displacement;
  int close_calls = 0;  ///< landings whose zone margin is inside the measurement's uncertainty
  std::vector<std::string> requirements_missing;
  std::vector<std::string> rule_breaks;  ///< e.g. "3 elements below 270° (at most 2)"
  double penalty = 0;
  /// The execution assistant's suggested deductions summed over the elements (one judge's view;
  /// E itself is the judges').
  double execution_deductions = 0;
  int faults_reported = 0;
  /// D + T + H − penalties (execution is the judges', not summed here).
  double total_without_execution = 0;
  bool valid() const { return requirements_missing.empty() && rule_breaks.empty() && !interrupted; }
};

/// The flights of a trial → its routine's score. The routine starts at the first complete flight
/// that is not a straight jump (the in-bounces before it are not elements) and ends at the rules'
/// element count, at a straight jump or a cut flight in between (interrupted), or at the trial's
/// end (interrupted when short).
RoutineScore ScoreRoutine(const RoutineRules& rules, const std::vector<PerformedFlight>& flights);

/// A planned routine as the score sheet reads it: FIG codes separated by spaces or commas ("821o
/// 42/ 812/"), each with its direction by the parity rule (ParseFigCode), feet to feet, no time of
/// flight yet. Throws acro::InputError naming the code at fault (or none given, or more than 100).
std::vector<PerformedFlight> PlannedFlights(std::string_view codes);

/// T from the flights' sum: 1 s = 1 point, truncated to `step` (0.005 by the Code).
double TruncateTimeOfFlight(double sum_s, double step);

/// The element's quantities that could not be measured, in words, "" when there are none:
/// "legs_apart (seen in 1 of 38 frames)" — for a sheet to say what it did not see.
std::string DescribeUnmeasured(const ScoredElement& element);

}  // namespace acro::fig
