#pragma once

// Reconstruction: a Trial of markers or video keypoints → the athlete's Motion. Steps, each
// reported in the summary: marker set (given or detected from the labels), gap filling, zero-lag
// low-pass filtering (cutoff by residual analysis unless given), scaling of the standard human to a
// static trial or to a window of the motion, per-frame inverse kinematics warm-started from the
// previous frame with left/right swap repair, run in parallel over independent chunks of frames.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/motion.h"
#include "acro/capture/trial.h"
#include "acro/dynamics/model.h"
#include "acro/reconstruct/butterworth.h"
#include "acro/reconstruct/flight_physics.h"
#include "acro/reconstruct/gap_filling.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"
#include "acro/reconstruct/scaling.h"
#include "acro/reconstruct/view_fit.h"

namespace acro::analysis {

/// The point rates the reconstruction takes (docs/limits.md): below 10 Hz the residual analysis
/// has nothing to scan and a flight of 1 s has fewer than ten samples; above 100 kHz no motion
/// capture records (high-speed video tops out there), and the rate is a corrupt header; above
/// 2 kHz a warning.
inline constexpr double kMinReconstructionRateHz = 10.0;
inline constexpr double kMaxReconstructionRateHz = 100000.0;
inline constexpr double kPlausibleReconstructionRateHz = 2000.0;

struct ReconstructionOptions {
  /// Marker set: a shipped name or a .yaml file; empty = detect from the labels.
  std::string markerset;
  bool fill_gaps = true;
  GapFillingOptions gaps;
  /// Whether inverse kinematics fits gap-filled samples. By default it does not: filled samples
  /// keep the filter's runs continuous and complete the exported trajectories, but the fit uses
  /// only recorded samples (a spline through a 20-frame gap of a hand in a twist is off by
  /// centimetres, which the joint angles would follow).
  bool fit_filled_samples = false;
  bool filter = true;
  int filter_order = 2;
  /// Cutoff of the zero-lag filter; 0 = Winter's residual analysis.
  double cutoff_hz = 0.0;
  bool scale = true;
  ScalingOptions scaling;
  /// Offset prior (ScalingOptions::offset_prior) for keypoint sets: video keypoints are meant to
  /// be joint centres and landmarks, so their offsets are held far more firmly than skin markers'.
  double keypoint_offset_prior = 2.0;
  /// For keypoint sets without ik.joint_prior_m_per_rad: the prior weight (m/rad) on the angles
  /// 17 keypoints cannot see — lumbar (pelvis tilt trades against it), forearm pronation, wrists
  /// and ankles (docs/reconstruction.md).
  double keypoint_unseen_angle_prior_m_per_rad = 0.05;
  /// For keypoint sets without ik.temporal_prior_m_per_rad: the temporal prior of their warm
  /// starts (InverseKinematicsOptions::temporal_prior_m_per_rad; 0: none).
  double keypoint_temporal_prior_m_per_rad = 0.02;
  /// For keypoint sets with no points on the hands and feet (COCO-17), without
  /// ik.joint_prior_m_per_rad: the prior weight (m/rad) on the shoulders' and hips' rotations,
  /// which such keypoints see only while the elbow or knee is bent; a
  /// straight limb's rotation otherwise drifts through the noise towards the gimbal lock of its
  /// flexion–rotation–abduction sequence (docs/reconstruction.md).
  double keypoint_limb_rotation_prior_m_per_rad = 0.01;
  /// Frames of the motion used for scaling without a static trial (evenly spread over the window).
  int scaling_window_frames = 20;
  /// Window for scaling without a static trial, in frames of the trial (−1: the whole trial).
  int scaling_first_frame = -1;
  int scaling_last_frame = -1;
  InverseKinematicsOptions ik;
  /// The cameras' 2D keypoints a triangulated trial was made from (view_fit.h): with them, the
  /// motion fitted to the triangulated points is then fitted to the views themselves (when
  /// fit_to_views). Empty: a trial of markers or keypoints alone.
  std::shared_ptr<const ViewsToFit> views;
  bool fit_to_views = true;
  ViewFitOptions view_fit;
  /// Flights known before the reconstruction (seconds of the trial: the first and last instant
  /// in the air; one camera: from the picture's soles against the bed). With views, each is
  /// refitted as one free flight (flight_physics.h: the centre of mass on gravity's parabola,
  /// the angular momentum constant) when fit_flight_physics — off by default: on real video it
  /// is not yet nearer the truth than the frame-by-frame fit (docs/one-camera.md).
  std::vector<std::pair<double, double>> ballistic_flights_s;
  bool fit_flight_physics = false;
  FlightPhysicsOptions flight_physics;
  /// Repair left/right swaps: in the raw data of marker sets (not keypoints), a mirror pair whose
  /// exchange brings both markers closer to their positions in the previous frame; before each
  /// warm-started frame, a pair whose exchange fits the model's predicted positions better.
  bool repair_swaps = true;
  /// A swap is repaired when exchanging the pair reduces the pair's distance (to the previous
  /// frame, or to the prediction) below this factor and by at least swap_min_gain_m.
  double swap_ratio = 0.3;
  double swap_min_gain_m = 0.08;
  /// Worker threads (0: hardware concurrency); frames are cut into this many chunks.
  int num_threads = 0;
  /// Chunks shorter than this many frames are not split off.
  int min_chunk_frames = 100;
  /// Called with (frames done, total frames) from the worker threads (serialised).
  std::function<void(int, int)> progress;
  /// Asked with the progress (every ten frames, serialised): true stops the inverse kinematics,
  /// and Reconstruct throws acro::Cancelled.
  std::function<bool()> cancelled;
  bool IsValid(std::string* why) const;
};

/// A flight phase found in the motion (no marker near the lowest level), with its fit quality.
struct FlightFit {
  int first_frame = 0;
  int last_frame = 0;
  double median_rms_m = 0.0;
  double p95_rms_m = 0.0;
  double max_m = 0.0;
};

struct ReconstructionSummary {
  std::string markerset;  ///< the set's name
  std::string markerset_report;
  GapFillingSummary gaps;
  bool filtered = false;
  int filter_order = 0;
  double cutoff_hz = 0.0;
  bool cutoff_from_residual_analysis = false;
  /// The measurement noise, RMS per coordinate (m): the intercept of Winter's residual analysis
  /// (the RMS of the noise), or with a cutoff given what the filter removed; 0 when not filtered.
  double noise_rms_m = 0.0;
  std::string scaling_report;  ///< empty when not scaled
  int frames = 0;
  int frames_fitted = 0;
  int swaps_repaired = 0;
  int chunks = 0;
  int chunks_resolved =
      0;  ///< chunks re-solved sequentially after a branch mismatch at their start
  double median_rms_m = 0.0;
  double p95_rms_m = 0.0;
  double max_m = 0.0;
  std::vector<FlightFit> flights;
  /// The fit to the views, when there was one: the marker errors above (and the motion's) are then
  /// each keypoint's RMS distance from the rays of the detections it was fitted to.
  std::optional<ViewFitSummary> view_fit;
  /// The flights refitted as free flights, when there were any (ballistic_flights_s).
  std::optional<FlightPhysicsSummary> flight_physics;
  std::vector<std::string> warnings;
  std::string BriefReport() const;
};

struct ReconstructionResult {
  dynamics::Model<double> model;  ///< the (scaled) standard human
  MarkerSet markerset;
  std::vector<ModelMarker> markers;  ///< on `model`, in marker-set order
  /// The processed marker trajectories (set order, 3 × frames·markers, frame-major, NaN = gap).
  Eigen::Matrix3Xd marker_positions;
  /// Which samples of marker_positions were recorded (1 × frames·markers; the others are filled).
  Eigen::Array<bool, 1, Eigen::Dynamic> recorded;
  /// The inverse kinematics' limits and options (with the keypoint priors) the motion was fitted
  /// with, so that the same fit can be run again (the physical check's noise floor).
  std::vector<JointLimit> joint_limits;
  InverseKinematicsOptions ik_options;
  Motion motion;
  ReconstructionSummary summary;
};

/// Reconstructs `trial`. `static_trial` (optional) scales the model; without it the model is
/// scaled to a window of the motion when options.scale is set. Throws acro::InputError when no
/// marker set matches or the options are invalid.
ReconstructionResult Reconstruct(const capture::Trial& trial,
                                 const capture::Trial* static_trial,
                                 const AthleteBody& body,
                                 const ReconstructionOptions& options = {});

/// Complete flights (first and last frame in the air) of a marker trial: the phase detector's feet
/// route (phases.h) on the lowest marker of each frame against its resting level (the 2nd
/// percentile of that height), in the air when more than `clearance_m` above it for at least
/// `min_duration_s`. For the per-flight fit summary, before any model exists.
std::vector<std::pair<int, int>> FindFlights(const Eigen::Matrix3Xd& positions,
                                             int num_markers,
                                             const Eigen::VectorXd& time_s,
                                             double clearance_m = 0.25,
                                             double min_duration_s = 0.3);

}  // namespace acro::analysis
