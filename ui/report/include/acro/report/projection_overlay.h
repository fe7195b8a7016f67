#pragma once

// The simplest virtual-over-real overlay: a trial's points, projected into a calibrated camera,
// drawn on the synced frames of its video (`acrolab project --video`), as an MP4 or a PNG per
// frame. Drawing is Cairo's; decoding and encoding capture's.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/video.h"
#include "acro/vision/projection.h"

namespace acro::ui {

/// Draws a filled disc with a dark rim at each point on an RGB frame (3 bytes per pixel), in
/// place; the colour of point i is the palette's colour of `colour_index[i]` (or the first).
void DrawPoints(int width,
                int height,
                const std::vector<Eigen::Vector2d>& points_px,
                const std::vector<int>& colour_index,
                double radius_px,
                std::vector<std::uint8_t>* rgb);

struct OverlayVideoOptions {
  vision::AxisMapping axes;
  vision::VideoSync sync;
  /// Disc radius in pixels; 0: 0.4 % of the frame's diagonal, at least 3 px.
  double radius_px = 0.0;
  /// Called with (frames done, frames in all); returns false to cancel (nothing is left behind).
  std::function<bool(int, int)> progress;
};

/// Draws the trial's points on every frame of the video (the sample the sync puts nearest to each
/// frame; frames outside the trial are written as they are) into `output`: an .mp4 file (H.264, at
/// the video's average rate), or else a directory of frame_NNNNNN.png. Both appear only when
/// complete; an existing directory is replaced only if it holds nothing but such frames. Returns
/// the frames written. Throws acro::InputError naming the file for anything that cannot be read or
/// written, and for a cancelled run.
int WriteProjectionOverlay(capture::VideoReader& video,
                           const capture::Trial& trial,
                           const vision::Camera& camera,
                           const std::filesystem::path& output,
                           const OverlayVideoOptions& options);

}  // namespace acro::ui
