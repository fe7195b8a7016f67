#pragma once

// `acrolab compare`'s video: two jumps aligned at take-off (analysis/scene/compare_scene.h), seen
// from the side in three views — the first, the second, and both superimposed (the second as a
// blue ghost) — over the trampoline, with the chart panel under them and a cursor on it. Needs an
// X display (display.h).

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "acro/capture/video.h"
#include "acro/scene/compare_scene.h"
#include "acro/scene/place_scene.h"
#include "acro/scene/scene.h"
#include "acro/views/scene_renderer.h"

namespace acro::ui {

struct CompareVideoOptions {
  /// Each of the three views (the video is three views wide; the panel goes under them).
  int view_width = 480;
  int view_height = 540;
  double fps = 30.0;
  /// Video seconds per second of the jumps (2: half speed).
  double slow = 1.0;
  /// Where the views look from, for A's take-off heading: its side (from the athlete's right), its
  /// front or the top, at mid-flight height above A's take-off.
  ViewPreset view = ViewPreset::kSide;
  /// Follow the athletes (their centres of mass) instead: the same direction and distance.
  bool follow = false;
  /// The trampoline to draw (the first trial's bed), if any.
  std::optional<analysis::TrampolineScene> trampoline;
  capture::VideoWriterOptions video = {.crf = 18, .preset = "superfast"};
  std::function<bool(int, int)> progress;
};

/// The comparison one instant at a time (the studio's compare window, and each frame of
/// WriteCompareVideo): the three views over the panel with its cursor, as one RGB picture (three
/// views wide). Holds an X display (display.h).
class CompareDrawer {
 public:
  /// Throws std::invalid_argument when the panel (not empty) is not three views wide.
  CompareDrawer(analysis::CompareScene& scene,
                const analysis::TimedPanel& panel,
                const CompareVideoOptions& options);
  ~CompareDrawer();
  CompareDrawer(const CompareDrawer&) = delete;
  CompareDrawer& operator=(const CompareDrawer&) = delete;
  int width() const;
  int height() const;
  /// The picture at τ = `tau_s` from the take-offs into `rgb` (width × height × 3).
  void Draw(double tau_s, std::vector<std::uint8_t>* rgb);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes the comparison into `output` (.mp4, else a directory of PNG frames); returns the frames
/// written. The panel (may be empty) is scaled to nothing: its width should be three views'.
/// Throws acro::InputError naming the file for anything that cannot be written, and for a
/// cancelled run.
int WriteCompareVideo(analysis::CompareScene& scene,
                      const analysis::TimedPanel& panel,
                      const std::filesystem::path& output,
                      const CompareVideoOptions& options);

}  // namespace acro::ui
