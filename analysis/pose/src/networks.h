#pragma once

// The two BlazePose networks run by OpenCV's DNN, with MediaPipe's pre- and post-processing
// (facts from MediaPipe's pose graphs, mediapipe/modules/pose_detection and pose_landmark; docs/
// pose.md): the person detector (224 × 224 letterbox in [−1, 1], 2 254 SSD anchors, weighted
// non-maximum suppression, the region from keypoints 0 and 1) and the landmark network (a rotated
// 256 × 256 crop in [0, 1], 39 landmarks, heatmap refinement, projection back to the image).
// Internal to analysis/pose: OpenCV appears here and nowhere public.

#include <array>
#include <filesystem>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

namespace acro::pose::internal {

/// A square region of the image, turned by `rotation` (radians, clockwise in the image as y points
/// down; 0 for an upright body whose hips are below its head).
struct Roi {
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();
  double size_px = 0.0;
  double rotation = 0.0;
};

/// MediaPipe's region from two alignment points: centre p0 (the hips), side 2.5·|p1 − p0|, rotation
/// π/2 − atan2(−(y1 − y0), x1 − x0) wrapped to [−π, π).
Roi RoiFromAlignment(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1);

/// An angle wrapped to [−π, π).
double WrapAngle(double a);

/// Seconds spent per stage, summed over the calls (the benchmark's shares).
struct StageTimes {
  double crop_s = 0.0, network_s = 0.0, post_s = 0.0;
  int runs = 0;
};

struct PersonCandidate {
  double score = 0.0;
  Eigen::Vector2d box_min_px, box_max_px;       ///< the face box (what the detector's SSD boxes are)
  std::array<Eigen::Vector2d, 4> keypoints_px;  ///< hip centre, full-body point, shoulder centre, upper-body point
  Roi roi() const { return RoiFromAlignment(keypoints_px[0], keypoints_px[1]); }
};

class PersonDetectorNet {
 public:
  explicit PersonDetectorNet(const std::filesystem::path& onnx);
  /// The people in `region_px` (x, y, width, height; it may reach outside the image, which reads as
  /// black), letterboxed into the detector's square input; in image pixels, best first.
  std::vector<PersonCandidate> Detect(const cv::Mat& rgb, const cv::Rect2d& region_px, double min_score);
  const StageTimes& times() const { return times_; }

 private:
  StageTimes times_;
  cv::dnn::Net net_;
  std::vector<Eigen::Vector2d> anchors_;  // centres in [0, 1]
};

/// What the landmark network says about one region.
struct LandmarkResult {
  /// 39 columns (33 body landmarks, then the auxiliary ones): u px, v px, z (image pixels, relative
  /// to the hips' depth), visibility, presence, heatmap confidence (the refinement window's peak).
  Eigen::Matrix<double, 6, 39> landmarks;
  double pose_score = 0.0;  ///< the network's pose flag: is there a person in the region
  Roi roi;                  ///< the region it looked at
  /// The next region, from auxiliary landmarks 33 (hips) and 34 (the body's extent and direction).
  Roi NextRoi() const;
  /// How much the network believes its own fit: the pose flag × the body landmarks' mean presence ×
  /// (½ + ½ their mean visibility). The pose flag alone stays near 1 for a body fitted upside down
  /// in a region turned half a turn the wrong way; its landmarks' presence and visibility drop
  /// (0.55 and 0.24 against 1.0 and 0.65 on the sample's standing athlete; docs/pose.md).
  double Quality() const;
};

class LandmarkNet {
 public:
  explicit LandmarkNet(const std::filesystem::path& onnx);
  LandmarkResult Run(const cv::Mat& rgb, const Roi& roi);
  const StageTimes& times() const { return times_; }

 private:
  StageTimes times_;
  cv::dnn::Net net_;
};

}  // namespace acro::pose::internal
