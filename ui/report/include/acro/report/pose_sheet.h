#pragma once

// 2D keypoints drawn over video frames (docs/pose.md): a skeleton on one frame, and a contact
// sheet — frames side by side, each cropped around the person, with the frame number — to look at
// a detection at a glance. Drawing is Cairo's; decoding capture's.

#include <cstdint>
#include <filesystem>
#include <utility>
#include <vector>

#include "acro/base/progress.h"
#include "acro/capture/detections.h"
#include "acro/capture/video.h"

namespace acro::ui {

/// Draws `person` (u px, v px, confidence per keypoint) on an RGB frame in place: each edge (a
/// pair of keypoint indices) whose two ends have a confidence of at least `min_confidence` as a
/// line — the person's left side blue, the right side orange, the middle white, by `side` (−1
/// right, +1 left, 0 middle, per keypoint) — and each such keypoint as a dot whose grey shows its
/// confidence.
void DrawSkeleton(int width,
                  int height,
                  const capture::DetectedPerson& person,
                  const std::vector<std::pair<int, int>>& edges,
                  const std::vector<int>& side,
                  double min_confidence,
                  std::vector<std::uint8_t>* rgb);

struct ContactSheetOptions {
  int columns = 6;
  int cell_px = 240;  ///< each cell's side
  double min_confidence = 0.2;
  /// Crop: one box for every frame (the union of the people's boxes, so that their motion shows)
  /// when true, else each frame cropped around its own person.
  bool common_crop = true;
};

/// A PNG of the frames `frame_indices` of `video` with `people[k]` (the person of frame
/// frame_indices[k]; an all-zero confidence for none) drawn over each, written atomically.
/// Throws acro::InputError for a video or file that cannot be read or written.
void WritePoseContactSheet(capture::VideoReader& video,
                           const std::vector<int>& frame_indices,
                           const std::vector<capture::DetectedPerson>& people,
                           const std::vector<std::pair<int, int>>& edges,
                           const std::vector<int>& side,
                           const std::filesystem::path& path,
                           const ContactSheetOptions& options = {});

/// The video with each frame's people drawn (`people[k]`: those of frame k; a frame beyond the
/// list, or without people, is written as it is) into `output`, an .mp4 (H.264 at the video's
/// average rate), written whole. `progress` as acro::Progress (false cancels: acro::Cancelled,
/// nothing left behind). Only the video frames first_frame … last_frame (0-based, inclusive;
/// last_frame −1: to the end) are written; a first frame beyond the video is acro::InputError.
/// Returns the frames written.
int WriteDetectionOverlay(capture::VideoReader& video,
                          const std::vector<std::vector<capture::DetectedPerson>>& people,
                          const std::vector<std::pair<int, int>>& edges,
                          const std::vector<int>& side,
                          const std::filesystem::path& output,
                          const Progress& progress = {},
                          double min_confidence = 0.2,
                          int first_frame = 0,
                          int last_frame = -1);

}  // namespace acro::ui
