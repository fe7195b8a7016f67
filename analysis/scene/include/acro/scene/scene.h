#pragma once

// The vocabulary of what to draw: meshes, line segments and points in the lab frame W (metres),
// with colours by meaning. Plain data, so that a scene is built and tested without a display and
// any renderer (ui/views, VTK) draws it the same way.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

/// A colour with components in [0, 1] and an opacity (1 opaque).
struct Rgba {
  float r = 0.6f;
  float g = 0.6f;
  float b = 0.6f;
  float a = 1.0f;
};

/// The side of the body a segment or a point is on, as the colours say it: the left side red, the
/// right green (the convention of Vicon's Plug-in Gait, which coaches and biomechanists know).
enum class BodySide { kLeft, kRight, kCentre };

/// The side a name says: a segment "l_thigh", a keypoint "LKnee" or "left_knee", a marker "RASI"
/// (a first word or letter l/left, r/right before the rest); anything else is the centre.
BodySide SideOfName(const std::string& name);

/// Red for the left, green for the right, `centre` for the centre.
Rgba SideColour(BodySide side, Rgba centre);

/// A triangle mesh: vertices (3 × V, W) and triangles (3 × T vertex indices, counter-clockwise seen
/// from outside).
struct SceneMesh {
  std::string name;
  Eigen::Matrix3Xd vertices_W;
  Eigen::Matrix3Xi triangles;
  Rgba colour;
};

/// Line segments: points 2k and 2k + 1 are the ends of segment k (3 × 2N, W).
struct SceneLines {
  std::string name;
  Eigen::Matrix3Xd points_W;
  Rgba colour;
  double width_px = 2.0;
  /// Per segment, its side of the body (SideColour: left red, right green, centre `colour`);
  /// empty: all `colour`.
  std::vector<BodySide> segment_sides;

  int num_segments() const { return static_cast<int>(points_W.cols() / 2); }
};

/// A picture to show beside the 3D views (a chart drawn elsewhere: RGB, 3 bytes per pixel, rows
/// top to bottom) and where a time cursor runs on it: per plot, the columns of `start_s` and
/// `end_s` and the rows it spans.
struct TimedPanel {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
  std::vector<std::array<double, 4>> cursor_spans_px;  ///< x at start, x at end, y top, y bottom
  double start_s = 0.0;
  double end_s = 1.0;
};

}  // namespace acro::analysis
