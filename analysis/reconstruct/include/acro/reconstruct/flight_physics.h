#pragma once

// The athlete's flights held to the physics of free flight, fitted to the cameras' 2D keypoints
// (docs/one-camera.md, "Flight physics"). From one camera a frame-by-frame fit cannot tell a
// limb's depth, and with it a turn about an axis the picture shows edge-on (a side camera's twist);
// in flight the body obeys two laws the picture alone does not: its centre of mass follows the
// parabola of gravity, c(t) = c0 + v0 t + ½ g t², and its angular momentum about the centre of
// mass, H, is constant — which, with the joint angles the frame-by-frame fit found, fixes the
// root's rotation at every instant from its orientation at take-off (dynamics/flight_rotation.h:
// ω_B = I_Scm_B⁻¹ (R_WBᵀ H − H_joints_B)). So a flight's root is a few numbers — H, c0, v0 and
// the orientation at the start of each segment of about segment_s (held to where the segment
// before ended: the generic body's inertia is the athlete's only approximately) — fitted at once
// to every detection of the flight (the reprojection error in pixels, weighted by confidence,
// robust beyond a few pixels), the joint angles kept from the frame-by-frame fit. With one camera
// the parabola holds the depth and the picture the position across it (each frame moved square to
// the camera's axis to the detections' median: the centre of mass of a generic body is
// centimetres off the athlete's as the shape changes). One camera's remaining ambiguity, the
// picture's mirror image through the depth (the same picture, the twist turning the other way),
// is fitted too and its cost reported: never silently guessed.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/motion.h"
#include "acro/base/progress.h"
#include "acro/dynamics/model.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"
#include "acro/reconstruct/view_fit.h"

namespace acro::analysis {

struct FlightPhysicsOptions {
  /// A detection is used when the frame-by-frame fit projects its keypoint within this distance
  /// of it (px).
  double gate_px = 40.0;
  /// The Huber loss's scale (px): beyond it a detection's pull stops growing.
  double robust_px = 5.0;
  int max_iterations = 60;
  /// The flight's root turned by one angular momentum in segments of about this duration (s),
  /// each from its own first orientation, held to where the segment before ended by
  /// continuity_px_per_rad (a turn of 0.01 rad costs like a detection that many hundredths of a
  /// pixel off): the model's inertia is the athlete's only approximately, and over a whole
  /// twisting flight a small error in it turns the body far from the picture.
  double segment_s = 0.3;
  double continuity_px_per_rad = 300.0;
  /// Rounds of (each frame's joints refitted to its detections with the root held at the flight's,
  /// then the flight refitted to the new joints) after the first fit (on the sample's side video
  /// they brought the reprojection error down, not the rotation's: docs/one-camera.md).
  int rounds = 0;
  /// How firmly the joints' refit holds the root at the flight's (RootPrior): a centimetre costs
  /// like root_prior centimetres of ray distance, 0.1 rad like root_prior_m_per_rad / 10 m.
  double root_prior = 5.0;
  double root_prior_m_per_rad = 0.5;
  /// Flights with fewer frames in the air are left as fitted frame by frame.
  int min_frames = 6;
  /// Frames on each side of a flight over which the change of the root is blended out into the
  /// contact (so that the motion stays continuous where the flight meets the bed).
  int blend_frames = 4;
  /// When the mirror image's best cost is within this factor of the chosen one, the flight's
  /// twist direction is reported as not told by the picture.
  double ambiguous_ratio = 1.10;
  /// … and when the two turn apart by more than this somewhere in the flight (a flight without
  /// twist is its own mirror image: nothing to tell).
  double distinct_deg = 30.0;
  /// A free flight whose median reprojection error is above worse_factor × the frame-by-frame
  /// fit's + worse_px is not kept (the joints it was given cannot fly that way; said).
  double worse_factor = 1.3;
  double worse_px = 1.0;
  /// Worker threads, one flight each (0: the machine's cores).
  int num_threads = 0;
  bool IsValid(std::string* why) const;
};

struct FlightPhysicsFit {
  int first_frame = 0;  ///< first frame in the air
  int last_frame = 0;   ///< last frame in the air
  int detections = 0;   ///< detections fitted
  /// Median reprojection error of those detections (px): the frame-by-frame fit, the flight's.
  double median_before_px = 0.0;
  double median_after_px = 0.0;
  Eigen::Vector3d H_Scm_W = Eigen::Vector3d::Zero();  ///< angular momentum about the COM
  Eigen::Vector3d c0_W = Eigen::Vector3d::Zero();     ///< COM at the first frame in the air
  Eigen::Vector3d v0_W = Eigen::Vector3d::Zero();     ///< its velocity
  /// One camera: the mirror image's best cost over the chosen one's (≥ 1; near 1, the picture
  /// cannot tell the twist's direction), and whether the mirror image was the one chosen. NaN with
  /// several cameras (no mirror image).
  double mirror_cost_ratio = 0.0;
  double mirror_apart_deg = 0.0;  ///< the largest angle between the two flights' roots
  bool mirror_chosen = false;
  bool ambiguous = false;
  bool kept = true;  ///< false: worse than the frame-by-frame fit, the motion left as it was
  bool converged = false;
};

struct FlightPhysicsSummary {
  std::vector<FlightPhysicsFit> flights;
  std::vector<std::string> warnings;
  /// "flight physics: …", one line per flight.
  std::string Report() const;
};

/// Refits the root of `motion` (the frame-by-frame fit to `views` by `markers` on `model`) in each
/// flight of `flights` (first and last frame in the air) as one free flight; the joint angles are
/// kept. `marker_of_point` as FitModelToViews. Flights shorter than options.min_frames, or with
/// too few detections, are left as they are (a warning says which). `progress` is told
/// "flight physics" (flights done); false throws acro::Cancelled.
FlightPhysicsSummary FitFlightsToPhysics(const ViewsToFit& views,
                                         const std::vector<int>& marker_of_point,
                                         const dynamics::Model<double>& model,
                                         const std::vector<ModelMarker>& markers,
                                         const std::vector<JointLimit>& limits,
                                         const InverseKinematicsOptions& ik_options,
                                         const std::vector<std::pair<int, int>>& flights,
                                         const FlightPhysicsOptions& options,
                                         Motion* motion,
                                         const Progress& progress = {});

}  // namespace acro::analysis
