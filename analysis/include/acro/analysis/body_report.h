#pragma once

// What `acrolab body` prints: per-segment and whole-body mass, centre of mass and inertia about the
// centre of mass, and the somersault-axis inertia of the straight, piked and tucked shapes, as text
// or JSON (docs/cli.md). Also the parser of the command's pose specification.

#include <string>
#include <string_view>

#include "acro/analysis/athlete_body.h"

namespace acro::analysis {

/// Somersault-axis inertia (lateral axis through the centre of mass, kg·m²) of the three shapes a
/// coach names, and of the pose being reported.
struct ShapeInertias {
  double straight_kgm2 = 0.0;
  double pike_kgm2 = 0.0;
  double tuck_kgm2 = 0.0;
  double pose_kgm2 = 0.0;
};

/// `rest` is the reference-pose body, `posed` the reported one.
ShapeInertias CalcShapeInertias(const AthleteBody& rest, const AthleteBody& posed);

/// Parses "tuck", "pike", "straight", "NAME=DEG" entries separated by commas, in order (later
/// entries override earlier ones): "tuck,knee_flexion=120". Angles in degrees. Throws
/// acro::InputError (where "--pose") naming the entry at fault.
BodyPose ParseBodyPose(std::string_view spec);

/// Human-readable report. `pose_spec` is echoed ("" for the reference pose).
std::string FormatBodyReportText(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec);

/// JSON report: {"model", "height_m", "frame", "pose", "total": {"mass_kg", "com_m",
/// "inertia_com_kgm2" (3×3)}, "segments": [{"name", "mass_kg", "com_m", "inertia_com_kgm2",
/// "joint_m", "end_m"}], "somersault_inertia_kgm2": {"straight", "pike", "tuck", "pose"},
/// "somersault_ratio_straight_to_pose"}.
std::string FormatBodyReportJson(const AthleteBody& posed,
                                 const ShapeInertias& shapes,
                                 std::string_view pose_spec);

}  // namespace acro::analysis
