#pragma once

/// \file
/// One video's jumps from the image alone (docs/one-camera.md, "Flights from the image"): the
/// athlete detected (kept in the video's PoseCacheDirectory), the bed's rest line found in the
/// first frame (or given), every take-off and landing timed from the soles and the hips' arc —
/// time of flight from a phone beside the trampoline, with no calibration.

#include <filesystem>
#include <optional>
#include <string>

#include "acro/base/progress.h"
#include "acro/capture/video.h"
#include "acro/pose/pose_models.h"
#include "acro/vision/image_flights.h"

namespace acro::pipeline {

struct VideoFlightsRequest {
  std::filesystem::path video;
  /// The bed's rest line in the picture; empty: from the bed detected in frame 0.
  std::optional<vision::BedLine> bed_line;
  pose::LandmarkModel model = pose::LandmarkModel::kHeavy;
  vision::ImageFlightOptions options;
};

struct VideoFlights {
  vision::ImageFlights flights;
  capture::VideoInfo info;
  /// The FIG T of the complete flights (all of them: the in-bounces are not told from the
  /// elements without the skills read).
  double time_of_flight_score = 0.0;
};

/// Throws acro::InputError naming the video when it cannot be read, has no bed in frame 0 and no
/// line is given, or its detections cannot give flights; acro::Cancelled when `progress` says stop
/// ("detect").
VideoFlights FindFlightsInVideo(const VideoFlightsRequest& request, const Progress& progress = {});

/// flights.json: the video, its rate, the bed's line, per flight the frames and times (video time,
/// s), how each crossing was timed, and the T.
std::string FormatVideoFlightsJson(const VideoFlights& flights, const std::filesystem::path& video);

}  // namespace acro::pipeline
