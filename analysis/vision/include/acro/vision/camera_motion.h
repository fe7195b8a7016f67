#pragma once

// Whether a camera held still (docs/one-camera.md, "When the camera moves"): one camera's
// analysis takes the bed's line and the camera's pose from the first frame, so a camera that pans,
// tilts or is knocked afterwards puts every later number against a bed that is no longer where the
// picture shows it. The picture's shift against the first frame: patches around the first frame's
// corners (Shi–Tomasi, OpenCV's goodFeaturesToTrack) found again in each frame near where the
// shift so far puts them (normalised cross-correlation), the median of their displacements — the
// athlete's corners move and are outvoted by the background's. Phase correlation was tried first:
// on a picture with little texture (the sample's rendered hall) the athlete's motion dominates its
// whitened spectrum and it read a still camera as moving 25–35 px.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "acro/base/progress.h"
#include "acro/vision/image_flights.h"

namespace acro::vision {

struct CameraMotionOptions {
  /// Frames are reduced to about this width (px) before the matching.
  int analysis_width_px = 640;
  /// Every this many frames is compared with the first (the rest are decoded, not compared).
  int every_frames = 3;
  /// A shift of the picture beyond this (px of the video) is a camera that moved.
  double moved_px = 4.0;
  bool IsValid(std::string* why) const;
};

struct CameraMotion {
  std::string path;
  int width_px = 0;         ///< the video's
  std::vector<int> frames;  ///< the frames compared with the first
  std::vector<Eigen::Vector2d>
      shift;              ///< per compared frame: its picture's shift (px of the video)
  double moved_px = 4.0;  ///< the options' threshold
  /// Why the motion could not be measured at all (empty: it was).
  std::string unmeasured;
  /// The frame where the first frame's background could not be followed any more (the
  /// measurement stops there: where the camera points after it is not known); empty: followed.
  std::vector<int> lost_frames;
  /// The largest shift's length over the compared frames in [first, last] (0 when none; infinite
  /// when the background was lost at or before `last`).
  double LargestShiftPx(int first, int last) const;
  /// The first compared frame whose shift is beyond moved_px, else the frame where the background
  /// was lost (−1: the camera held still).
  int FirstMovedFrame() const;
};

/// Throws acro::InputError naming the video when it cannot be read; `progress` as acro::Progress
/// ("camera motion", frames read).
CameraMotion MeasureCameraMotion(const std::filesystem::path& video,
                                 const CameraMotionOptions& options = {},
                                 const Progress& progress = {});

/// One line per flight (first and last frame of the span it was timed over, and its label) whose
/// frames show the picture shifted beyond motion.moved_px from the first frame's — the frame the
/// bed's line and the camera's pose came from — and, before them, one line for the whole video
/// when its camera moved at all.
std::vector<std::string> CameraMotionWarnings(
    const CameraMotion& motion,
    const std::vector<std::pair<std::pair<int, int>, std::string>>& spans);

/// CameraMotionWarnings for the flights found in the picture (each from its last frame on the
/// bed to its first back on it, or to the video's end), named "flight N (t0–t1 s)" by its frames
/// in the air as the flights' own warnings name them. With motion.unmeasured, its one line.
std::vector<std::string> CameraMotionWarnings(const CameraMotion& motion,
                                              const ImageFlights& flights);

}  // namespace acro::vision
