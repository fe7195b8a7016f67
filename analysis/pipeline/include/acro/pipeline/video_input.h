#pragma once

/// \file
/// A calibrated camera's video of a trial, as every door uses it (docs/design.md, "One
/// pipeline"): opened once (one reader, one index of its packets), its camera read and sized, the
/// sync with the trial given or found — `auto` means one thing everywhere: the image motion, then
/// refined by the silhouettes to the trial's sample —, the background median built once and
/// shared by the sync, the silhouette check and the overlay.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/base/progress.h"
#include "acro/capture/video.h"
#include "acro/scene/silhouette_check.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/silhouette.h"
#include "acro/vision/video_sync.h"

namespace acro::pipeline {

/// How the video's time relates to the trial's.
struct SyncRequest {
  enum class Kind { kOffset, kEvent, kAuto };
  Kind kind = Kind::kOffset;
  double offset_s = 0.0;  ///< kOffset: video time of the trial's first sample
  double rate = 1.0;      ///< video seconds per trial second
  double event_trial_s = 0.0, event_video_s = 0.0;  ///< kEvent: one moment seen in both

  bool IsValid(std::string* why) const;
};

struct VideoRequest {
  std::filesystem::path video, calibration;
  std::string camera;  ///< the camera's name in the calibration; empty: the only one
  /// A camera had another way (from the bed in the video: MonocularInput::camera), instead of
  /// `calibration`.
  std::optional<vision::Camera> camera_given;
  SyncRequest sync;

  bool IsValid(std::string* why) const;
};

/// The sync found or given, and what was found on the way (for the lines a door prints).
struct SyncOutcome {
  vision::VideoSync sync;
  /// With kAuto: the image motion's result and the silhouettes' refinement.
  std::optional<analysis::AutoVideoSync> found;
  std::vector<std::string> lines;  ///< one per step, for the user
};

class VideoInput {
 public:
  /// Opens the video (once) and reads its camera; a video of another size than the camera's
  /// calibration is a warning (its pixels are taken as the camera's from the top-left corner).
  /// Throws acro::InputError naming the file for what cannot be read, or a camera not in the
  /// calibration.
  explicit VideoInput(const VideoRequest& request);
  ~VideoInput();
  VideoInput(VideoInput&&) noexcept;
  VideoInput& operator=(VideoInput&&) noexcept;

  const VideoRequest& request() const { return request_; }
  capture::VideoReader& reader() { return *reader_; }
  const capture::VideoReader& reader() const { return *reader_; }
  const vision::Camera& camera() const { return camera_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// The background median (25 frames spread over the video, colour), built on first use.
  const vision::BackgroundModel& Background();

  /// The sync as requested. kAuto: the image motion in the athlete's box (a grey pass on this
  /// reader), refined by the silhouettes of `scene`'s athlete (the shared background). Kept: a
  /// second call returns the same. Throws acro::Cancelled when `progress` says stop.
  const SyncOutcome& Sync(analysis::TrialScene& scene, const Progress& progress = {});

  /// The silhouettes of `scene`'s athlete against the video's foreground over every flight frame,
  /// at the sync found (Sync first).
  analysis::SilhouetteCheck CheckSilhouettes(analysis::TrialScene& scene,
                                             const Progress& progress = {});

 private:
  VideoRequest request_;
  std::unique_ptr<capture::VideoReader> reader_;
  vision::Camera camera_;
  std::vector<std::string> warnings_;
  std::unique_ptr<vision::BackgroundModel> background_;
  std::optional<SyncOutcome> sync_;
};

}  // namespace acro::pipeline
