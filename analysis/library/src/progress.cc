#include "acro/library/progress.h"

#include <algorithm>
#include <chrono>
#include <map>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/fig/score_sheet.h"

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
    case ProgressMetric::kFaults:
      return double(j.faults.size());
    case ProgressMetric::kRoutineTime:
    case ProgressMetric::kRoutineDisplacement:
      break;  // a routine's (RoutineValues)
  }
  return 0.0;
}

bool PerRoutine(ProgressMetric metric) {
  return metric == ProgressMetric::kRoutineTime || metric == ProgressMetric::kRoutineDisplacement;
}

// One value per trial with a scored routine: T or H from its elements, as the score sheet counts
// them (analysis/fig: T truncated to 0.005; H only when every element's landing zone is known).
struct RoutineValue {
  const JumpRow* first = nullptr;
  double value = 0.0;
};
std::vector<RoutineValue> RoutineValues(const std::vector<const JumpRow*>& rows,
                                        ProgressMetric metric) {
  std::vector<RoutineValue> out;
  std::map<std::int64_t, std::vector<const JumpRow*>> by_trial;
  std::vector<std::int64_t> order;
  for (const JumpRow* r : rows) {
    if (r->jump.element <= 0) continue;
    if (by_trial.find(r->trial_id) == by_trial.end()) order.push_back(r->trial_id);
    by_trial[r->trial_id].push_back(r);
  }
  for (std::int64_t id : order) {
    const std::vector<const JumpRow*>& elements = by_trial[id];
    double sum = 0, deductions = 0;
    bool zones_known = true;
    for (const JumpRow* e : elements) {
      sum += e->jump.time_of_flight_s;
      if (e->jump.hd_deduction)
        deductions += *e->jump.hd_deduction;
      else
        zones_known = false;
    }
    if (metric == ProgressMetric::kRoutineTime)
      out.push_back({elements.front(), fig::TruncateTimeOfFlight(sum, 0.005)});
    else if (zones_known)
      out.push_back({elements.front(), double(elements.size()) - deductions});
  }
  return out;
}

// The reported faults of `rows`' elements, most frequent first (ties in order of appearance).
std::vector<std::pair<std::string, int>> CountFaults(const std::vector<const JumpRow*>& rows,
                                                     int* elements) {
  std::vector<std::pair<std::string, int>> counts;
  *elements = 0;
  for (const JumpRow* r : rows) {
    if (r->jump.element <= 0) continue;
    ++*elements;
    for (const std::string& f : r->jump.faults) {
      auto it =
          std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == f; });
      if (it == counts.end())
        counts.emplace_back(f, 1);
      else
        ++it->second;
    }
  }
  std::stable_sort(counts.begin(), counts.end(), [](const auto& a, const auto& b) {
    return a.second > b.second;
  });
  return counts;
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
  if (word == "T") return ProgressMetric::kRoutineTime;
  if (word == "H") return ProgressMetric::kRoutineDisplacement;
  if (word == "faults") return ProgressMetric::kFaults;
  throw InputError(
      "", "--metric", "'" + word + "' is not tof, hd, dd, apex, verdict, T, H or faults");
}

