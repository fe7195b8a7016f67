#pragma once

// Physical-correctness check of a reconstructed motion (DESIGN.md, "Conventions that the physics
// depends on"; docs/physical-check.md). Newton–Euler inverse dynamics on every frame: in flight
// the only external force is gravity, so the root residual — the wrench that would have to act on
// the athlete for the recorded motion to happen — must vanish, the angular momentum about the
// centre of mass must stay constant and the centre of mass must fall with g. How far the capture
// is from that is the verdict. A failed verdict is localised (markers, timing, segment masses)
// and a correction suggested, never applied. In contact the root residual is the bed's reaction.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/motion.h"
#include "acro/dynamics/model.h"
#include "acro/reconstruct/markerset.h"
#include "acro/reconstruct/phases.h"

namespace acro::analysis {

/// Verdict thresholds. The force and moment limits are OpenSim's residual guidelines (Hicks et al.
/// 2015, "Is my model good enough?", J Biomech Eng 137: peak residual force below 5 % of the peak
/// external force, peak residual moment below 1 % of the COM height times that force) with the
/// external force of a flight, the body weight, and the COM height of a standing human, 0.55 of the
/// stature (de Leva 1996). The marker limit is OpenSim's 4 cm maximum marker error.
///
/// The force and moment limits apply to the residual averaged over `residual_window_s` (the
/// impulse over the window divided by its length), not to single frames: the residual is a second
/// derivative of marker data, and with 1 mm of marker noise at 120 Hz single frames reach 0.1–0.4
/// body weights where the averaged residual of the same clean flight stays below 0.04
/// (docs/physical-check.md). A 0.2 s mean is a low-pass of about 2.2 Hz (−3 dB), the smoothing that
/// OpenSim users apply to the coordinates before inverse dynamics (6 Hz, twice) in one step.
struct PhysicalCheckOptions {
  double max_force_bw = 0.05;           ///< peak windowed |force| / (m g) over a flight
  double max_moment_bwh = 0.01 * 0.55;  ///< peak windowed |moment about the COM| / (m g height)
  /// Length of the averaging window of the residual (s); 0 judges single frames.
  double residual_window_s = 0.2;
  /// max−min of |L| about the COM over a flight, over the reference max(mean |L|, floor): a
  /// torque-free body keeps L exactly, a 10 % swing is beyond what marker noise explains.
  double max_momentum_variation = 0.10;
  /// Floor of the momentum reference, in m·height² per second (0.05 ≈ 10 kg·m²/s for 70 kg and
  /// 1.70 m), so that a straight jump (L ≈ 0) is judged in absolute terms.
  double momentum_floor_mh2_per_s = 0.05;
  /// |fitted vertical COM acceleration − g| / g over a flight.
  double max_gravity_error = 0.05;
  /// Largest distance model marker ↔ measured marker (m) tolerated in a flight frame.
  double max_marker_error_m = 0.04;
  /// Frames this close to take-off or landing are not judged: the zero-lag filter and the
  /// central differences reach across the contact there. Negative: max(2 frames, 0.5/cutoff).
  double edge_margin_s = -1.0;
  /// With a noise floor (JudgeAgainstNoise): a flight fails a criterion only when its measure is
  /// beyond both the threshold above and this multiple of what the trial's noise alone gives.
  double noise_factor = 1.5;
  bool IsValid(std::string* why) const;
};

/// What the trial's measurement noise alone gives a flight's judged measures, after the same
/// filtering, inverse kinematics and differentiation as the data (CalcNoiseFloor in
/// noise_floor.h): the largest over its repetitions.
struct FlightNoiseFloor {
  double window_force_bw = 0.0;
  double window_moment_bwh = 0.0;
  double momentum_variation = 0.0;
  double gravity_error_m_per_s2 = 0.0;  ///< |fitted g − g|
  double max_marker_error_m = 0.0;
};

/// Per-frame results over the whole trial (columns are frames).
struct FrameDynamics {
  Eigen::MatrixXd v;                  ///< nv × frames, generalised velocities
  Eigen::MatrixXd a;                  ///< nv × frames, generalised accelerations
  Eigen::MatrixXd joint_torque_Nm;    ///< (nv − 6) × frames, one torque per joint axis
  Eigen::Matrix3Xd force_bw;          ///< root residual force at the COM, in W / (m g)
  Eigen::Matrix3Xd moment_bwh;        ///< root residual moment about the COM, in W / (m g h)
  Eigen::Matrix3Xd com_W;             ///< p_WoScm_W (m)
  Eigen::Matrix3Xd angular_momentum;  ///< L about the COM in W (kg·m²/s)
};

/// Which part of the data most likely drives a failed verdict.
struct Finding {
  enum class Kind { kMarkers, kSwap, kTiming, kSegmentMass };
  Kind kind = Kind::kMarkers;
  std::vector<std::string> names;  ///< the markers or segments named
  double value = 0.0;              ///< error (m), lag (s) or suggested mass ratio
  std::string text;                ///< one line a coach or biomechanist can read
};

struct FlightCheck {
  int flight = 0;       ///< index into the segmentation's flights
  int first_frame = 0;  ///< judged frames [first_frame, last_frame]
  int last_frame = 0;
  /// Single frames: the largest and the RMS residual over the judged frames.
  double peak_force_bw = 0.0;
  double rms_force_bw = 0.0;
  double peak_moment_bwh = 0.0;
  double rms_moment_bwh = 0.0;
  /// The judged figures: the largest residual averaged over residual_window_s, and where that
  /// window starts (s).
  double window_force_bw = 0.0;
  double window_moment_bwh = 0.0;
  double window_force_at_s = 0.0;
  double window_moment_at_s = 0.0;
  double mean_angular_momentum = 0.0;  ///< |mean L| (kg·m²/s)
  double momentum_variation = 0.0;     ///< see PhysicalCheckOptions::max_momentum_variation
  double fitted_gravity_m_per_s2 = 0.0;
  double max_marker_error_m = 0.0;
  /// What noise alone gives these measures, when the check was judged against the noise.
  std::optional<FlightNoiseFloor> noise;
  /// Whether the flight fails a threshold alone and the noise floor raised a limit above its
  /// threshold (its verdict then depends on the noise: "within" or "beyond" it).
  bool judged_against_noise = false;
  bool pass = true;
  std::vector<std::string> failures;  ///< which criteria failed, with their numbers
  /// The failures joined by ", " (empty when the flight passes).
  std::string FailureText() const;
};

/// Peak bed (or floor) reaction in a contact phase: the root residual there.
struct ContactLoad {
  int first_frame = 0;
  int last_frame = 0;
  double peak_force_bw = 0.0;
  double peak_s = 0.0;
};

/// Segment mass scale factors that best zero the flight residuals in least squares with the total
/// mass kept (like OpenSim's RRA, reported, never applied).
struct MassSuggestion {
  std::vector<std::string> segments;
  Eigen::VectorXd current_kg;
  Eigen::VectorXd suggested_kg;
  double residual_before = 0.0;  ///< RMS normalised flight residual with the current masses
  double residual_after = 0.0;   ///< with the suggested masses
};

struct PhysicalCheck {
  FrameDynamics frames;
  /// Per frame, the |residual| averaged over the window centred on it (what the verdict judges),
  /// NaN outside the judged flight frames.
  Eigen::VectorXd window_force_bw;
  Eigen::VectorXd window_moment_bwh;
  std::vector<FlightCheck> flights;  ///< complete flights only
  std::vector<ContactLoad> contacts;
  bool pass = true;
  /// "pass", or "fail: " and the causes in one line; judged against a noise floor that raised a
  /// limit: "pass within its noise (≈ N mm per coordinate, video keypoints)" or "fail beyond its
  /// noise (…): " and the causes.
  std::string verdict;
  /// The measurement noise the check was judged against (RMS per coordinate, m; 0: not judged
  /// against noise) and the data's class ("markers", "video keypoints").
  double noise_rms_m = 0.0;
  std::string data_class;
  double gravity_m_per_s2 = 9.81;  ///< the model's g the flights are judged with
  std::vector<Finding> findings;
  MassSuggestion mass_suggestion;
  double edge_margin_s = 0.0;
  double height_m = 0.0;  ///< the stature the moments are normalised by
};

/// Generalised velocities and accelerations of a motion by central differences (the root's
/// angular velocity from the relative rotation of the neighbouring frames, in the root frame).
void CalcMotionDerivatives(const dynamics::Model<double>& model,
                           const Motion& motion,
                           Eigen::MatrixXd& v,
                           Eigen::MatrixXd& a);

/// Inverse dynamics, centre of mass and momentum on every frame.
FrameDynamics CalcFrameDynamics(const dynamics::Model<double>& model,
                                const Motion& motion,
                                double height_m);

/// The root residual about a fixed point P summed segment by segment from the segments' own
/// motion (each segment's rate of change of momentum minus its weight, by central differences of
/// its pose): the Newton–Euler balance of the whole body, a second route to the same residual as
/// the recursive inverse dynamics. Returns per frame and segment the 6-vector [moment about P;
/// force] in W (rows 6·segment … 6·segment+5); frames at the ends are zero.
Eigen::MatrixXd CalcSegmentWrenches(const dynamics::Model<double>& model,
                                    const Motion& motion,
                                    const Eigen::Vector3d& p_WoP_W);

/// Runs the check. `flights` are the motion's flights (phases.h); `cutoff_hz` is the marker
/// filter's cutoff (0: unknown) for the edge margin.
PhysicalCheck CheckPhysics(const dynamics::Model<double>& model,
                           const Motion& motion,
                           const std::vector<Flight>& flights,
                           double height_m,
                           double cutoff_hz,
                           const PhysicalCheckOptions& options = {});

/// How far the angular momentum L (columns: frames) strays: the largest distance between two of
/// its columns over max(|mean L|, floor).
double CalcMomentumVariation(const Eigen::Matrix3Xd& L, double floor);

/// The gravity a falling height shows: −2 c₂ of the parabola c₀ + c₁ t + c₂ t² fitted to z(t) by
/// least squares.
double FitFallingGravity(const Eigen::VectorXd& time_s, const Eigen::VectorXd& z);

/// The norm of the mean of `x`'s columns over every window of `window` consecutive columns
/// (window clamped to 1…cols), in order of the window's first column.
Eigen::VectorXd WindowedMeanNorms(const Eigen::Matrix3Xd& x, int window);

/// Judges the check's flights again with the noise floor of each (`floors`, one per
/// check.flights entry): each criterion's limit becomes the larger of its threshold and
/// options.noise_factor times the floor; the verdict names the noise and the data class when a
/// floor raised a limit.
void JudgeAgainstNoise(PhysicalCheck& check,
                       const std::vector<FlightNoiseFloor>& floors,
                       double noise_rms_m,
                       const std::string& data_class,
                       const PhysicalCheckOptions& options);

/// Localises a failed verdict, as findings in this order: pairs of markers that fit each other's
/// model positions (swaps); markers recorded late (timing: pairs of markers on one segment whose
/// distance is steadiest at a non-zero relative lag, per-marker lags by least squares); segment
/// masses that fit the flights far better (the mass suggestion); and only when none of these
/// explains it, the markers with the largest fit error at the peak-residual frames.
/// `marker_positions` are the measured positions (3 × frames·markers, frame-major, NaN = gap) of
/// `markers` (set order).
void LocalisePhysicsFailure(const dynamics::Model<double>& model,
                            const Motion& motion,
                            const Eigen::Matrix3Xd& marker_positions,
                            const std::vector<ModelMarker>& markers,
                            const PhysicalCheckOptions& options,
                            PhysicalCheck& check);

/// The mass suggestion alone (see MassSuggestion) over the judged flight frames of `check`.
MassSuggestion SuggestSegmentMasses(const dynamics::Model<double>& model,
                                    const Motion& motion,
                                    const PhysicalCheck& check,
                                    double height_m);

}  // namespace acro::analysis
