#pragma once

// The main job: a recorded trial → the athlete's motion → a verdict on the data → the numbers of
// every jump (docs/metrics.md, docs/physical-check.md). Steps, each reported in the result:
// reconstruction (reconstruction.h), flight and contact phases (phases.h: from force plates when
// the trial has them, otherwise from the whole-body COM), the physical-correctness check with its
// localisation (physical_check.h), and per flight the jump metrics — time of flight, apex, take-off
// velocity, horizontal displacement, somersaults, twists, shape, FIG code and difficulty.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/assess/execution.h"
#include "acro/assess/jump_rotation.h"
#include "acro/assess/noise_floor.h"
#include "acro/assess/physical_check.h"
#include "acro/athlete/athlete_body.h"
#include "acro/capture/storage.h"
#include "acro/capture/trial.h"
#include "acro/fig/rules.h"
#include "acro/fig/score_sheet.h"
#include "acro/fig/skill.h"
#include "acro/fig/synchro.h"
#include "acro/fig/trampoline.h"
#include "acro/reconstruct/phases.h"
#include "acro/reconstruct/reconstruction.h"

namespace acro::analysis {

/// The trampoline bed as the trial shows it: the centre of the woven bed at rest (the cross), its
/// long axis (horizontal, unit) and size.
struct BedGeometry {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d long_axis_W = Eigen::Vector3d::UnitX();
  double length_m = fig::kBedLength_m;  ///< FIG norms: the woven bed is about 4.28 m × 2.14 m
  double width_m = fig::kBedWidth_m;
  std::string source;  ///< "markers BED_C1–BED_C4", "option"
};

/// The bed from four static markers at the corners of the woven bed: points whose labels start
/// with "BED" (any case) and that are present in at least half of the frames. Centre = the mean of
/// their median positions; long axis along the longer pair of opposite sides. Nothing when fewer
/// than four such markers exist.
std::optional<BedGeometry> FindBed(const capture::Trial& trial);

struct TrialAnalysisOptions {
  ReconstructionOptions reconstruction;
  PhaseOptions phases;
  /// Use the trial's force plates for the phases when it has any (else the whole-body COM).
  bool use_force_plates = true;
  PhysicalCheckOptions check;
  /// Judge the flights against what the trial's measured noise alone gives them (noise_floor.h;
  /// docs/physical-check.md): for clean markers the thresholds stay as they are.
  bool judge_against_noise = true;
  NoiseFloorOptions noise_floor;
  JumpRotationOptions rotation;
  /// Localise a failed verdict (swaps, timing, segment masses, worst markers).
  bool localise = true;
  /// The bed; empty: found from the trial's markers (FindBed) when it has them.
  std::optional<BedGeometry> bed;
  /// Without a bed: the height of the surface the athlete takes off from (a trampoline bed at rest,
  /// 1.155 m above the floor by the FIG norms; the floor), so that the phases come from the soles.
  /// Empty: the phases come from the COM.
  std::optional<double> surface_height_m;
  /// Flights timed elsewhere (take-off, landing in the trial's seconds; NaN: outside the
  /// recording): they replace the phases from the feet or the COM — one camera's picture, whose
  /// soles are surer than its 3D feet (docs/one-camera.md). `given_flights_source` names them.
  std::vector<std::pair<double, double>> given_flights_s;
  std::string given_flights_source;
  /// The rules the routine is scored by (the score sheet, docs/scoring.md).
  fig::RoutineRules rules = fig::RoutineRules::FigSenior();
  /// How far a landing's contact points may be off (m): a zone margin within it is a close call.
  /// Markers: the feet's outline is the model's (de Leva's proportions: the heel 20 % of the
  /// foot's length behind the ankle, the sole 38 % of it wide), not measured — about 3 cm, the
  /// competition devices' own figure (docs/scoring.md).
  double landing_uncertainty_m = 0.03;
  /// The execution assistant's uncertainties (execution.h): motion capture's by default.
  ExecutionOptions execution;
  /// One line per step ("reconstruct: …", "phases: …") as the analysis goes.
  std::function<void(const std::string&)> progress;
  /// Asked between the steps and, unless reconstruction.cancelled is set, every ten frames of the
  /// inverse kinematics: true stops the analysis, which throws acro::Cancelled.
  std::function<bool()> cancelled;

