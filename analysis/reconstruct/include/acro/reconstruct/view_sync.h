#pragma once

// Several cameras that were not started together, put on one time line from their detections
// alone (docs/markerless.md, "Sync"): two calibrated views of one moving body agree only at the
// right offset — each keypoint of one view must lie on the epipolar line of the same keypoint in
// the other. The offset of each camera against the first is the one with the least epipolar
// distance over the whole take (searched frame by frame, then to a tenth of a frame on detections
// interpolated between frames), and different frame rates are resampled onto the first camera's.

#include <string>
#include <vector>

#include "acro/base/progress.h"
#include "acro/reconstruct/triangulation.h"

namespace acro::analysis {

struct ViewSyncOptions {
  /// Offsets searched, in the first camera's frames, either way.
  double max_offset_s = 5.0;
  /// Detections below this confidence are not used.
  double min_confidence = 0.3;
  /// Epipolar distances beyond this count as this much (px): a wrong person or a wild keypoint
  /// does not decide.
  double max_distance_px = 30.0;
  /// See ViewOffset::distinct.
  double min_distinctness = 1.5;
  bool IsValid(std::string* why) const;
};

struct ViewOffset {
  std::string camera;
  /// The camera's frame k shows the moment of the first camera's frame k + offset_frames (in the
  /// first camera's frames; 0 for the first camera).
  double offset_frames = 0.0;
  /// Mean truncated epipolar distance (px) at the offset found, and at the best offset at least
  /// two frames away from it: how distinct the minimum is.
  double cost_px = 0.0;
  double runner_up_cost_px = 0.0;
  int pairs = 0;  ///< keypoint pairs compared at the offset found
  /// The minimum stands out: the runner-up costs at least ViewSyncOptions::min_distinctness
  /// times as much. A take with too little motion (someone standing still) leaves it flat, and
  /// the offset found then means little.
  bool distinct = false;
};

/// The offset of every view against the first (views[0].camera's time line), each view's frames
/// at its own rate (`rates_hz[v]`, frames per second). Throws acro::InputError (where "sync") when
/// a view shares too few confident keypoints with the first at every offset.
std::vector<ViewOffset> SyncViews(const std::vector<CameraView>& views,
                                  const std::vector<double>& rates_hz,
                                  const ViewSyncOptions& options = {},
                                  const Progress& progress = {});

/// The detections of one camera on another time line: frame k of the result is the moment of
/// the source's frame (k − offset_frames) · source_rate / target_rate — interpolated linearly
/// between the two frames around it, keypoint by keypoint, when both hold it (the lower of the
/// two confidences), taken from the nearer one when the two are within a hundredth of a frame,
/// and absent otherwise. The first person of each frame only (the athlete, once chosen).
/// `num_frames` frames.
capture::KeypointDetections ResampleDetections(const capture::KeypointDetections& source,
                                               double source_rate_hz,
                                               double target_rate_hz,
                                               double offset_frames,
                                               int num_frames);

}  // namespace acro::analysis
