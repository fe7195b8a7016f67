#pragma once

// A trial's markers or keypoints in a camera's image: the geometry behind `acrolab project` and,
// later, every overlay on video.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/trial.h"
#include "acro/vision/camera.h"
#include "acro/vision/video_sync.h"

namespace acro::vision {

/// How a file's axes map to the lab's: world axis k is sign[k] × file axis index[k]. "xyz" is the
/// identity; "zxy" reads a Y-up TRC (OpenSim, Pose2Sim) into a Z-up lab: world = (z, x, y).
struct AxisMapping {
  int index[3] = {0, 1, 2};
  double sign[3] = {1.0, 1.0, 1.0};
  Eigen::Vector3d ToWorld(const Eigen::Vector3d& p) const {
    return Eigen::Vector3d(sign[0] * p[index[0]], sign[1] * p[index[1]], sign[2] * p[index[2]]);
  }
};

/// Parses "xyz", "zxy", "x-zy" (a minus before a letter flips that axis): three distinct letters.
/// Throws acro::InputError (where "--axes") otherwise.
AxisMapping ParseAxisMapping(const std::string& text);

/// One projected point.
struct ProjectedPoint {
  int frame = 0;      ///< the trial's sample, 0-based, or the video frame (ProjectTrialOnFrames)
  double time_s = 0;  ///< the video time: of that sample + the offset, or of that frame
  int marker = 0;     ///< index into the trial's points
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();  ///< distortion applied
  int sample = 0;                                   ///< the trial's sample the point comes from
};

/// Every non-gap point of every sample in front of the camera, in sample then point order.
/// `offset_s` is added to the times (video time = offset + trial time).
std::vector<ProjectedPoint> ProjectTrial(const capture::Trial& trial,
                                         const Camera& camera,
                                         const AxisMapping& axes = {},
                                         double offset_s = 0.0);

/// The points on the frames of a video: for each frame time (s from the first frame), the trial
/// sample the sync puts nearest to it; `frame` is the video frame, `time_s` its time. Frames
/// outside the trial get no points.
std::vector<ProjectedPoint> ProjectTrialOnFrames(const capture::Trial& trial,
                                                 const Camera& camera,
                                                 const std::vector<double>& frame_times_s,
                                                 const VideoSync& sync,
                                                 const AxisMapping& axes = {});

/// CSV rows "camera,frame,time_s,marker,u_px,v_px" (with that header) for the points.
std::string FormatProjectionCsv(const capture::Trial& trial,
                                const Camera& camera,
                                const std::vector<ProjectedPoint>& points);

}  // namespace acro::vision
