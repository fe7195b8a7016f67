#pragma once

// Several calibrated views' 2D keypoints → 3D keypoints (docs/markerless.md, "Triangulation"): per
// keypoint and frame, a confidence-weighted linear triangulation (DLT in each camera's undistorted
// normalised coordinates), a consensus over views when the views disagree (every pair of views
// triangulated, the pair that most other views agree with kept, as RANSAC does over a handful of
// views), then Gauss–Newton on the confidence-weighted reprojection error of the views that agree.
// Around it, what a real recording needs: the athlete chosen among the people each camera sees (by
// the projection of the athlete's 3D keypoints, frame to frame), a camera whose detector turned
// left and right over put right against the others, and gaps where fewer than two views agree —
// never a point guessed from one ray.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/base/progress.h"
#include "acro/capture/detections.h"
#include "acro/capture/trial.h"
#include "acro/vision/camera.h"

namespace acro::analysis {

struct TriangulationOptions {
  /// Detections below this confidence are not used.
  double min_confidence = 0.3;
  /// A view agrees with a 3D point when the point projects within this distance of its detection
  /// (px). Pose2Sim's default threshold is the same 15 px (Config.toml,
  /// reproj_error_threshold_triangulation).
  double max_reprojection_px = 15.0;
  /// A set of views agrees when their mean error is within max_reprojection_px and none of them is
  /// beyond this many times it.
  double max_view_error_factor = 3.0;
  /// Fewer agreeing views than this leave a gap (at least 2: one ray has no depth).
  int min_views = 2;
  /// Put right a camera whose left and right keypoints are exchanged against what the other views
  /// agree on (per left/right pair and frame).
  bool repair_left_right = true;
  /// The lens distortion taken out of each detection before triangulating. Off reproduces
  /// triangulations that ignore it (Pose2Sim's `undistort_points = false`, its default; s2mLab's
  /// TRC): measured, not recommended.
  bool model_distortion = true;
  /// The consensus point refined by Gauss–Newton on the weighted reprojection error; off leaves
  /// the weighted linear (DLT) point, as Pose2Sim does.
  bool refine = true;
  bool IsValid(std::string* why) const;
};

/// One camera's detections, frame k at the common time k / rate (already synchronised). The
/// detections' names are the keypoint set's; every view must have the same names in the same order.
struct CameraView {
  vision::Camera camera;
  capture::KeypointDetections detections;
};

/// What each camera contributed.
struct CameraTriangulationStats {
  std::string name;
  int frames_with_person = 0;           ///< frames where the camera saw someone
  int frames_chosen_among_several = 0;  ///< frames where it saw several and one was chosen
  int detections = 0;                   ///< keypoints at or above the confidence threshold
  int agreed = 0;                       ///< of those, used in a 3D point (the view agreed)
  int rejected = 0;                     ///< of those, outvoted by the other views
  int left_right_repairs = 0;           ///< left/right pairs exchanged back, over all frames
  /// Reprojection error of the 3D points into this camera where it agreed (px, distortion
  /// applied): median and 90th percentile; NaN when it agreed nowhere.
  double median_reprojection_px = 0.0;
  double p90_reprojection_px = 0.0;
};

/// What one camera saw of the athlete as the triangulation used it: the chosen person's keypoints
/// (its left and right put right), in the camera's normalised coordinates (distortion taken out
/// unless TriangulationOptions::model_distortion is off) — what a fit of the model to the views
/// starts from (view_fit.h).
struct ViewKeypoints {
  vision::Camera camera;
  /// 2 × (frames · points), frame-major; NaN where the camera did not see the point (or below
  /// the confidence threshold).
  Eigen::Matrix2Xd xy;
  Eigen::ArrayXXd confidence;  ///< points × frames; 0 where not seen
  /// points × frames: the view agreed with the triangulated point (not outvoted).
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> agreed;
};

struct Triangulation {
  std::vector<std::string> names;  ///< the keypoint set's names
  int num_frames = 0;
  /// 3 × (frames · points), frame-major as capture::Trial stores them, in the cameras' world (m);
  /// NaN where fewer than min_views views agree.
  Eigen::Matrix3Xd positions;
  /// points × frames: the confidence-weighted RMS reprojection error of each point's agreeing
  /// views (px), and how many views agreed (0 for a gap).
  Eigen::ArrayXXd reprojection_px;
  Eigen::ArrayXXi views;
  /// points × frames: each point's standard error per coordinate (m, NaN for a gap), from its fit:
  /// σ² (JᵀWJ)⁻¹ with σ² the weighted squared reprojection residual per degree of freedom.
  Eigen::ArrayXXd uncertainty_m;
  std::vector<CameraTriangulationStats> cameras;
  /// Per camera, the detections used (in the views' order).
  std::vector<ViewKeypoints> observed;
  /// Anything the user should know (a camera that never saw anyone, …), one line each.
  std::vector<std::string> warnings;

  int num_points() const { return static_cast<int>(names.size()); }
  auto position(int frame, int point) const {
    return positions.col(static_cast<Eigen::Index>(frame) * num_points() + point);
  }
  /// The median of uncertainty_m over the points found (0 when nothing was triangulated): the
  /// keypoints' noise as the views' agreement measures it.
  double NoiseRmsM() const;
  /// The points as a trial of keypoints (PointType::kMarker, "m") at `rate_hz`, Z up as the
  /// cameras' world is; its source says "triangulated from N cameras".
  capture::Trial ToTrial(double rate_hz, const std::string& source) const;
  /// Lines for a summary: points found, gaps, per camera its agreement and reprojection error.
  std::string BriefReport() const;
};

/// The 3D keypoints of the athlete seen by `views` (at least two cameras). Throws acro::InputError
/// (where "detections") when fewer than two views are given, the views' keypoint sets differ, or a
/// camera is not valid. `progress` is told "triangulate" per frame; false throws acro::Cancelled.
Triangulation TriangulateKeypoints(const std::vector<CameraView>& views,
                                   const TriangulationOptions& options = {},
                                   const Progress& progress = {});

/// The left/right pairs among keypoint names, by the conventions of OpenPose, COCO and HALPE
/// ("LShoulder"/"RShoulder", "L Hip"/"R Hip") and MediaPipe ("left_knee"/"right_knee"): pairs of
/// indices (left, right).
std::vector<std::pair<int, int>> LeftRightPairsOfNames(const std::vector<std::string>& names);

/// The confidence-weighted linear triangulation of one point from its pixels in several cameras
/// (distortion removed first) followed by Gauss–Newton on the weighted reprojection error: the
/// building block above, for tests and tools. Needs two views or more; returns NaN when the rays
/// are parallel or the point falls behind a camera.
Eigen::Vector3d TriangulatePoint(const std::vector<const vision::Camera*>& cameras,
                                 const std::vector<Eigen::Vector2d>& pixels,
                                 const std::vector<double>& weights);

}  // namespace acro::analysis
