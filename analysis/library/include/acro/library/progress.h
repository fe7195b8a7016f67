#pragma once

// A season's progress for one athlete (and one skill): one value per jump, the session medians, a
// trend line through the jumps (least squares), and the landings on the bed per session. Plain
// data: ui/report draws it.

#include <string>
#include <vector>

#include "acro/library/library.h"

namespace acro::library {

enum class ProgressMetric { kTimeOfFlight, kDisplacement, kDifficulty, kApex, kVerdict };

/// "tof", "hd", "dd", "apex", "verdict"; throws acro::InputError naming the word otherwise.
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
};

struct Progress {
  std::string athlete;
  std::string fig_code;  ///< empty: every skill
  ProgressMetric metric = ProgressMetric::kTimeOfFlight;
  std::string metric_name;  ///< e.g. "time of flight"
  std::string unit;         ///< e.g. "s"
  std::string first_date;   ///< day 0
  std::vector<ProgressPoint> points;
  std::vector<SessionProgress> sessions;
  /// value ≈ intercept + slope · day over the jumps (needs two distinct days; else slope 0).
  double trend_intercept = 0.0;
  double trend_slope_per_day = 0.0;
  double trend_r2 = 0.0;
};

/// The progress of `rows` (one athlete's jumps, as Library::QueryJumps gives them) in `metric`.
/// Throws acro::InputError when there are no rows.
Progress CalcProgress(const std::vector<JumpRow>& rows,
                      ProgressMetric metric,
                      const std::string& athlete,
                      const std::string& fig_code);

/// The table of the sessions as CSV: date, jumps, median, min, max, landings in zone A.
std::string FormatProgressCsv(const Progress& progress);

/// Days from `from` to `to` (YYYY-MM-DD, the proleptic Gregorian calendar).
int DaysBetween(const std::string& from, const std::string& to);

}  // namespace acro::library
