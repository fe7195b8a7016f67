#pragma once

// What the studio has open (no Qt here): a trial analysed for an athlete, and optionally a
// calibrated camera's video synced with it — read, analysed and synced by the same library
// functions as `acrolab analyze` — and the session file that says what was open and where the
// cursor was, so that a coach picks up where they left off (docs/studio.md).

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_body.h"
#include "acro/capture/trial.h"
#include "acro/capture/video.h"
#include "acro/scene/silhouette_check.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/video_sync.h"

namespace acro::studio {

/// The files a session opens. Paths as given (relative to the working directory, or to the
/// session file when read from one).
struct SessionFiles {
  std::string trial;
  std::string athlete;      ///< empty: a default de Leva athlete (1.70 m, 65 kg), with a warning
  std::string video;        ///< empty: no video
  std::string calibration;  ///< the video's camera calibration (TOML, XML…), with `video`
  std::string camera;       ///< the camera's name in the calibration; empty: the only one
  std::optional<double> offset_s;  ///< the sync; empty: found from the video
};

/// Where the session was left.
struct SessionView {
  int cursor_sample = 0;
  double speed = 1.0;
  std::string preset = "side";  ///< side, front, top
  bool follow = false;
};

class Session {
 public:
  /// Called with (step, done, total); returns false to cancel.
  using Progress = std::function<bool(const std::string&, int, int)>;

  /// Reads the trial and the athlete, analyses the trial, opens the video and its camera and syncs
  /// them (automatically when files.offset_s is empty). Slow (seconds): off the window's thread.
  /// Throws acro::InputError naming the file and what is wrong (or "cancelled").
  static std::unique_ptr<Session> Open(const SessionFiles& files, const Progress& progress = {});

  /// The files, with the offset found when it was found here.
  const SessionFiles& files() const { return files_; }
  const capture::Trial& trial() const { return *trial_; }
  const analysis::AthleteBody& body() const { return body_; }
  const analysis::TrialAnalysis& analysis() const { return *analysis_; }
  analysis::TrialScene& scene() { return *scene_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

  int num_samples() const { return trial_->num_frames; }
  double rate_hz() const { return trial_->point_rate_hz; }

  bool has_video() const { return video_ != nullptr; }
  capture::VideoReader& video() { return *video_; }
  const vision::Camera& camera() const { return camera_; }
  const vision::VideoSync& sync() const { return sync_; }
  /// The video's athlete against the reconstructed one in every filmed flight frame, as `analyze
  /// --video` checks it (the jumps' median IoU is in the analysis); empty without a video.
  const analysis::SilhouetteCheck& silhouettes() const { return silhouettes_; }
  /// The video frame whose time is nearest the sample's (−1 without a video, or when the sample is
  /// more than half a frame outside the video); the sample a video frame shows (−1 outside the
  /// trial).
  int VideoFrameOf(int sample) const;
  int SampleOf(int video_frame) const;

 private:
  Session() = default;
  SessionFiles files_;
  std::unique_ptr<capture::Trial> trial_;
  analysis::AthleteBody body_;
  std::unique_ptr<analysis::TrialAnalysis> analysis_;
  std::unique_ptr<analysis::TrialScene> scene_;
  std::unique_ptr<capture::VideoReader> video_;
  vision::Camera camera_;
  vision::VideoSync sync_;
  analysis::SilhouetteCheck silhouettes_;
  std::vector<std::string> warnings_;
};

/// The session file (JSON, `.acrolab`): format "acrolab-session", version 1, the files (relative
/// to the session file's folder when they are below it), the view. Written atomically.
void WriteSessionFile(const std::filesystem::path& path,
                      const SessionFiles& files,
                      const SessionView& view);
/// Reads one back, paths made relative to the working directory. Throws acro::InputError naming
/// the file and the field at fault.
std::pair<SessionFiles, SessionView> ReadSessionFile(const std::filesystem::path& path);

}  // namespace acro::studio
