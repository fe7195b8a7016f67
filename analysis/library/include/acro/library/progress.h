#pragma once

// A season's progress for one athlete (and one skill): one value per jump, the session medians, a
// trend line through the jumps (least squares), and the landings on the bed per session. Plain
// data: ui/report draws it.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "acro/library/library.h"

namespace acro::library {

/// Per jump: time of flight, travel on the bed (take-off to landing), difficulty, apex, the
/// physical check's pass; per element on the score sheet: the execution faults reported; per
/// routine (trial): the score sheet's T (its elements' flights summed, truncated to 0.005) and H
/// (1 per element less each landing's deduction, when every landing's zone is known).
enum class ProgressMetric {
  kTimeOfFlight,
  kDisplacement,
  kDifficulty,
  kApex,
  kVerdict,
  kRoutineTime,
  kRoutineDisplacement,
  kFaults
};

/// "tof", "hd", "dd", "apex", "verdict", "T", "H", "faults"; throws acro::InputError naming the
/// word otherwise.
ProgressMetric ParseProgressMetric(const std::string& word);

struct ProgressPoint {
  std::string date;
  double day = 0.0;  ///< days since the first session shown
  double value = 0.0;
  std::string trial_path;
  int jump = 0;
  std::string fig_code;
};

struct SessionProgress {
  std::string date;
  double day = 0.0;
  int num_jumps = 0;
  /// The session's median of the metric (for the verdict: the fraction of jumps that pass).
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
  /// The session's landings in the bed's frame (m) and how many lie in zone A.
  std::vector<double> landing_x_m, landing_y_m;
  int landings_in_zone_a = 0;
  /// The score sheet's elements among the session's jumps, the execution faults reported on them,
  /// and the most frequent (empty when none; ties: the first in the rule keys' order of
  /// appearance).
  int elements = 0;
  int faults_reported = 0;
  std::string most_frequent_fault;
  int most_frequent_count = 0;
  std::map<std::string, int> fault_counts;
};

struct Progress {
  std::string athlete;
  std::string fig_code;  ///< empty: every skill
  ProgressMetric metric = ProgressMetric::kTimeOfFlight;
  std::string metric_name;  ///< e.g. "time of flight"
  std::string unit;         ///< e.g. "s"
  std::string first_date;   ///< day 0
  /// One per jump; for T and H one per routine (trial; `jump` 0).
  std::vector<ProgressPoint> points;
  std::vector<SessionProgress> sessions;
  /// value ≈ intercept + slope · day over the jumps (needs two distinct days; else slope 0).
  double trend_intercept = 0.0;
  double trend_slope_per_day = 0.0;
  double trend_r2 = 0.0;
  /// Over the whole season: elements, and each reported fault with how often, most frequent first.
  int elements = 0;
  std::vector<std::pair<std::string, int>> fault_counts;
};

/// The progress of `rows` (one athlete's jumps, as Library::QueryJumps gives them) in `metric`.
/// Throws acro::InputError when there are no rows, and for T and H with a skill (they are a
/// routine's) or when no trial has a scored routine.
Progress CalcProgress(const std::vector<JumpRow>& rows,
                      ProgressMetric metric,
                      const std::string& athlete,
                      const std::string& fig_code);

/// The table of the sessions as CSV: date, jumps, median, min, max, landings in zone A, elements,
/// faults reported and the most frequent.
std::string FormatProgressCsv(const Progress& progress);

/// Days from `from` to `to` (YYYY-MM-DD, the proleptic Gregorian calendar).
int DaysBetween(const std::string& from, const std::string& to);

}  // namespace acro::library