namespace {

// The values a metric counts: every jump's, the score sheet's elements' (faults), or one per
// routine (T, H).
std::vector<std::pair<const JumpRow*, double>> MetricValues(const std::vector<const JumpRow*>& all,
                                                            ProgressMetric metric,
                                                            const std::string& athlete) {
  std::vector<std::pair<const JumpRow*, double>> values;
  if (PerRoutine(metric)) {
    for (const RoutineValue& v : RoutineValues(all, metric)) values.emplace_back(v.first, v.value);
    if (values.empty())
      throw InputError(
          "",
          "--metric",
          fmt::format(
              "no trial of athlete '{}' has a scored routine{} (analysed by Acrolab 0.3 or later)",
              athlete,
              metric == ProgressMetric::kRoutineDisplacement ? " with every landing's zone" : ""));
  } else {
    for (const JumpRow* r : all)
      if (metric != ProgressMetric::kFaults || r->jump.element > 0)
        values.emplace_back(r, MetricOf(r->jump, metric));
    if (values.empty())
      throw InputError(
          "", "--metric", fmt::format("no element of a scored routine for athlete '{}'", athlete));
  }
  return values;
}

// One session: its jumps' landings and faults, and its values' median (the verdict's pass
// fraction: a median of 0s and 1s says less), least and most.
SessionProgress SummarizeSession(const std::string& date,
                                 const std::vector<const JumpRow*>& jumps,
                                 const std::vector<double>& v,
                                 const std::string& first_date,
                                 ProgressMetric metric) {
  SessionProgress s;
  s.date = date;
  s.day = DaysBetween(first_date, date);
  s.num_jumps = static_cast<int>(jumps.size());
  for (const JumpRow* r : jumps) {
    if (r->jump.landing_x_m && r->jump.landing_y_m) {
      s.landing_x_m.push_back(*r->jump.landing_x_m);
      s.landing_y_m.push_back(*r->jump.landing_y_m);
      s.landings_in_zone_a += r->jump.landing_in_zone_a.value_or(false) ? 1 : 0;
    }
  }
  const std::vector<std::pair<std::string, int>> faults = CountFaults(jumps, &s.elements);
  for (const auto& f : faults) {
    s.faults_reported += f.second;
    s.fault_counts[f.first] = f.second;
  }
  if (!faults.empty()) {
    s.most_frequent_fault = faults.front().first;
    s.most_frequent_count = faults.front().second;
  }
  if (metric == ProgressMetric::kVerdict) {
    double sum = 0;
    for (double x : v) sum += x;
    s.median = sum / double(v.size());
  } else {
    s.median = Median(v);
  }
  s.min = *std::min_element(v.begin(), v.end());
  s.max = *std::max_element(v.begin(), v.end());
  return s;
}

// Least squares through the jumps: slope per day, intercept, R².
void FitTrend(Progress* p) {
  const double n = double(p->points.size());
  double sx = 0, sy = 0;
  for (const ProgressPoint& q : p->points) {
    sx += q.day;
    sy += q.value;
  }
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (const ProgressPoint& q : p->points) {
    sxx += (q.day - mx) * (q.day - mx);
    sxy += (q.day - mx) * (q.value - my);
    syy += (q.value - my) * (q.value - my);
  }
  p->trend_slope_per_day = sxx > 0 ? sxy / sxx : 0.0;
  p->trend_intercept = my - p->trend_slope_per_day * mx;
  p->trend_r2 = sxx > 0 && syy > 0 ? sxy * sxy / (sxx * syy) : 0.0;
}

}  // namespace

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
      {ProgressMetric::kVerdict, {"physical check passed", "fraction"}},
      {ProgressMetric::kRoutineTime, {"T, the routine's time of flight", "points"}},
      {ProgressMetric::kRoutineDisplacement,
       {"H, the routine's horizontal displacement", "points"}},
      {ProgressMetric::kFaults, {"execution faults per element", "faults"}}};
  if (PerRoutine(metric) && !fig_code.empty())
    throw InputError("", "--skill", "T and H are a routine's, not one skill's: leave out --skill");
  p.metric_name = kNames.at(metric).first;
  p.unit = kNames.at(metric).second;
  p.first_date = rows.front().session_date;
  for (const JumpRow& r : rows) p.first_date = std::min(p.first_date, r.session_date);

  std::vector<const JumpRow*> all;
  for (const JumpRow& r : rows) all.push_back(&r);
  const std::vector<std::pair<const JumpRow*, double>> values = MetricValues(all, metric, athlete);
  p.fault_counts = CountFaults(all, &p.elements);
  std::map<std::string, std::vector<double>> session_values;
  std::map<std::string, std::vector<const JumpRow*>> session_rows;
  for (const auto& [r, value] : values) {
    ProgressPoint point;
    point.date = r->session_date;
    point.day = DaysBetween(p.first_date, r->session_date);
    point.value = value;
    point.trial_path = r->trial_path;
    point.jump = PerRoutine(metric) ? 0 : r->jump.index;
    point.fig_code = PerRoutine(metric) ? std::string() : r->jump.fig_code;
    p.points.push_back(point);
    session_values[r->session_date].push_back(value);
  }
  for (const JumpRow* r : all) session_rows[r->session_date].push_back(r);
  for (const auto& [date, jumps] : session_rows)
    if (const auto v = session_values.find(date); v != session_values.end())
      p.sessions.push_back(SummarizeSession(date, jumps, v->second, p.first_date, metric));
  FitTrend(&p);
  return p;
}

std::string FormatProgressCsv(const Progress& p) {
  std::string out = fmt::format(
      "date,day,jumps,median_{0},min_{0},max_{0},landings,in_zone_a,elements,faults,most_frequent_"
      "fault\n",
      p.unit == "fraction" ? "pass_fraction" : p.unit);
  for (const SessionProgress& s : p.sessions)
    out += fmt::format("{},{:g},{},{:.4f},{:.4f},{:.4f},{},{},{},{},{}\n",
                       s.date,
                       s.day,
                       s.num_jumps,
                       s.median,
                       s.min,
                       s.max,
                       s.landing_x_m.size(),
                       s.landings_in_zone_a,
                       s.elements,
                       s.faults_reported,
                       s.most_frequent_fault);
  return out;
}

}  // namespace acro::library
