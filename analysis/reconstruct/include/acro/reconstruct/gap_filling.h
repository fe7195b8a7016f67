#pragma once

// Filling gaps (occlusions) in marker trajectories: a cubic spline through the samples on both
// sides for short gaps, the rigid-body motion of three other markers of the same segment for
// longer ones. A gap is filled only between two recorded samples (never extrapolated at the
// trial's ends) and never when longer than max_rigid_gap_s — a third of the shortest trampoline
// flight (about 1 s), so that no gap that spans a whole flight is ever invented.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

struct GapFillingOptions {
  /// Gaps up to this many frames get a cubic spline.
  int max_spline_gap_frames = 20;
  /// Samples each side used by the spline (natural cubic spline through them).
  int spline_support_frames = 6;
  /// Longer gaps up to this duration get the rigid-body fill (needs three other markers of the
  /// segment present over the gap and at both ends).
  double max_rigid_gap_s = 0.3;
  bool IsValid(std::string* why) const;
};

struct GapFillingSummary {
  int gaps_found = 0;
  int filled_spline = 0;
  int filled_rigid = 0;
  int left_open = 0;  ///< at the ends, too long, or without three segment partners
  long samples_filled = 0;
  std::string BriefReport() const;
};

/// Fills gaps in `positions` (3 × (frames·markers), frame-major as capture::Trial stores them,
/// NaN = gap). `segment_of_marker` groups markers for the rigid fill (−1: no group).
GapFillingSummary FillGaps(Eigen::Matrix3Xd& positions,
                           int num_markers,
                           const std::vector<int>& segment_of_marker,
                           double rate_hz,
                           const GapFillingOptions& options = {});

}  // namespace acro::analysis
