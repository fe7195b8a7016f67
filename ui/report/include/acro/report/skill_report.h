#pragma once

// What `acrolab optimize` writes for a designed skill: result.json, the timing table (CSV) and plot
// (initial vs optimised keyframe times), the angular-momentum plot, the motion as C3D virtual
// markers and as an OpenSim .mot, and an HTML report page that shows them. Every file is written
// atomically.

#include <filesystem>
#include <string>
#include <vector>

#include "acro/capture/storage.h"
#include "acro/capture/trial.h"
#include "acro/design/skill_from_code.h"
#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"
#include "acro/report/chart.h"

namespace acro::ui {

/// result.json's text (keyframe_names, keyframe_times_initial_s, keyframe_times_s,
/// objective_initial, objective, angular_momentum_variation(_initial), model, solver, simulation).
std::string MakeSkillResultJson(const analysis::SkillDesign& design,
                                const analysis::SkillOptimizationResult& result,
                                const analysis::SkillSimulationResult* simulation);

/// design.json's text for a skill designed from its FIG code: the code, its difficulty, the
/// take-off it needs (vertical velocity, flight time, angular momentum: somersault, twist,
/// normalised), the aerial twist actions, the flight (somersaults, twists, half twists per
/// somersault, tilt, time left to prepare the landing) and the feasibility with its reasons.
std::string MakeSkillFromCodeJson(const analysis::SkillFromCodeResult& result);

/// The designed motion sampled at `rate_hz`: the standard human's named points as virtual markers.
capture::Trial MakeSkillMarkerTrial(const analysis::SkillDesign& design,
                                    const analysis::SkillTrajectory& trajectory,
                                    double rate_hz = 100.0);

/// The designed motion sampled at `rate_hz`: root position (m), root orientation as somersault,
/// tilt, twist unwrapped (deg) and every joint angle (deg).
capture::Storage MakeSkillMotionTable(const analysis::SkillDesign& design,
                                      const analysis::SkillTrajectory& trajectory,
                                      double rate_hz = 100.0);

/// The keyframe times, initial and optimised, against the keyframe number (the paper's Figure 7).
Chart MakeSkillTimingChart(const analysis::SkillDesign& design,
                           const analysis::SkillOptimizationResult& result);

/// |H| about the centre of mass over the flight, the initial timing against the optimised one
/// (constant for a motion that obeys physics in flight).
Chart MakeSkillMomentumChart(const analysis::SkillDesign& design,
                             const analysis::SkillOptimizationResult& result);

/// What the page shows beside the charts, made elsewhere (the 3D views draw the filmstrips).
struct SkillReportExtras {
  /// The initial and the optimised timing one above the other (file names in the folder; empty:
  /// none), or why there is none.
  std::string filmstrip;
  std::string filmstrip_video;
  std::string filmstrip_note;
  /// The instants the filmstrip shows (s from take-off).
  std::vector<double> filmstrip_times_s;
  /// A skill designed from its FIG code (`acrolab design`): what its take-off needs and whether the
  /// athlete can do it, one sentence per line (FormatSkillFromCode), shown first; empty: none.
  std::vector<std::string> design_lines;
};

/// Writes result.json, timing.csv, timing.svg/.png, angular_momentum.svg/.png, motion.c3d,
/// motion.mot and report.html into `dir` (created if needed). Returns the file names written.
std::vector<std::string> WriteSkillOutputs(const std::filesystem::path& dir,
                                           const analysis::SkillDesign& design,
                                           const analysis::SkillOptimizationResult& result,
                                           const analysis::SkillSimulationResult* simulation,
                                           const SkillReportExtras& extras = {});

}  // namespace acro::ui
