#pragma once

// 2D keypoint detections of a video, one set per frame, as pose estimators write them
// (docs/formats/detections.md): OpenPose's JSON per frame (also written by Pose2Sim, RTMPose
// through Sports2D, MMPose's OpenPose-style export). Keypoint sets are named here because the files
// are not self-describing: a JSON file holds numbers in the order of the model that made it.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::capture {

/// The keypoint names of a set, in its order: "body25" (OpenPose BODY_25), "body25b" (OpenPose's
/// BODY_25B, Pose2Sim's default), "coco17" (COCO, also the first 17 of HALPE), "halpe26". Throws
/// acro::InputError (where "--keypoints") for another name.
const std::vector<std::string>& KeypointSetNames(const std::string& set);

/// One person in one frame: a column (u px, v px, confidence) per keypoint of the set.
using DetectedPerson = Eigen::Matrix3Xd;

struct KeypointDetections {
  std::string source;              ///< the directory read
  std::vector<std::string> names;  ///< the keypoint set's names
  /// frames[k]: the people detected in video frame k (0-based, from the file names); a frame with
  /// no file or nobody in it is empty.
  std::vector<std::vector<DetectedPerson>> frames;
  /// What the reader decided that the user should know (a 2D TRC's convention), one line each.
  std::vector<std::string> warnings;

  int num_frames() const { return static_cast<int>(frames.size()); }
};

/// Reads a directory of OpenPose JSON files, one per frame, whose frame number is the last number
/// in the file name (cam01.0042.json, video_000000000042_keypoints.json); `people[i]
/// .pose_keypoints_2d` holds 3 numbers per keypoint of `keypoint_set`. Throws acro::InputError
/// naming the file and the key for malformed JSON, a keypoint count that does not match the set,
/// or a directory with no JSON file; at most 1 000 000 frames.
KeypointDetections ReadOpenPoseJson(const std::filesystem::path& directory,
                                    const std::string& keypoint_set);

/// Reads 2D detections from a CSV with a header naming at least the columns `frame` (the video
/// frame, 0-based), `marker` (or `keypoint`), `u_px` and `v_px`, and optionally `confidence`
/// (default 1) and `camera` (rows of other cameras than `camera` are skipped when both are given):
/// the rows `acrolab project --csv` writes, or a hand-labelled or tracked set (one person per
/// frame). The names are the file's, in order of first appearance. Throws acro::InputError naming
/// the file and line.
KeypointDetections ReadDetectionsCsv(const std::filesystem::path& path,
                                     const std::string& camera = "");

/// Reads 2D detections from a TRC whose Z column is 0 (or a gap) everywhere: what Sports2D writes
/// (`*_px_person00.trc`) and what 2D trackers export for OpenSim-style tools. Two conventions are
/// in use and told apart by the numbers: pixels as they are, x right and y down (Sports2D 0.5 and
/// later, whose header says "m" although the values are pixels), or pixels ÷ 1000 with y negated
/// (Sports2D before 0.5: every |value| ≤ 10 and every y ≤ 0); the warnings say which was read.
/// Row k is video frame k + round(t₀ · DataRate), t₀ the time of the first row; a keypoint at
/// exactly (0, 0) or a gap is absent (confidence 0), the others have confidence 1. Throws
/// acro::InputError naming the file for a TRC with a non-zero Z (a 3D file) or no frame.
KeypointDetections ReadDetectionsTrc(const std::filesystem::path& path);

/// A directory: ReadOpenPoseJson; a .csv file: ReadDetectionsCsv; a .trc file: ReadDetectionsTrc.
KeypointDetections ReadDetections(const std::filesystem::path& path,
                                  const std::string& keypoint_set,
                                  const std::string& camera = "");

}  // namespace acro::capture
