#pragma once

// A filmstrip (the source paper's Figure 8): the athlete at a few instants of a flight, drawn from
// the side one after another left to right — each pose moved along the strip, its height kept —
// in a parallel projection, so that shapes and heights compare at one scale. Needs an X display
// (display.h).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "acro/scene/athlete_scene.h"
#include "acro/scene/scene.h"

namespace acro::ui {

struct FilmstripOptions {
  int width = 1200;
  int height = 320;
  /// Metres between consecutive poses along the strip.
  double spacing_m = 1.1;
  analysis::Rgba colour = {0.9f, 0.62f, 0.45f, 1.0f};
};

/// An RGB picture (3 bytes per pixel, rows top to bottom, options' size) of `scene`'s athlete at
/// the motion's frames `frames`, seen from its left side for an athlete facing `heading_W`
/// (horizontal). Throws std::invalid_argument for no frame or a frame outside the motion.
std::vector<std::uint8_t> RenderFilmstrip(analysis::AthleteScene& scene,
                                          const std::vector<int>& frames,
                                          const Eigen::Vector3d& heading_W,
                                          const FilmstripOptions& options = {});

/// `count` frames evenly spaced from `first` to `last` (both included).
std::vector<int> EvenlySpacedFrames(int first, int last, int count);

}  // namespace acro::ui
