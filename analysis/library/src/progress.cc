#include "acro/library/progress.h"

#include <algorithm>
#include <chrono>
#include <map>

#include <fmt/format.h>

#include "acro/base/input_error.h"

namespace acro::library {

namespace {

long DayNumber(const std::string& date) {
  if (date.size() != 10) throw InputError("", "date", "'" + date + "' is not YYYY-MM-DD");
  // C++20's civil calendar (proleptic Gregorian).
  const std::chrono::year_month_day ymd{std::chrono::year(std::stoi(date.substr(0, 4))),
                                        std::chrono::month(unsigned(std::stoi(date.substr(5, 2)))),
                                        std::chrono::day(unsigned(std::stoi(date.substr(8, 2))))};
  if (!ymd.ok()) throw InputError("", "date", "'" + date + "' is not a calendar date");
  return std::chrono::sys_days(ymd).time_since_epoch().count();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double MetricOf(const JumpRecord& j, ProgressMetric metric) {
  switch (metric) {
    case ProgressMetric::kTimeOfFlight:
      return j.time_of_flight_s;
    case ProgressMetric::kDisplacement:
      return j.displacement_m;
    case ProgressMetric::kDifficulty:
      return j.difficulty;
    case ProgressMetric::kApex:
      return j.apex_above_bed_m;
    case ProgressMetric::kVerdict:
      return j.verdict_class == "pass" ? 1.0 : 0.0;
  }
  return 0.0;
}

}  // namespace

int DaysBetween(const std::string& from, const std::string& to) {
  return static_cast<int>(DayNumber(to) - DayNumber(from));
}

ProgressMetric ParseProgressMetric(const std::string& word) {
  if (word == "tof") return ProgressMetric::kTimeOfFlight;
  if (word == "hd") return ProgressMetric::kDisplacement;
  if (word == "dd") return ProgressMetric::kDifficulty;
  if (word == "apex") return ProgressMetric::kApex;
  if (word == "verdict") return ProgressMetric::kVerdict;
  throw InputError("", "--metric", "'" + word + "' is not tof, hd, dd, apex or verdict");
}

Progress CalcProgress(const std::vector<JumpRow>& rows,
                      ProgressMetric metric,
                      const std::string& athlete,
                      const std::string& fig_code) {
  if (rows.empty())
    throw InputError("",
                     "",
                     fmt::format("no jumps in the library for athlete '{}'{}",
                                 athlete,
                                 fig_code.empty() ? "" : " and skill " + fig_code));
  Progress p;
  p.athlete = athlete;
  p.fig_code = fig_code;
  p.metric = metric;
  static const std::map<ProgressMetric, std::pair<const char*, const char*>> kNames = {
      {ProgressMetric::kTimeOfFlight, {"time of flight", "s"}},
      {ProgressMetric::kDisplacement, {"horizontal displacement", "m"}},
      {ProgressMetric::kDifficulty, {"difficulty (DD)", "points"}},
      {ProgressMetric::kApex, {"apex above the bed", "m"}},
      {ProgressMetric::kVerdict, {"physical check passed", "fraction"}}};
  p.metric_name = kNames.at(metric).first;
  p.unit = kNames.at(metric).second;
  p.first_date = rows.front().session_date;
  for (const JumpRow& r : rows) p.first_date = std::min(p.first_date, r.session_date);

  std::map<std::string, std::vector<const JumpRow*>> by_session;
  for (const JumpRow& r : rows) {
    ProgressPoint point;
    point.date = r.session_date;
    point.day = DaysBetween(p.first_date, r.session_date);
    point.value = MetricOf(r.jump, metric);
    point.trial_path = r.trial_path;
    point.jump = r.jump.index;
    point.fig_code = r.jump.fig_code;
    p.points.push_back(point);
    by_session[r.session_date].push_back(&r);
  }
  for (const auto& [date, jumps] : by_session) {
    SessionProgress s;
    s.date = date;
    s.day = DaysBetween(p.first_date, date);
    s.num_jumps = static_cast<int>(jumps.size());
    std::vector<double> values;
    for (const JumpRow* r : jumps) {
      values.push_back(MetricOf(r->jump, metric));
      if (r->jump.landing_x_m && r->jump.landing_y_m) {
        s.landing_x_m.push_back(*r->jump.landing_x_m);
        s.landing_y_m.push_back(*r->jump.landing_y_m);
        s.landings_in_zone_a += r->jump.landing_in_zone_a.value_or(false) ? 1 : 0;
      }
    }
    // The verdict's "median" is the pass fraction: a median of 0s and 1s says less.
    if (metric == ProgressMetric::kVerdict) {
      double sum = 0;
      for (double v : values) sum += v;
      s.median = sum / double(values.size());
    } else {
      s.median = Median(values);
    }
    s.min = *std::min_element(values.begin(), values.end());
    s.max = *std::max_element(values.begin(), values.end());
    p.sessions.push_back(std::move(s));
  }

  // Trend: least squares through the jumps.
  const double n = double(p.points.size());
  double sx = 0, sy = 0;
  for (const ProgressPoint& q : p.points) {
    sx += q.day;
    sy += q.value;
  }
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (const ProgressPoint& q : p.points) {
    sxx += (q.day - mx) * (q.day - mx);
    sxy += (q.day - mx) * (q.value - my);
    syy += (q.value - my) * (q.value - my);
  }
  p.trend_slope_per_day = sxx > 0 ? sxy / sxx : 0.0;
  p.trend_intercept = my - p.trend_slope_per_day * mx;
  p.trend_r2 = sxx > 0 && syy > 0 ? sxy * sxy / (sxx * syy) : 0.0;
  return p;
}

std::string FormatProgressCsv(const Progress& p) {
  std::string out = fmt::format("date,day,jumps,median_{0},min_{0},max_{0},landings,in_zone_a\n",
                                p.unit == "fraction" ? "pass_fraction" : p.unit);
  for (const SessionProgress& s : p.sessions)
    out += fmt::format("{},{:g},{},{:.4f},{:.4f},{:.4f},{},{}\n",
                       s.date,
                       s.day,
                       s.num_jumps,
                       s.median,
                       s.min,
                       s.max,
                       s.landing_x_m.size(),
                       s.landings_in_zone_a);
  return out;
}

}  // namespace acro::library
