#pragma once

// The virtual athlete over the real video (`acrolab overlay`): every frame of a calibrated
// camera's video, the trial sample the sync puts on it drawn by the scene renderer through that
// camera (distortion included, camera_composite.h), with the heads-up line; into an MP4 or a
// directory of PNG frames. Needs an X display (display.h).

#include <filesystem>
#include <functional>

#include "acro/capture/video.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/silhouette.h"
#include "acro/vision/video_sync.h"

namespace acro::ui {

struct SceneOverlayOptions {
  analysis::SceneShow show;
  vision::VideoSync sync;
  /// The video frames to write, [first_frame, last_frame]; −1: to the end.
  int first_frame = 0;
  int last_frame = -1;
  /// Frames inside a flight are written this many times (slow motion around the flights).
  int slow = 1;
  /// Draw the heads-up line.
  bool heads_up = true;
  /// Shade by the lights; false draws every actor flat in its colour (high contrast, and what a
  /// test measures centroids on).
  bool shaded = true;
  /// The MP4's encoding: x264's "superfast" preset, because the encoder is most of an overlay's
  /// CPU (docs/performance.md, "Overlay": "veryfast" made 1.37× real time at 1080p, this 1.64×).
  capture::VideoWriterOptions video = {.crf = 18, .preset = "superfast"};
  /// Called with (frames done, frames in all); returns false to cancel (nothing is left behind).
  std::function<bool(int, int)> progress;
  /// The video's background (show.mismatch needs it: the athlete's silhouette in each frame), and
  /// how a pixel is told from it.
  const vision::BackgroundModel* background = nullptr;
  vision::BackgroundOptions background_options;
  /// The mismatch is compared in the athlete's silhouette box grown by this fraction of its size
  /// (SilhouetteCheckOptions::box_margin).
  double box_margin = 0.5;
};

/// Where the time of an overlay went (s, wall clock): decoding, drawing the scene (posing, VTK's
/// render and the read-back of its pixels, which waits for the render to finish), compositing
/// onto the frame, and encoding with writing.
struct OverlayTiming {
  int frames_read = 0;
  int frames_written = 0;
  double decode_s = 0;
  double scene_s = 0;
  double render_s = 0;
  double composite_s = 0;
  double encode_s = 0;
};

/// The overlay one frame at a time (the studio's video view, and each frame of WriteSceneOverlay):
/// the trial sample a frame shows drawn over it through the camera, with the mismatch and the
/// heads-up line as `options` say (their sync, frames and encoding are not used here). Needs an X
/// display (it holds one: display.h).
class TrialOverlay {
 public:
  /// Frames of `width` × `height` (the video's size; the camera's pixels are the video's from the
  /// top-left corner). Throws std::invalid_argument for the mismatch without a background model of
  /// that size or without an athlete, and acro::InputError when no X display can be had.
  TrialOverlay(analysis::TrialScene& scene,
               const vision::Camera& camera,
               int width,
               int height,
               const SceneOverlayOptions& options);
  ~TrialOverlay();
  TrialOverlay(const TrialOverlay&) = delete;
  TrialOverlay& operator=(const TrialOverlay&) = delete;

  /// Draws trial sample `sample` over `frame` (RGB, the overlay's size) in place; adds the time
  /// spent to `timing` when given.
  void Draw(int sample, capture::VideoFrame* frame, OverlayTiming* timing = nullptr);
  /// The scene frame last drawn.
  const analysis::TrialFrame& frame() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes the overlay of `scene` on `video` (opened for RGB) through `camera` into `output` (.mp4,
/// else a directory of frame_NNNNNN.png). The camera's pixels are taken to be the video's from the
/// top-left corner even when it was calibrated at another size (the caller warns about it). Throws
/// acro::InputError naming the file for anything that cannot be read or written, and for a
/// cancelled run; std::invalid_argument for show.mismatch without a background model of the
/// video's size or without an athlete.
OverlayTiming WriteSceneOverlay(capture::VideoReader& video,
                                analysis::TrialScene& scene,
                                const vision::Camera& camera,
                                const std::filesystem::path& output,
                                const SceneOverlayOptions& options);

}  // namespace acro::ui
