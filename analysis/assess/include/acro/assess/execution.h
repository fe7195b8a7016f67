#pragma once

// The execution assistant (docs/scoring.md, "Execution"): for each flight, the measured quantity
// behind each fault judges deduct for — knee and elbow flexion, the legs' spread, the arms' lift,
// the body's bend in a straight shape, the trunk–thigh angle of a pike or tuck, the opening before
// landing, travel and loss of height — with the instant where it is worst, and the deduction the
// rules suggest when it is past their first threshold by more than the measurement's uncertainty.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "acro/fig/rules.h"
#include "acro/fig/score_sheet.h"

namespace acro::analysis {

struct TrialAnalysis;

/// How far each kind of measurement may be off for this input. The defaults are motion capture's:
/// joint angles from skin markers by inverse kinematics are good to a few degrees (soft tissue
/// moves the markers by 1–2 cm over segments of 30–45 cm), feet and the COM to the 3 cm the
/// landing's outline already carries, times to two frames at 200 Hz.
struct ExecutionOptions {
  double angle_uncertainty_deg = 5.0;
  /// The elbows' (a forearm is short: its angle moves most with the markers' noise).
  double elbow_uncertainty_deg = 5.0;
  double position_uncertainty_m = 0.03;
  double time_uncertainty_s = 0.01;
  /// Each uncertainty grows with the trial's measured noise beyond motion capture's
  /// (`WithNoise`); AnalyzeTrial applies it when true.
  bool scale_with_noise = true;
  /// Frames this close to the take-off are not the element's (the bed's push still in the body),
  /// nor those this close to the landing (its preparation: knees and hips bend to meet the bed —
  /// the sample's athlete starts 0.33 s before touch-down, to 20° of knee and 29° of hip flexion).
  /// The opening before landing is measured up to the landing itself.
  double takeoff_edge_s = 0.05;
  double landing_edge_s = 0.35;
  /// The camera's centre (the trial's world) when one camera alone saw the motion: along its rays
  /// the fitted body is the fit's guess, not a measurement. A joint angle is then measured only
  /// where its limb's plane faces the camera (within 60° of the picture's plane), the legs' spread
  /// across the view only (where the hips' axis is within 30° of the picture's plane), and a
  /// keypoint agrees with the fit by its distance across the ray. Empty: several cameras, markers.
  std::optional<Eigen::Vector3d> single_camera_centre_W;
  bool IsValid(std::string* why) const;
  /// The uncertainties for a trial whose noise is `noise_rms_m` per coordinate (the physical
  /// check's Winter estimate): each grows by its sensitivity times the noise beyond 2 mm (motion
  /// capture's, which the defaults already carry) — per mm, 0.4° for joint angles, 1.5° for the
  /// elbows, 1.5 mm for positions, 1 ms for times. The sensitivities are the largest changes seen
  /// when the sample routine's markers were given 5–30 mm of white noise (three draws each,
  /// tests/analysis/assess/execution_noise_test.cc; docs/scoring.md, "Noise").
  ExecutionOptions WithNoise(double noise_rms_m) const;
};

/// The measurements of flight `jump` (0-based index into analysis.jumps); empty for a partial
/// flight. Every measure applicable to the element's shape is returned, reported or not.
std::vector<fig::MeasuredFault> MeasureExecution(const TrialAnalysis& analysis,
                                                 size_t jump,
                                                 const fig::ExecutionRules& rules,
                                                 const ExecutionOptions& options);

}  // namespace acro::analysis
