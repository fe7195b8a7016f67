#pragma once

// The competition trampoline as the FIG describes it, and where a landing falls on its bed: the
// apparatus (FIG Apparatus Norms, trampoline), the horizontal-displacement zones and the deduction
// a landing costs (Code of Points, trampoline, "Horizontal displacement"). One place for every
// layer: the bed's size used to sit in four files and zone A in two.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::fig {

/// FIG Apparatus Norms, trampoline: the woven bed about 4.28 m × 2.14 m, the frame 5.05 m × 2.91 m
/// outside, the bed 1.155 m above the floor.
inline constexpr double kBedLength_m = 4.28;
inline constexpr double kBedWidth_m = 2.14;
inline constexpr double kFrameLength_m = 5.05;
inline constexpr double kFrameWidth_m = 2.91;
inline constexpr double kBedHeight_m = 1.155;
/// Zone A: 215 × 108 cm (± 4 cm) about the bed's centre, its red lines (13–24 mm wide) belonging
/// to it (Code of Points, trampoline, bed markings; as quoted by tramponline.eu's HD page).
inline constexpr double kZoneALength_m = 2.15;
inline constexpr double kZoneAWidth_m = 1.08;
inline constexpr double kZoneATolerance_m = 0.04;

/// One horizontal-displacement zone: an axis-aligned rectangle in the bed's axes (x along the
/// bed's long axis, y across, metres from the centre), and the deduction a landing in it costs.
/// Several rectangles may share a name (a zone in two strips).
struct HdZone {
  std::string name;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  double deduction = 0;
  bool Contains(const Eigen::Vector2d& p) const {
    return p.x() >= x_min && p.x() <= x_max && p.y() >= y_min && p.y() <= y_max;
  }
};

/// The zones of one rule set. A point's deduction is the smallest of the zones that contain it
/// (lines belong to the zone they bound), the `outside` deduction where none does.
struct HdZones {
  std::vector<HdZone> zones;
  std::string outside_name = "outside";
  double outside_deduction = 0.3;
  /// Where the sizes come from, said on every score sheet ("zone A: Code of Points; B: assumed").
  std::string source;

  /// The default set: zone A as the Code gives it (0.0), the rest of the bed between A's long
  /// lines continued to the bed's ends (0.1), the bed beside them (0.2), off the bed (0.3). Only
  /// zone A's size is from a source; the split of the outer deductions is an assumption a rule
  /// file replaces (docs/scoring.md).
  static HdZones Default();
  /// The deduction and zone name at one point.
  double DeductionAt(const Eigen::Vector2d& p_bed, std::string* zone = nullptr) const;
  bool IsValid(std::string* why) const;
};

/// Where a landing falls: the worst zone any of its contact points touches ("any part of a foot";
/// for front, back and seat landings, the hip region), that zone's deduction, and the margin — how
/// far the whole landing could move before its deduction changes (the distance to the nearest line
/// that matters), so a coach sees a 2 cm call as one.
struct HdLanding {
  std::string zone;
  double deduction = 0;
  double margin_m = 0;
  /// The margin is inside the measurement's uncertainty: the call could go either way.
  bool uncertain = false;
};

/// Classifies a landing from its contact points in the bed's axes (at least one). The margin is
/// searched along every direction (2.5°, refined to 0.1° around the best) to 1 mm, out to 3 m.
/// `uncertainty_m` marks close calls.
HdLanding ClassifyLanding(const HdZones& zones,
                          const std::vector<Eigen::Vector2d>& contact_points_bed,
                          double uncertainty_m);

}  // namespace acro::fig
