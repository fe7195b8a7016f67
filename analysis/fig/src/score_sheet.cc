#include "acro/fig/score_sheet.h"

#include "acro/base/input_error.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include <fmt/format.h>

namespace acro::fig {
namespace {

bool IsStraightJump(const FigSkill& s) {
  return s.quarter_somersaults == 0 && s.total_half_twists() == 0 &&
         s.shape == SkillShape::kStraight;
}

// What makes two elements the same element: code, direction, take-off and landing positions.
std::string ElementKey(const PerformedFlight& f) {
  return fmt::format("{}|{}|{}|{}",
                     FormatFigCode(f.skill),
                     static_cast<int>(f.skill.direction),
                     static_cast<int>(f.takeoff),
                     static_cast<int>(f.landing));
}

bool Meets(const ElementRequirement& r, const PerformedFlight& f) {
  auto in = [](const std::vector<BodyPosition>& allowed, BodyPosition p) {
    return allowed.empty() || std::find(allowed.begin(), allowed.end(), p) != allowed.end();
  };
  return f.skill.quarter_somersaults >= r.min_quarter_somersaults &&
         f.skill.total_half_twists() >= r.min_half_twists && in(r.landing, f.landing) &&
         in(r.takeoff, f.takeoff) &&
         (r.direction == SomersaultDirection::kNone || r.direction == f.skill.direction);
}

// Each requirement needs an element of its own: a maximum bipartite matching (augmenting paths).
// Returns, per requirement, the element (index into `elements`) or -1.
std::vector<int> MatchRequirements(const std::vector<ElementRequirement>& reqs,
                                   const std::vector<const PerformedFlight*>& elements) {
  std::vector<int> req_of_element(elements.size(), -1), element_of_req(reqs.size(), -1);
  std::function<bool(size_t, std::vector<char>&)> augment = [&](size_t r, std::vector<char>& seen) {
    for (size_t e = 0; e < elements.size(); ++e) {
      if (seen[e] || !Meets(reqs[r], *elements[e])) continue;
      seen[e] = 1;
      if (req_of_element[e] < 0 || augment(static_cast<size_t>(req_of_element[e]), seen)) {
        req_of_element[e] = static_cast<int>(r);
        element_of_req[r] = static_cast<int>(e);
        return true;
      }
    }
    return false;
  };
  for (size_t r = 0; r < reqs.size(); ++r) {
    std::vector<char> seen(elements.size(), 0);
    augment(r, seen);
  }
  return element_of_req;
}

}  // namespace

double MeasuredFault::ThresholdRatio() const {
  if (!std::isfinite(threshold) || threshold <= 0 || !std::isfinite(value))
    return std::numeric_limits<double>::quiet_NaN();
  if (!smaller_is_worse) return value / threshold;
  return value > 0 ? threshold / value : std::numeric_limits<double>::infinity();
}

std::string DescribeUnmeasured(const ScoredElement& element) {
  std::string out;
  for (const MeasuredFault& f : element.faults)
    if (!f.Measured())
      out += fmt::format("{}{} (seen in {} of {} frames)",
                         out.empty() ? "" : ", ",
                         f.fault,
                         f.frames_seen,
                         f.frames);
  return out;
}

std::vector<PerformedFlight> PlannedFlights(std::string_view codes) {
  std::vector<PerformedFlight> out;
  size_t k = 0;
  while (k < codes.size()) {
    const size_t start = codes.find_first_not_of(" ,\t\r\n", k);
    if (start == std::string_view::npos) break;
    const size_t end = std::min(codes.find_first_of(" ,\t\r\n", start), codes.size());
    if (out.size() == 100) throw InputError("", "codes", "more than 100 skills");
    PerformedFlight f;
    f.skill = ParseFigCode(codes.substr(start, end - start));
    out.push_back(std::move(f));
    k = end;
  }
  if (out.empty()) throw InputError("", "codes", "no FIG code given");
  return out;
}

double TruncateTimeOfFlight(double sum_s, double step) {
  if (!(step > 0.0) || !std::isfinite(sum_s)) return sum_s;
  // A hair of tolerance so that 0.0150000000001 s of rounding in the sum does not lose a step.
  return std::floor(sum_s / step + 1e-9) * step;
}

RoutineScore ScoreRoutine(const RoutineRules& rules, const std::vector<PerformedFlight>& flights) {
  RoutineScore s;
  s.rules_name = rules.name;
  s.rules_source = rules.source;
  s.zones_source = rules.zones.source;
  s.expected_elements = rules.elements;
  // 1. The routine's flights: from the first complete flight that is not a straight jump.
  size_t first = 0;
  while (first < flights.size() && (flights[first].partial || IsStraightJump(flights[first].skill)))
    ++first;
  std::vector<const PerformedFlight*> elements;
  std::vector<int> flight_index;
  for (size_t i = first; i < flights.size() && static_cast<int>(elements.size()) < rules.elements;
       ++i) {
    const PerformedFlight& f = flights[i];
    if (f.partial) {
      s.interrupted = true;
      s.interruption = fmt::format(
          "flight {} was cut by the recording after {} element(s)", i + 1, elements.size());
      break;
    }
    if (IsStraightJump(f.skill)) {
      s.interrupted = true;
      s.interruption =
          fmt::format("a straight jump (flight {}) after {} element(s)", i + 1, elements.size());
      break;
    }
    elements.push_back(&f);
    flight_index.push_back(static_cast<int>(i) + 1);
  }
  if (!s.interrupted && static_cast<int>(elements.size()) < rules.elements) {
    s.interrupted = true;
    s.interruption = elements.empty() ? "no element: every flight is a straight jump or cut"
                                      : fmt::format("the routine ends after {} of {} elements",
                                                    elements.size(),
                                                    rules.elements);
  }
  // 2. Per element: difficulty (a repeat gets none), flight, landing.
  std::map<std::string, int> seen;
  int tenths = 0;
  bool hd_known = !elements.empty();
  double hd = 0.0;
  int below_270 = 0;
  for (size_t k = 0; k < elements.size(); ++k) {
    const PerformedFlight& f = *elements[k];
    ScoredElement e;
    e.element = static_cast<int>(k) + 1;
    e.flight = flight_index[k];
    e.code = FormatFigCode(f.skill);
    e.name = FigSkillName(f.skill);
    e.difficulty = CalcFigDifficulty(f.skill);
    e.time_of_flight_s = f.time_of_flight_s;
    e.landing_s = f.landing_s;
    e.landing_zone = f.landing_zone;
    e.faults = f.faults;
    for (const MeasuredFault& m : f.faults) {
      if (!m.reported) continue;
      e.execution_deduction += m.deduction;
      ++s.faults_reported;
    }
    e.execution_deduction = std::min(e.execution_deduction, 0.5);
    s.execution_deductions += e.execution_deduction;
    const std::string key = ElementKey(f);
    if (rules.difficulty == DifficultyCounted::kNone) {
      e.difficulty_counted = false;
      e.note = "this routine's difficulty is not counted";
    } else if (const auto it = seen.find(key); rules.different_elements && it != seen.end()) {
      e.difficulty_counted = false;
      e.note = fmt::format("repeats element {}: no difficulty", it->second);
    } else {
      seen.emplace(key, e.element);
    }
    if (e.difficulty_counted) tenths += e.difficulty.total_tenths();
    s.time_of_flight_sum_s += f.time_of_flight_s;
    if (f.landing_zone) {
      hd += 1.0 - f.landing_zone->deduction;
      if (f.landing_zone->uncertain) ++s.close_calls;
    } else {
      hd_known = false;
    }
    if (f.skill.quarter_somersaults < 3) ++below_270;
    s.elements.push_back(std::move(e));
  }
  // 3. The routine's marks.
  s.difficulty_uncapped = tenths / 10.0;
  s.difficulty = s.difficulty_uncapped;
  if (rules.max_difficulty && s.difficulty > *rules.max_difficulty + 1e-9) {
    s.difficulty = *rules.max_difficulty;
    s.difficulty_capped = true;
  }
  s.time_of_flight = TruncateTimeOfFlight(s.time_of_flight_sum_s, rules.time_of_flight_step);
  if (hd_known) s.horizontal_displacement = hd;
  // 4. Requirements: each needs its own element.
  const std::vector<int> match = MatchRequirements(rules.requirements, elements);
  for (size_t r = 0; r < rules.requirements.size(); ++r) {
    if (match[r] < 0) {
      s.requirements_missing.push_back(rules.requirements[r].name);
      s.penalty += rules.missing_requirement_penalty;
    } else {
      s.elements[static_cast<size_t>(match[r])].requirements.push_back(rules.requirements[r].name);
    }
  }
  if (rules.max_elements_below_270 && below_270 > *rules.max_elements_below_270)
    s.rule_breaks.push_back(fmt::format("{} elements below 270° of somersault (at most {})",
                                        below_270,
                                        *rules.max_elements_below_270));
  if (rules.different_elements && rules.difficulty == DifficultyCounted::kAll) {
    for (const ScoredElement& e : s.elements)
      if (!e.difficulty_counted)
        s.rule_breaks.push_back(fmt::format("element {} ({}) {}", e.element, e.code, e.note));
  }
  s.total_without_execution =
      s.difficulty + s.time_of_flight + s.horizontal_displacement.value_or(0.0) - s.penalty;
  return s;
}

}  // namespace acro::fig
