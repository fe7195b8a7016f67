#pragma once

// What the fits to the cameras' keypoints share (view_fit.cc, flight_physics.cc): a camera's focal
// length in pixels and the median of the reported errors.

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "acro/vision/camera.h"

namespace acro::analysis::view_residuals {

/// The mean of fx and fy (px): normalised coordinates × this = pixels.
inline double FocalPx(const vision::Camera& c) {
  return 0.5 * (c.K(0, 0) + c.K(1, 1));
}

/// The median (the upper of the middle two); NaN when empty.
inline double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace acro::analysis::view_residuals
