#include "acro/fig/synchro.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace acro::fig {

bool SynchroRules::IsValid(std::string* why) const {
  auto fail = [why](std::string text) {
    if (why != nullptr) *why = std::move(text);
    return false;
  };
  if (!(element_points > 0 && element_points <= 10))
    return fail(
        fmt::format("synchronisation element_points is {} (above 0, at most 10)", element_points));
  if (!(points_lost_per_s >= 0 && points_lost_per_s <= 1000))
    return fail(
        fmt::format("synchronisation points_lost_per_s is {} (0 to 1000)", points_lost_per_s));
  if (!(tolerance_s >= 0 && tolerance_s <= 1))
    return fail(fmt::format("synchronisation tolerance_s is {} (0 to 1 s)", tolerance_s));
  if (source.empty()) return fail("synchronisation: say where the conversion comes from (source)");
  return true;
}

namespace {

// The shape symbol at the end of a FIG code ("o", "<", "/"), or empty for a jump with none.
std::string ShapeOf(const std::string& code) {
  if (!code.empty() && (code.back() == 'o' || code.back() == '<' || code.back() == '/'))
    return code.substr(code.size() - 1);
  return "";
}

}  // namespace

SynchroScore ScoreSynchro(const SynchroRules& rules,
                          const RoutineScore& a,
                          const RoutineScore& b,
                          double b_clock_offset_s) {
  SynchroScore s;
  s.source = rules.source;
  const size_t n = std::min(a.elements.size(), b.elements.size());
  bool synchronised = true;
  double sum_abs = 0;
  for (size_t k = 0; k < n; ++k) {
    const ScoredElement& ea = a.elements[k];
    const ScoredElement& eb = b.elements[k];
    SynchroElement e;
    e.element = static_cast<int>(k) + 1;
    e.code_a = ea.code;
    e.code_b = eb.code;
    e.skills_match = ea.code == eb.code;
    e.shapes_match = ShapeOf(ea.code) == ShapeOf(eb.code);
    e.landing_difference_s = (eb.landing_s + b_clock_offset_s) - ea.landing_s;
    if (synchronised && !e.skills_match) {
      synchronised = false;
      s.ended_at_element = e.element;
      s.ending = fmt::format(
          "different skills at element {}: A {}, B {}{}: the synchronised routine ends there",
          e.element,
          ea.code,
          eb.code,
          e.shapes_match ? "" : " (different shapes)");
    }
    e.counted = synchronised;
    if (e.counted) {
      const double d = std::max(0.0, std::abs(e.landing_difference_s) - rules.tolerance_s);
      e.points = std::max(0.0, rules.element_points - rules.points_lost_per_s * d);
      s.score += e.points;
      ++s.elements_counted;
      sum_abs += std::abs(e.landing_difference_s);
      s.max_abs_difference_s = std::max(s.max_abs_difference_s, std::abs(e.landing_difference_s));
    }
    s.elements.push_back(std::move(e));
  }
  if (synchronised && a.elements.size() != b.elements.size()) {
    s.ended_at_element = static_cast<int>(n) + 1;
    s.ending =
        fmt::format("{} ends after {} elements, {} after {}: the synchronised routine ends there",
                    a.elements.size() < b.elements.size() ? "A" : "B",
                    n,
                    a.elements.size() < b.elements.size() ? "B" : "A",
                    std::max(a.elements.size(), b.elements.size()));
  }
  if (s.elements_counted > 0) s.mean_abs_difference_s = sum_abs / s.elements_counted;
  // Rounded as the sheets show points (to 0.001).
  s.score = std::round(s.score * 1000) / 1000;
  return s;
}

}  // namespace acro::fig
