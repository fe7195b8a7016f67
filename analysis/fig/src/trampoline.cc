#include "acro/fig/trampoline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

namespace acro::fig {

HdZones HdZones::Default() {
  HdZones z;
  const double ax = kZoneALength_m / 2, ay = kZoneAWidth_m / 2;
  const double bx = kBedLength_m / 2, by = kBedWidth_m / 2;
  z.zones = {
      {"A", -ax, ax, -ay, ay, 0.0}, {"B", -bx, bx, -ay, ay, 0.1}, {"C", -bx, bx, -by, by, 0.2}};
  z.outside_name = "off the bed";
  z.outside_deduction = 0.3;
  z.source =
      "zone A 2.15 m x 1.08 m from the Code of Points; the outer zones (B: A's long lines to the "
      "bed's ends, 0.1; C: the rest of the bed, 0.2; off the bed, 0.3) are assumed, not from a "
      "source";
  return z;
}

double HdZones::DeductionAt(const Eigen::Vector2d& p, std::string* zone) const {
  double best = outside_deduction;
  const std::string* name = &outside_name;
  for (const HdZone& r : zones) {
    if (r.Contains(p) && r.deduction < best) {
      best = r.deduction;
      name = &r.name;
    }
  }
  if (zone != nullptr) *zone = *name;
  return best;
}

bool HdZones::IsValid(std::string* why) const {
  auto fail = [&](std::string text) {
    if (why != nullptr) *why = std::move(text);
    return false;
  };
  auto deduction_ok = [](double d) { return std::isfinite(d) && d >= 0.0 && d <= 1.0; };
  if (!deduction_ok(outside_deduction))
    return fail(fmt::format("the deduction outside the zones is {} (0 to 1)", outside_deduction));
  for (const HdZone& r : zones) {
    for (double v : {r.x_min, r.x_max, r.y_min, r.y_max})
      if (!std::isfinite(v) || std::abs(v) > 10.0)
        return fail(
            fmt::format("zone {} reaches {} m from the bed's centre (at most 10 m)", r.name, v));
    if (r.x_min >= r.x_max || r.y_min >= r.y_max)
      return fail(fmt::format("zone {} is empty ({} to {} m along, {} to {} m across)",
                              r.name,
                              r.x_min,
                              r.x_max,
                              r.y_min,
                              r.y_max));
    if (!deduction_ok(r.deduction))
      return fail(fmt::format("zone {} costs {} (0 to 1)", r.name, r.deduction));
  }
  return true;
}

namespace {

// How far the rigid set of points can move along `u` before `changed` holds for the set. Marches in
// 5 mm steps, then bisects to 1 mm; +inf when nothing changes within `reach` (and its last step).
template <typename Changed>
double DistanceAlong(const std::vector<Eigen::Vector2d>& points,
                     const Eigen::Vector2d& u,
                     double reach,
                     const Changed& changed) {
  constexpr double kStep = 0.005;
  double inside = 0.0;
  // Up to the step that passes `reach`: a change closer than `reach` is found even inside the last
  // step.
  for (double s = kStep; s < reach + kStep; s += kStep) {
    if (changed(points, s * u)) {
      double lo = inside, hi = s;
      while (hi - lo > 0.001) {
        const double mid = 0.5 * (lo + hi);
        (changed(points, mid * u) ? hi : lo) = mid;
      }
      return hi;
    }
    inside = s;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

HdLanding ClassifyLanding(const HdZones& zones,
                          const std::vector<Eigen::Vector2d>& points,
                          double uncertainty_m) {
  HdLanding out;
  out.deduction = -1.0;
  for (const Eigen::Vector2d& p : points) {
    std::string name;
    const double d = zones.DeductionAt(p, &name);
    if (d > out.deduction) {
      out.deduction = d;
      out.zone = name;
    }
  }
  if (points.empty()) {
    out.deduction = zones.outside_deduction;
    out.zone = zones.outside_name;
    return out;
  }
  // The landing's deduction is the worst of its points: it changes when any point reaches a worse
  // zone, or when every point is out of the worst one.
  const double current = out.deduction;
  auto changed = [&](const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& shift) {
    double worst = -1.0;
    for (const Eigen::Vector2d& p : pts) worst = std::max(worst, zones.DeductionAt(p + shift));
    return std::abs(worst - current) > 1e-9;
  };
  // Every 2.5°, then every 0.1° around the two best directions: a landing off a zone's corner is
  // reached diagonally, where a coarse direction misses by up to 2 % of the distance.
  constexpr int kDirections = 144;
  constexpr double kReach = 3.0;
  auto along = [&](double a, double reach) {
    return DistanceAlong(
        points, Eigen::Vector2d(std::cos(a), std::sin(a)), std::min(kReach, reach), changed);
  };
  double margin = std::numeric_limits<double>::infinity();
  std::vector<std::pair<double, double>> coarse;  // distance, angle
  for (int k = 0; k < kDirections; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kDirections;
    const double d = along(a, std::numeric_limits<double>::infinity());
    coarse.emplace_back(d, a);
    margin = std::min(margin, d);
  }
  std::partial_sort(coarse.begin(), coarse.begin() + 2, coarse.end());
  const double step = 2.0 * std::numbers::pi / kDirections;
  for (int best = 0; best < 2 && std::isfinite(coarse[static_cast<size_t>(best)].first); ++best)
    for (int k = -25; k <= 25; ++k)
      margin = std::min(margin,
                        along(coarse[static_cast<size_t>(best)].second + k * step / 25.0, margin));
  out.margin_m = margin;
  out.uncertain = std::isfinite(margin) && margin <= uncertainty_m;
  return out;
}

}  // namespace acro::fig
