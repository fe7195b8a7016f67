#pragma once

#include <string>
#include <vector>

#include "acro/capture/trial.h"

namespace acro::capture {

/// Missing samples of one marker.
struct MarkerGaps {
  std::string label;
  int missing_frames = 0;      ///< frames where the marker is a gap
  int longest_gap_frames = 0;  ///< longest run of consecutive missing frames
  int gap_count = 0;           ///< number of runs of missing frames
};

/// Gaps of every marker (PointType::kMarker points) in label order.
std::vector<MarkerGaps> CalcMarkerGaps(const Trial& trial);

/// What `acrolab info` prints: a human-readable report, and the JSON object documented in
/// docs/cli.md (keys: format, processor, frames, point_rate_hz, markers, marker_labels,
/// missing_marker_frames_total, gaps, analog_channels, analog_rate_hz, force_plates, events,
/// warnings, and more).
std::string FormatTrialInfoText(const Trial& trial);
std::string FormatTrialInfoJson(const Trial& trial);

}  // namespace acro::capture
