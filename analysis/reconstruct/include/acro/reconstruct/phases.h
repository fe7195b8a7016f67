#pragma once

// Contact and flight phases of a trampoline (or floor) trial, from the whole-body centre of mass,
// the soles or force plates: the one flight detector of every stage (reconstruction's per-flight
// fit summary too). One flight = one skill; flights cut by the start or end of the recording
// are flagged partial and not scored.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

struct PhaseOptions {
  double gravity_m_per_s2 = 9.81;
  /// Half-width of the Savitzky–Golay window used to find free fall (s); wide enough that 1 mm of
  /// COM noise does not break a flight into pieces.
  double smoothing_half_window_s = 0.08;
  /// A frame is in free fall when the smoothed vertical COM acceleration is at most −g plus this
  /// (a support only pushes, so contact never reads below −g). 2 m/s² suits optical markers; a COM
  /// reconstructed from video keypoints needs about 6.
  double free_fall_tolerance_m_per_s2 = 2.0;
  /// Shorter free-fall runs are not flights (bounces, noise).
  double min_flight_s = 0.15;
  /// How far into the contact phase the take-off/landing model is fitted (s): see RefineEvent in
  /// phases.cc (the COM departs from the flight parabola with d³ at take-off, d² at a damped
  /// landing).
  double contact_fit_window_s = 0.10;
  /// Force-plate route: contact while the vertical force exceeds its flight baseline by this (N).
  double force_threshold_N = 20.0;
  /// Feet route: in the air while the lowest sole is more than this above the surface (m). The
  /// sole points are the model's (the midpoint of the toe tip and the heel point below the ankle).
  double feet_clearance_m = 0.0;
  /// Feet route: dips below the surface shorter than this inside a flight are marker noise (s).
  double feet_bridge_s = 0.03;

  bool IsValid(std::string* why) const;
};

struct Flight {
  double takeoff_s = 0.0;  ///< sub-frame estimate
  double landing_s = 0.0;
  int takeoff_frame = 0;  ///< first frame in the air
  int landing_frame = 0;  ///< first frame back in contact
  bool partial = false;   ///< cut by the start or end of the recording: not a complete skill
  /// COM vertical motion fitted over the flight: z(t) = z0 + v0 (t − takeoff) − ½ g_fit (t −
  /// takeoff)².
  double fitted_gravity_m_per_s2 = 0.0;
  double takeoff_vertical_velocity_m_per_s = 0.0;
  double apex_z_m = 0.0;
  double apex_s = 0.0;
  double parabola_rms_m = 0.0;  ///< RMS of COM z about the fitted parabola over the flight

  double time_of_flight_s() const { return landing_s - takeoff_s; }
};

struct PhaseSegmentation {
  std::vector<Flight> flights;
  std::string method;  ///< "com", "feet" or "force plates"
};

/// Flights from the whole-body COM height sampled at `time_s` (uniform rate).
PhaseSegmentation DetectFlightsFromCom(const Eigen::VectorXd& time_s,
                                       const Eigen::VectorXd& com_z_m,
                                       const PhaseOptions& options = {});

/// Flights timed elsewhere — `flights_s` holds each flight's take-off and landing (s, on
/// `time_s`'s clock; NaN: before the recording starts / after it ends) — with their frames and the
/// COM parabola from `com_z_m` at `time_s`: the picture's soles of one camera
/// (vision/image_flights.h) for a motion whose 3D feet are less sure than the picture's.
PhaseSegmentation DetectFlightsFromIntervals(
    const std::vector<std::pair<double, double>>& flights_s,
    const Eigen::VectorXd& time_s,
    const Eigen::VectorXd& com_z_m,
    const std::string& method,
    const PhaseOptions& options = {});

/// Flights from the total vertical ground reaction (N) sampled at `time_s`; the parabola fields are
/// filled from `com_z_m` at `com_time_s` when given (may be empty).
PhaseSegmentation DetectFlightsFromForce(const Eigen::VectorXd& time_s,
                                         const Eigen::VectorXd& force_z_N,
                                         const Eigen::VectorXd& com_time_s,
                                         const Eigen::VectorXd& com_z_m,
                                         const PhaseOptions& options = {});

/// Flights from the lowest sole height per frame against the height of the surface at rest (a
/// trampoline bed, the floor): take-off and landing where the soles cross it (interpolated), the
/// parabola fields from `com_z_m` (same frames). A trampoline bed without mass lets go of the feet
/// when it is back at its rest level, so this is the instant of leaving and touching the bed.
/// With `com_z_m` empty the flights have their events and frames but no parabola.
PhaseSegmentation DetectFlightsFromFeet(const Eigen::VectorXd& time_s,
                                        const Eigen::VectorXd& feet_z_m,
                                        double surface_z_m,
                                        const Eigen::VectorXd& com_z_m,
                                        const PhaseOptions& options = {});

/// The surface the athlete takes off from, estimated from the motion itself (no bed markers, no
/// option): a trampoline bed or a floor at rest.
struct SurfaceEstimate {
  double z_m = 0.0;  ///< the surface's height at rest: the median of the contacts' estimates
  /// How much the contacts' own estimates disagree: 1.4826 × their median absolute deviation (a
  /// standard deviation for normal scatter), 0 with a single contact.
  double spread_m = 0.0;
  std::vector<double> contact_z_m;  ///< each contact's estimate, in time order
  /// How far the lowest sole sank below the surface in the median contact (m).
  double depth_m = 0.0;
  bool gives_way = true;  ///< a trampoline bed (the soles sink with it) or a rigid floor
  /// One line: "bed at rest 1.153 m (spread 0.004 m over 6 contacts, soles sink 0.62 m)".
  std::string Describe() const;
};

/// The surface's height at rest from the lowest sole per frame and the whole-body COM (same
/// frames, uniform rate), over the contacts between the flights `com_phases` found from the COM
/// (DetectFlightsFromCom), each from its core, where the support exceeds one body weight. A
/// contact whose soles stay within 6 cm is a floor: the median sole there. Otherwise a sprung bed,
/// whose force k·d makes the COM a sinusoid of ω = √(k/m): fitted to the COM over the core, it
/// accelerates at −g (the bed's force is zero, the feet at its rest level) where its excursion
/// above the equilibrium is g/ω², before and after the bottom; the soles at those two instants.
/// The sole is the model's, so a constant error of its height is in the estimate too and cancels
/// when flights are found from the same soles (docs/metrics.md). Nothing without a complete
/// contact (one whose core lies inside the recording).
std::optional<SurfaceEstimate> EstimateContactSurface(const Eigen::VectorXd& time_s,
                                                      const Eigen::VectorXd& feet_z_m,
                                                      const Eigen::VectorXd& com_z_m,
                                                      const PhaseSegmentation& com_phases,
                                                      const PhaseOptions& options = {});

/// Savitzky–Golay (quadratic) second derivative of uniformly sampled values, half-window h samples;
/// the ends use the nearest full window.
Eigen::VectorXd SavitzkyGolaySecondDerivative(const Eigen::VectorXd& values,
                                              double dt,
                                              int half_window);

}  // namespace acro::analysis
