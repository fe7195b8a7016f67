#pragma once

// Finding the sync between a trial and a video (video_sync.h) automatically (docs/sync.md): by
// correlating the trial's projection with 2D detections in the video, or with the motion inside
// the athlete's projected box.

#include <functional>
#include <string>
#include <vector>

#include "acro/capture/detections.h"
#include "acro/capture/trial.h"
#include "acro/capture/video.h"
#include "acro/vision/camera.h"
#include "acro/vision/projection.h"
#include "acro/vision/video_sync.h"

namespace acro::vision {

struct AutoSyncOptions {
  AxisMapping axes;
  double rate = 1.0;
  /// The offsets searched (s): video time of the trial's first sample.
  double min_offset_s = -2.0;
  double max_offset_s = 2.0;
  /// Detections below this confidence are ignored.
  double min_confidence = 0.5;
  /// Distances beyond this count as this much (px): a wrong person or a wild detection does not
  /// dominate the cost.
  double max_error_px = 50.0;
  /// Image motion: the frames are analysed at this width (px), the athlete's box grown by this
  /// fraction of its size on every side.
  int analysis_width_px = 192;
  double box_margin = 0.15;
  /// Called with (frames done, frames in all) while decoding; returns false to cancel.
  std::function<bool(int, int)> progress;

  bool IsValid(std::string* why) const;
};

struct AutoSyncResult {
  VideoSync sync;
  std::string method;  ///< "detections" or "image motion"
  /// The cost at the offset found: mean truncated distance (px) for detections, 1 − correlation for
  /// image motion; and at the second-best minimum at least two frames away (how distinct it is).
  double cost = 0.0;
  double runner_up_cost = 0.0;
  int pairs = 0;  ///< point–detection pairs, or frames correlated, at the offset found
  /// The cost over the searched offsets, one per step, for a plot.
  std::vector<double> offsets_s;
  std::vector<double> costs;
};

/// One camera's detections with the times of their frames (s from the first frame; frame k of the
/// detections is frame k of the video).
struct CameraDetections {
  const Camera* camera = nullptr;
  const capture::KeypointDetections* detections = nullptr;
  std::vector<double> frame_times_s;
};

/// The offset (at the given rate) at which the trial's points, projected into the cameras, land
/// nearest to the detections of the same names: a search over the offsets one frame apart, then a
/// parabola through the best and its neighbours on a tenth-of-a-frame grid. Throws
/// acro::InputError (where "sync") when no trial point shares a name with the keypoint set or no
/// offset gives enough pairs.
AutoSyncResult SyncFromDetections(const capture::Trial& trial,
                                  const std::vector<CameraDetections>& cameras,
                                  const AutoSyncOptions& options = {});

/// The offset at which the image motion inside the athlete's projected box (frame differences)
/// correlates best with the speed of the trial's projected points: for a video without
/// detections. Decodes the video once (sequentially). Throws acro::InputError as above.
AutoSyncResult SyncFromImageMotion(const capture::Trial& trial,
                                   const Camera& camera,
                                   capture::VideoReader& video,
                                   const AutoSyncOptions& options = {});

}  // namespace acro::vision
