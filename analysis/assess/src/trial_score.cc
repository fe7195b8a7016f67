// The score sheet of an analysed trial: its flights in the score sheet's terms, scored by the
// rules (analysis/fig), and written as JSON.

#include <cmath>

#include <nlohmann/json.hpp>

#include "acro/assess/trial_analysis.h"
#include "score_json.h"

namespace acro::analysis {

std::vector<fig::PerformedFlight> PerformedFlights(const TrialAnalysis& a,
                                                   const fig::HdZones& zones,
                                                   double landing_uncertainty_m) {
  std::vector<fig::PerformedFlight> out;
  for (const JumpMetrics& j : a.jumps) {
    fig::PerformedFlight f;
    f.skill = j.rotation.skill;
    f.takeoff = j.rotation.takeoff_position;
    f.landing = j.rotation.landing_position;
    f.time_of_flight_s = j.time_of_flight_s();
    f.landing_s = j.flight.landing_s;
    f.partial = j.partial();
    f.faults = j.execution;
    if (!j.landing_contacts_in_bed_m.empty())
      f.landing_zone =
          fig::ClassifyLanding(zones, j.landing_contacts_in_bed_m, landing_uncertainty_m);
    out.push_back(std::move(f));
  }
  return out;
}

fig::RoutineScore ScoreTrial(const TrialAnalysis& a,
                             const fig::RoutineRules& rules,
                             double landing_uncertainty_m) {
  return fig::ScoreRoutine(rules, PerformedFlights(a, rules.zones, landing_uncertainty_m));
}

nlohmann::ordered_json ElementScoreJson(const fig::ScoredElement& e) {
  using Json = nlohmann::ordered_json;
  Json o;
  o["element"] = e.element;
  o["flight"] = e.flight;
  o["code"] = e.code;
  o["difficulty"] = e.difficulty.total();
  o["difficulty_counted"] = e.difficulty_counted;
  o["note"] = e.note;
  o["time_of_flight_s"] = e.time_of_flight_s;
  if (e.landing_zone) {
    const fig::HdLanding& z = *e.landing_zone;
    o["landing"] = {{"zone", z.zone},
                    {"deduction", z.deduction},
                    {"margin_m", std::isfinite(z.margin_m) ? Json(z.margin_m) : Json(nullptr)},
                    {"close_call", z.uncertain}};
  } else {
    o["landing"] = nullptr;
  }
  o["requirements"] = e.requirements;
  // Every execution quantity measured, with the instant where it is worst; a suggested deduction
  // only where the fault is past the rules' threshold by more than the measurement's uncertainty.
  Json faults = Json::array();
  for (const fig::MeasuredFault& f : e.faults)
    faults.push_back({{"fault", f.fault},
                      {"quantity", f.quantity},
                      {"value", f.Measured() ? Json(f.value) : Json(nullptr)},
                      {"unit", f.unit},
                      {"uncertainty", f.uncertainty},
                      {"threshold", std::isfinite(f.threshold) ? Json(f.threshold) : Json(nullptr)},
                      {"time_s", std::isfinite(f.time_s) ? Json(f.time_s) : Json(nullptr)},
                      {"frame", f.frame},
                      {"reported", f.reported},
                      {"deduction", f.deduction},
                      {"frames", f.frames},
                      {"frames_seen", f.frames_seen}});
  o["execution"] = std::move(faults);
  o["execution_deduction"] = e.execution_deduction;
  return o;
}

std::string FormatScoreJson(const fig::RoutineScore& s) {
  using Json = nlohmann::ordered_json;
  Json o;
  o["rules"] = s.rules_name;
  o["rules_source"] = s.rules_source;
  o["zones_source"] = s.zones_source;
  o["elements_expected"] = s.expected_elements;
  o["elements_performed"] = s.elements.size();
  o["interrupted"] = s.interrupted;
  o["interruption"] = s.interruption;
  o["D"] = s.difficulty;
  o["D_uncapped"] = s.difficulty_uncapped;
  o["D_capped"] = s.difficulty_capped;
  o["T"] = s.time_of_flight;
  o["time_of_flight_sum_s"] = s.time_of_flight_sum_s;
  o["H"] = s.horizontal_displacement ? Json(*s.horizontal_displacement) : Json(nullptr);
  o["close_calls"] = s.close_calls;
  o["E"] = nullptr;  // the judges' (docs/scoring.md)
  o["penalty"] = s.penalty;
  o["faults_reported"] = s.faults_reported;
  o["execution_deductions_suggested"] = s.execution_deductions;
  o["requirements_missing"] = s.requirements_missing;
  o["rule_breaks"] = s.rule_breaks;
  o["valid"] = s.valid();
  o["total_without_execution"] = s.total_without_execution;
  Json elements = Json::array();
  for (const fig::ScoredElement& e : s.elements) elements.push_back(ElementScoreJson(e));
  o["elements"] = std::move(elements);
  return o.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string FormatSynchroJson(const fig::SynchroScore& s,
                              const fig::RoutineScore& a,
                              const fig::RoutineScore& b) {
  using Json = nlohmann::ordered_json;
  Json o;
  o["S"] = s.score;
  o["conversion_source"] = s.source;
  o["elements_counted"] = s.elements_counted;
  o["ended_at_element"] = s.ended_at_element == 0 ? Json(nullptr) : Json(s.ended_at_element);
  o["ending"] = s.ending;
  o["mean_abs_landing_difference_s"] = s.mean_abs_difference_s;
  o["max_abs_landing_difference_s"] = s.max_abs_difference_s;
  Json elements = Json::array();
  for (const fig::SynchroElement& e : s.elements)
    elements.push_back({{"element", e.element},
                        {"code_a", e.code_a},
                        {"code_b", e.code_b},
                        {"skills_match", e.skills_match},
                        {"shapes_match", e.shapes_match},
                        {"landing_difference_s", e.landing_difference_s},
                        {"counted", e.counted},
                        {"points", e.points}});
  o["elements"] = std::move(elements);
  o["a"] = Json::parse(FormatScoreJson(a));
  o["b"] = Json::parse(FormatScoreJson(b));
  return o.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace acro::analysis
