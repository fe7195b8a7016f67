#pragma once

// What `acrolab routine` writes for a designed routine (docs/cli.md): routine.json, the motion as
// C3D of the trampoline marker set with the bed's corners and as an OpenSim .mot, the centre of
// mass height over the routine, every skill's keyframes as a skill file, and a report page. The
// marker trial is also what the sample routine (tools/sample_routine.h) is made of. Every file is
// written atomically.

#include <filesystem>
#include <string>
#include <vector>

#include "acro/capture/storage.h"
#include "acro/capture/trial.h"
#include "acro/design/routine_design.h"
#include "acro/report/chart.h"

namespace acro::ui {

struct RoutineMarkerOptions {
  /// Gaussian noise on every coordinate (m; 0: none), one stream (Box–Muller on a 32-bit Mersenne
  /// Twister: the same numbers on every platform), markers then bed corners, frame by frame.
  double noise_sd_m = 0.0;
  unsigned noise_seed = 20261122;
};

/// The routine's frames seen through the "trampoline" marker set (placed for the athlete's height)
/// and four static markers BED_C1…BED_C4 at the corners of the woven bed at rest.
capture::Trial MakeRoutineMarkerTrial(const analysis::SimulatedRoutine& routine,
                                      const analysis::AthleteProfile& athlete,
                                      const RoutineMarkerOptions& options = {});

/// Root position (m), somersault, tilt and twist unwrapped (deg) and every joint angle (deg) per
/// frame.
capture::Storage MakeRoutineMotionTable(const analysis::SimulatedRoutine& routine,
                                        const std::string& name);

/// The centre of mass height above the bed over the routine, the flights shaded.
Chart MakeRoutineHeightChart(const analysis::RoutineDesignResult& result);

/// routine.json's text: the routine's DD and time of flight, the notes, every skill (code, name,
/// DD, flight: take-off and landing times, time of flight, take-off velocity, apex, angular
/// momentum, rotations, landing place) and every contact (times, push, peak force, depression).
std::string MakeRoutineJson(const analysis::RoutineDesignResult& result);

/// What the page shows beside the tables, made elsewhere (the 3D views draw the filmstrips).
struct RoutineReportExtras {
  /// One picture per skill (file names in the folder, in routine order), or why there are none.
  std::vector<std::string> filmstrips;
  std::string filmstrip_note;
  /// The routine as a video (file name in the folder; empty: none).
  std::string video;
};

/// Writes routine.json, routine.c3d, routine.mot, height.svg/.png, skills/NN.yaml (each skill's
/// keyframes) and report.html into `dir`. Returns the file names written.
std::vector<std::string> WriteRoutineOutputs(const std::filesystem::path& dir,
                                             const std::filesystem::path& final_dir,
                                             const analysis::RoutineDesignResult& result,
                                             const RoutineMarkerOptions& markers,
                                             const RoutineReportExtras& extras = {});

}  // namespace acro::ui
