#pragma once

/// \file
/// A whole video's poses (docs/pose.md, "acrolab detect"): frames decoded once, in order, on their
/// own thread, the athlete followed by a PoseTracker, each frame's pose written as it is found as
/// an OpenPose JSON file (what Pose2Sim, Sports2D and Kinovea read), so that an interrupted run
/// resumes where it stopped; at the end the whole video as a 2D TRC, a CSV and a summary.

#include <filesystem>
#include <string>
#include <vector>

#include "acro/base/progress.h"
#include "acro/capture/video.h"
#include "acro/pose/pose_tracker.h"

namespace acro::pose {

struct DetectVideoOptions {
  PoseTrackerOptions tracker;
  int first_frame = 0;  ///< the frames detected: first_frame … end_frame − 1
  int end_frame = -1;   ///< −1: to the video's end
  bool resume = true;  ///< continue an interrupted run found in the output folder

  bool IsValid(std::string* why) const;
};

struct VideoPoses {
  std::filesystem::path video;
  capture::VideoInfo info;
  int first_frame = 0, end_frame = 0;
  std::vector<FramePose> frames;  ///< one per frame detected, in order
  int frames_resumed = 0;         ///< taken from an earlier run's files
  int frames_repaired = 0;        ///< left and right exchanged by RepairLeftRight
  int frames_dropped = 0;         ///< poses seen in fewer than 3 frames in a row, taken out
  PoseTiming timing;              ///< this run's
  double decode_s = 0.0;          ///< time the decoder thread spent (this run)
  double elapsed_s = 0.0;         ///< wall time of this run
  std::vector<std::string> warnings;

  int frames_with_pose() const;
  /// The median keypoint confidence over the frames with a pose (0 when none).
  double median_confidence() const;
};

/// The threads the networks use, process-wide (OpenCV's own pool): 1 when several videos are
/// detected at once, each on its own thread; all cores for a single video.
void SetNetworkThreads(int threads);

/// The folder a video's outputs go to inside `output_dir`: its file name's stem.
std::filesystem::path VideoOutputDirectory(const std::filesystem::path& output_dir,
                                           const std::filesystem::path& video);

/// Detects the athlete in `video` and writes into `directory` (created): json/<stem>_<frame,
/// 12 digits>_keypoints.json per frame (OpenPose's format: pose_keypoints_2d in BODY_25B order,
/// blazepose_keypoints_2d with BlazePose's 33, and the tracker's state under "acrolab"), and at the
/// end keypoints_2d.trc (BODY_25B, pixels, y down, Z 0: Sports2D's convention), blazepose_2d.csv
/// (frame, time_s, keypoint, u_px, v_px, confidence) and detect.json (the summary), each written
/// whole. With `resume`, frames already in json/ from a run with the same video, model and region
/// are taken as they are. Throws acro::InputError naming the video for an unreadable video or
/// frames outside it, acro::Cancelled when `progress` says stop (the frames written stay for a
/// resumed run).
VideoPoses DetectVideoPoses(const std::filesystem::path& video,
                            const std::filesystem::path& directory,
                            const DetectVideoOptions& options,
                            const Progress& progress = {});

/// detect.json's text: video, model, frames, frames_with_pose, median_confidence, the time per
/// frame and its shares (decode, crop, network, post-processing), warnings.
std::string FormatVideoPosesJson(const VideoPoses& poses, const DetectVideoOptions& options);

}  // namespace acro::pose
