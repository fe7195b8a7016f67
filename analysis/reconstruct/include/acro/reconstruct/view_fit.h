#pragma once

// The athlete's model fitted directly to the 2D keypoints of every view (docs/markerless.md, "The
// model fitted to the views"), after triangulate-then-IK: per frame, the configuration that
// minimises each keypoint's distance from the rays of its detections in the cameras (the
// reprojection error in metres at the keypoint's depth, weighted per view as pixels and by the
// detector's confidence), with the inverse kinematics' robust loss, joint limits and priors,
// warm-started from the triangulate-then-IK pose of the frame. What it uses that the triangulated
// points lost: a keypoint seen by one camera only (a gap in the triangulation), a view the
// consensus outvoted but the whole body agrees with, and the body's rigidity across keypoints
// when the views disagree.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/motion.h"
#include "acro/base/progress.h"
#include "acro/dynamics/model.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"
#include "acro/reconstruct/triangulation.h"

namespace acro::analysis {

/// The cameras' keypoints as the trial sees them: the triangulation's observations with the
/// cameras turned as the trial was turned upright.
struct ViewsToFit {
  std::vector<std::string> names;    ///< the keypoint set's names
  std::vector<ViewKeypoints> views;  ///< per camera, posed in the trial's world
  int num_frames = 0;
};

/// `triangulation`'s observations with every camera turned by R (p_trial = R p_world: the
/// rotation that turned the triangulated trial upright, analysis::RotationToZUp).
ViewsToFit MakeViewsToFit(const Triangulation& triangulation, const Eigen::Matrix3d& R_trial_world);

struct ViewFitOptions {
  /// Low-pass each view's 2D tracks (zero lag, per run of detections) at the cutoff the
  /// reconstruction filtered the triangulated points with, so that the fit to the views is as
  /// smooth as the fit to the points.
  bool filter = true;
  /// A detection is used when the frame's warm start projects its keypoint within this distance
  /// of it (px): a view the consensus outvoted comes back when the whole body agrees with it, a
  /// wrong detection (another limb, another person) stays out.
  double gate_px = 30.0;
  /// Levenberg–Marquardt iterations per frame.
  int max_iterations = 10;
  /// Worker threads (0: the machine's cores).
  int num_threads = 0;
  bool IsValid(std::string* why) const;
};

struct ViewFitCamera {
  std::string name;
  int used = 0;                   ///< detections fitted
  int gated = 0;                  ///< detections left out (beyond gate_px of the warm start)
  double median_before_px = 0.0;  ///< the warm start's reprojection error of the detections used
  double median_after_px = 0.0;   ///< the fitted model's
};

struct ViewFitSummary {
  int frames = 0;           ///< frames fitted
  int detections_used = 0;  ///< over all cameras
  int detections_gated = 0;
  /// Detections used that no triangulated point had (a keypoint one camera saw, or a view the
  /// consensus outvoted).
  int detections_added = 0;
  double median_before_px = 0.0;
  double median_after_px = 0.0;
  std::vector<ViewFitCamera> cameras;
  /// One line per camera and one for the whole: "fit to the views: 4 cameras, …".
  std::string Report() const;
};

/// Refits `motion` (fitted to the triangulated keypoints by `markers` on `model`) to the views,
/// frame by frame, in parallel. `marker_of_point[j]` is the marker of views.names[j] (−1: not in
/// the set). `cutoff_hz` (0: no filter) and `filter_order` as the reconstruction's filter,
/// `rate_hz` the trial's. The frames whose motion.fit is not valid are left as they are.
/// `progress` is told "fit to the views" (frames done); false throws acro::Cancelled.
ViewFitSummary FitModelToViews(const ViewsToFit& views,
                               const std::vector<int>& marker_of_point,
                               const dynamics::Model<double>& model,
                               const std::vector<ModelMarker>& markers,
                               const std::vector<JointLimit>& limits,
                               const InverseKinematicsOptions& ik_options,
                               double cutoff_hz,
                               int filter_order,
                               double rate_hz,
                               const ViewFitOptions& options,
                               Motion* motion,
                               const Progress& progress = {});

}  // namespace acro::analysis
