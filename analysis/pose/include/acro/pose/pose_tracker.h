#pragma once

/// \file
/// One athlete followed through a video with BlazePose (docs/pose.md, "Tracking"). A
/// general-purpose pose tracker crops each frame around the last pose and loses an athlete who
/// turns upside down or tucks; this one carries the region's rotation and angular velocity from
/// frame to frame (a somersault turns at a steady rate in flight), searches rotations when the pose
/// is lost, looks for the athlete in a region the user or the bed gives before the whole frame,
/// and prefers the person it was following (or the one above the bed) over people around. Left and
/// right are the network's; acro/pose/left_right.h repairs their swaps over a whole sequence.

#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/capture/detections.h"
#include "acro/capture/video.h"
#include "acro/pose/pose_models.h"

namespace acro::pose {

struct PoseTrackerOptions {
  LandmarkModel model = LandmarkModel::kHeavy;
  /// Where the networks are; empty: DefaultModelDirectory().
  std::filesystem::path model_directory;
  /// A box around where the athlete is (image pixels): searched first when no pose is followed.
  std::optional<Eigen::AlignedBox2d> box_px;
  /// The trampoline bed's corners in the image (vision::DetectBed): the air above it is searched
  /// first, and a person above the bed is preferred to people beside it.
  std::optional<std::array<Eigen::Vector2d, 4>> bed_corners_px;
  double min_pose_score = 0.5;       ///< the landmark network's pose flag to accept a pose
  double min_detection_score = 0.5;  ///< the person detector's score
  /// While nobody is followed, the costly search (tiles of the frame, rotations of the region) runs
  /// on one frame in this many; the person detector on the whole frame runs on every frame.
  int search_every_frames = 4;

  bool IsValid(std::string* why) const;
};

/// What the tracker knows after a frame: the pose, and the state the next frame starts from
/// (written with each frame so that an interrupted detection resumes where it stopped).
struct FramePose {
  int frame = -1;
  double time_s = 0.0;
  bool found = false;
  /// BlazePose's 33 keypoints (u px, v px, confidence in [0, 1]); confidence 0 when not found.
  capture::DetectedPerson keypoints = capture::DetectedPerson::Zero(3, 33);
  double pose_score = 0.0;  ///< the landmark network's pose flag
  /// The fit's quality: the pose flag × the landmarks' mean presence × (½ + ½ their visibility).
  double quality = 0.0;
  /// How the pose was found: "tracked" (the region predicted from the last frames), "rotation
  /// search", "detector", "region" (the user's box or the bed's, searched over rotations).
  std::string how;
  /// Left and right exchanged from the network's labels by the swap repair (RepairLeftRight):
  /// bit 0 the legs, bit 1 the arms and face.
  int swapped_groups = 0;
  // The region followed into the next frame and its motion per frame.
  Eigen::Vector2d roi_centre_px = Eigen::Vector2d::Zero();
  double roi_size_px = 0.0;
  double roi_rotation_rad = 0.0;
  Eigen::Vector2d velocity_px = Eigen::Vector2d::Zero();
  double angular_velocity_rad = 0.0;
};

/// Time spent per stage (s, summed over the frames tracked).
struct PoseTiming {
  double crop_s = 0.0, network_s = 0.0, post_s = 0.0;
  int detector_runs = 0, landmark_runs = 0;
};

/// Follows one athlete frame by frame. Not thread-safe: one tracker per video and thread.
class PoseTracker {
 public:
  /// Loads the networks (FindPoseModels): acro::InputError in one line when they are missing or
  /// damaged, or when the options are not valid.
  explicit PoseTracker(const PoseTrackerOptions& options);
  ~PoseTracker();
  PoseTracker(const PoseTracker&) = delete;
  PoseTracker& operator=(const PoseTracker&) = delete;

  /// The pose in `frame` (RGB), following on from the previous call.
  FramePose Track(const capture::VideoFrame& frame);
  /// Continues from a frame tracked earlier (a resumed run): its region, motion and pose.
  void Resume(const FramePose& last);
  const PoseTiming& timing() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::pose