  bool IsValid(std::string* why) const;
};

/// The numbers of one flight (one skill).
struct JumpMetrics {
  int index = 0;  ///< 1-based, in the order of the flights
  Flight flight;  ///< events and the COM parabola
  /// Cut by the start or end of the recording: flagged, not scored.
  bool partial() const { return flight.partial; }
  double time_of_flight_s() const { return flight.time_of_flight_s(); }
  double apex_m() const { return flight.apex_z_m; }  ///< COM apex height in W (z)
  double takeoff_vertical_velocity_m_per_s() const {
    return flight.takeoff_vertical_velocity_m_per_s;
  }
  /// COM apex above the surface at rest (the bed's, the one given or the estimated; else NaN).
  double apex_above_bed_m = 0.0;
  /// Midpoint of the soles at take-off and at landing (interpolated at the event times), in W.
  Eigen::Vector3d takeoff_feet_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d landing_feet_W = Eigen::Vector3d::Zero();
  /// Horizontal distance of the landing from the take-off (m).
  double displacement_from_takeoff_m = 0.0;
  /// Horizontal distance of the landing from the bed's centre, and the landing in the bed's axes
  /// (along the long axis, across it), when the bed is known (else NaN).
  double displacement_from_centre_m = 0.0;
  Eigen::Vector2d landing_in_bed_m = Eigen::Vector2d::Zero();
  /// Whether the landing lies in the FIG zone A (2.15 m × 1.08 m about the centre), when known.
  std::optional<bool> landing_in_zone_a;
  /// What touches the bed at landing, in the bed's axes, when the bed is known: the corners of both
  /// soles for a landing on the feet ("any part of a foot"), the hip joint centres for a landing on
  /// the front or back ("the hip joint portion", Code of Points, horizontal displacement).
  std::vector<Eigen::Vector2d> landing_contacts_in_bed_m;
  /// The execution assistant's measurements of this flight (execution.h), by the options' rules.
  std::vector<fig::MeasuredFault> execution;
  JumpRotation rotation;
  std::string fig_code;
  std::string skill_name;  ///< the usual name ("barani"), or empty
  fig::FigDifficulty difficulty;
  /// The physical check of this flight (when judged), else nothing.
  std::optional<FlightCheck> check;
  std::string verdict;  ///< "pass", "fail: …", or "not judged: …"
  /// With a calibrated video (analysis/scene's CheckSilhouettes): the median intersection over
  /// union of the video's athlete and the reconstructed one over the flight's frames.
  std::optional<double> silhouette_iou;
};

struct TrialAnalysis {
  std::string trial_name;
  ReconstructionResult reconstruction;
  PhaseSegmentation phases;
  PhysicalCheck check;
  PhysicalCheckOptions check_options;  ///< the thresholds the check used
  /// The uncertainties the execution assistant used (its options grown with this trial's noise).
  ExecutionOptions execution_options;
  std::optional<BedGeometry> bed;
  /// With no bed and no surface height given: the surface estimated from the soles and the COM
  /// (EstimateContactSurface), from which the phases then come.
  std::optional<SurfaceEstimate> surface;
  /// The surface height the options gave (when there is no bed).
  std::optional<double> surface_height_m;
  /// The height the athlete takes off from: the bed's, the one given or the estimate's.
  std::optional<double> SurfaceHeight() const;
  /// Where that height comes from, one line ("bed at rest 1.155 m from markers BED_C1–BED_C4",
  /// "bed at rest 1.075 m (spread …), estimated from the soles and the COM", "no surface known").
  std::string SurfaceSource() const;
  std::vector<JumpMetrics> jumps;
  /// The routine's score sheet by the options' rules (H only with a bed).
  fig::RoutineScore score;
  /// Routine totals over the complete (scored) skills: DD and the time of flight the judges sum.
  int num_scored = 0;
  double total_difficulty = 0.0;
  double total_time_of_flight_s = 0.0;
  double stature_m = 0.0;  ///< the height the moments are normalised by
  double mass_kg = 0.0;
  /// The lowest sole's height per frame (the COM per frame is check.frames.com_W).
  Eigen::VectorXd feet_z_m;
  std::vector<std::string> warnings;
  /// Wall time of the steps (s).
  double reconstruct_s = 0.0;
  double check_s = 0.0;
  double metrics_s = 0.0;
  /// A few lines: routine summary, verdict, per-jump codes.
  std::string BriefReport() const;
};

/// Runs the whole analysis. `static_trial` (optional) scales the model. Throws acro::InputError
/// for invalid options or when no marker set matches the trial.
TrialAnalysis AnalyzeTrial(const capture::Trial& trial,
                           const capture::Trial* static_trial,
                           const AthleteBody& body,
                           const TrialAnalysisOptions& options = {});

/// The flights of an analysis as the score sheet reads them: skill, positions, time of flight and,
/// with a bed, the landing's zone by `zones` (a margin within `landing_uncertainty_m` a close
/// call).
std::vector<fig::PerformedFlight> PerformedFlights(const TrialAnalysis& analysis,
                                                   const fig::HdZones& zones,
                                                   double landing_uncertainty_m);
/// The score sheet of an analysis by `rules` (AnalyzeTrial fills TrialAnalysis::score with it).
fig::RoutineScore ScoreTrial(const TrialAnalysis& analysis,
                             const fig::RoutineRules& rules,
                             double landing_uncertainty_m);
/// The score sheet as JSON (score.json; docs/cli.md).
std::string FormatScoreJson(const fig::RoutineScore& score);
/// synchro.json: a synchro pair's elements (codes, landing-time difference, matches), S, where
/// the synchronised routine ended, and both routines' score sheets.
std::string FormatSynchroJson(const fig::SynchroScore& synchro,
                              const fig::RoutineScore& a,
                              const fig::RoutineScore& b);

/// A flight's rotation as coaches count it, frame by frame from its take-off frame to its landing
/// frame: the somersault about the pelvis's lateral axis at take-off and the twist, both from 0 at
/// take-off (degrees; backward somersaults negative, as the metrics count them).
struct FlightRotation {
  std::vector<int> frames;
  std::vector<double> somersault_deg;
  std::vector<double> twist_deg;
};
/// For jump `jump` (1-based, as jumps.json numbers them); empty for a jump that is not there.
FlightRotation CalcFlightRotation(const TrialAnalysis& analysis, int jump);
/// The same for frames `first` to `last` of any motion of a standard human (a designed skill's):
/// the somersault about the pelvis's lateral axis at `first`, the twist, both from 0 there. Empty
/// when the frames are not in the motion.
FlightRotation CalcMotionRotation(const Motion& motion, int first, int last);

/// Where the feet are in configuration `q` of `model` (a standard human, with r_toe and l_toe
/// points): the midpoint of the two sole centres, as the jumps' take-off and landing feet are
/// measured (JumpMetrics::takeoff_feet_W).
Eigen::Vector3d CalcFeetCentre(const dynamics::Model<double>& model, const Eigen::VectorXd& q);

/// The jumps as a JSON array, one object per flight (docs/cli.md, "acrolab analyze").
std::string FormatJumpsJson(const TrialAnalysis& analysis);

/// Per frame: time, phase (flight k / contact), root residual force (BW) and moment (BW·h) in W
/// with their norms, angular momentum about the COM (kg·m²/s), COM position (m), the lowest sole's
/// height (m).
std::string FormatResidualsCsv(const TrialAnalysis& analysis);

/// The joint torques as an OpenSim .sto table (N·m, one column per joint axis, named by the
/// coordinates: `r_hip_flexion_moment`, …).
capture::Storage MakeTorqueStorage(const TrialAnalysis& analysis);

/// Writes DIR/jumps.json, DIR/score.json, DIR/angles.mot, DIR/torques.sto and DIR/residuals.csv
/// (each atomically).
void WriteAnalysisTables(const TrialAnalysis& analysis, const std::filesystem::path& dir);

}  // namespace acro::analysis
