#pragma once

// What `acrolab body` prints: per-segment and whole-body mass, centre of mass and inertia about the
// centre of mass, and the somersault-axis inertia of the straight, piked and tucked shapes, as text
// or JSON (docs/cli.md).

#include <string>
#include <string_view>

#include "acro/athlete/athlete_body.h"

namespace acro::ui {

/// Human-readable report. `pose_spec` is echoed ("" for the reference pose).
std::string FormatBodyReportText(const analysis::AthleteBody& posed,
                                 const analysis::ShapeInertias& shapes,
                                 std::string_view pose_spec);

/// JSON report: {"model", "height_m", "frame", "pose", "total": {"mass_kg", "com_m",
/// "inertia_com_kgm2" (3×3)}, "segments": [{"name", "mass_kg", "com_m", "inertia_com_kgm2",
/// "joint_m", "end_m"}], "somersault_inertia_kgm2": {"straight", "pike", "tuck", "pose"},
/// "somersault_ratio_straight_to_pose"}.
std::string FormatBodyReportJson(const analysis::AthleteBody& posed,
                                 const analysis::ShapeInertias& shapes,
                                 std::string_view pose_spec);

}  // namespace acro::ui
