#pragma once

// Filmstrips (the source paper's Figure 8): the athlete at a few instants of a flight, drawn from
// the side one after another left to right — each pose moved along the strip, its height kept —
// in a parallel projection, so that shapes and heights compare at one scale. Several rows (an
// initial and an optimised timing, two jumps) are drawn one above the other at the same scale,
// each labelled. As a video, the strip fills in as the flight goes: the athlete moves along it and
// leaves a translucent copy at each instant it passes. Needs an X display (display.h).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/assess/trial_analysis.h"
#include "acro/scene/athlete_scene.h"
#include "acro/scene/scene.h"

namespace acro::ui {

struct FilmstripOptions {
  int width = 1200;
  /// Pixels per row (the picture is `rows` × this high).
  int height = 320;
  /// Metres between consecutive poses along the strip.
  double spacing_m = 1.1;
  analysis::Rgba colour = {0.9f, 0.62f, 0.45f, 1.0f};
};

/// One row: `scene`'s athlete at the motion's frames `frames` (left to right), the motion sampled
/// at `rate_hz` (for the video's clock), labelled `label` (none when empty).
struct FilmstripRow {
  analysis::AthleteScene* scene = nullptr;
  std::vector<int> frames;
  double rate_hz = 0.0;
  std::string label;
  analysis::Rgba colour = {0.9f, 0.62f, 0.45f, 1.0f};
};

/// An RGB picture (3 bytes per pixel, rows top to bottom, options' size) of `scene`'s athlete at
/// the motion's frames `frames`, seen from its left side for an athlete facing `heading_W`
/// (horizontal). Throws std::invalid_argument for no frame or a frame outside the motion.
std::vector<std::uint8_t> RenderFilmstrip(analysis::AthleteScene& scene,
                                          const std::vector<int>& frames,
                                          const Eigen::Vector3d& heading_W,
                                          const FilmstripOptions& options = {});

/// The rows one above the other at one scale, each labelled at its top left: an RGB picture of
/// options.width × (rows × options.height). Throws std::invalid_argument for no row, a row without
/// its scene, frames or rate, or a frame outside its motion.
std::vector<std::uint8_t> RenderFilmstrips(const std::vector<FilmstripRow>& rows,
                                           const Eigen::Vector3d& heading_W,
                                           const FilmstripOptions& options = {});

struct FilmstripVideoOptions {
  double fps = 30.0;
  /// Slow motion: each second of flight lasts `slow` seconds.
  int slow = 2;
  /// The finished strip held at the end (s).
  double hold_s = 1.0;
  /// Called after each frame with (frames done, frames in all); false cancels (acro::InputError,
  /// nothing written).
  std::function<bool(int, int)> progress;
};

/// The same rows as an MP4 (H.264) of the flight: at video time v each row shows its athlete at
/// motion time v / slow from its first frame, placed along the strip between the instants it lies
/// between, and a translucent copy at every instant already passed; the rows share the clock. The
/// file appears only when complete. Returns the number of frames written. Throws as
/// RenderFilmstrips, and acro::InputError naming `path` when it cannot be written.
int WriteFilmstripVideo(const std::vector<FilmstripRow>& rows,
                        const Eigen::Vector3d& heading_W,
                        const std::filesystem::path& path,
                        const FilmstripOptions& options = {},
                        const FilmstripVideoOptions& video = {});

/// `count` frames evenly spaced from `first` to `last` (both included).
std::vector<int> EvenlySpacedFrames(int first, int last, int count);

/// The filmstrips of an analysis, as `analyze` writes them into `dir`: per complete jump
/// filmstrip_jump_N.png (8 instants of its flight, seen from its take-off heading) and, with
/// `videos`, filmstrip_jump_N.mp4; the files' names per jump index. Throws acro::InputError when
/// the views cannot render here (no display) or a file cannot be written.
struct JumpFilmstrips {
  std::vector<std::pair<int, std::string>> pictures, videos;
};
JumpFilmstrips WriteJumpFilmstrips(analysis::AthleteScene& athlete, const analysis::TrialAnalysis& analysis,
                                   const std::filesystem::path& dir, bool videos,
                                   const std::function<bool(int, int)>& progress = {});

}  // namespace acro::ui
