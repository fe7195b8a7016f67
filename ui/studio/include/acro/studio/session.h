#pragma once

// What the studio has open (no Qt here): a trial analysed for an athlete, and up to four
// calibrated cameras' videos synced with it — read, analysed, synced and checked by the same
// library functions as `acrolab analyze` — and the session file that says what was open and where
// the cursor was, so that a coach picks up where they left off (docs/studio.md).

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_body.h"
#include "acro/base/progress.h"
#include "acro/capture/trial.h"
#include "acro/capture/video.h"
#include "acro/pipeline/trial_input.h"
#include "acro/pipeline/video_input.h"
#include "acro/scene/silhouette_check.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/video_sync.h"

namespace acro::studio {

/// One calibrated camera's video of the trial.
struct VideoFiles {
  std::string video;
  std::string calibration;         ///< the camera's calibration (TOML, XML…)
  std::string camera;              ///< the camera's name in the calibration; empty: the only one
  std::optional<double> offset_s;  ///< the sync; empty: found from the video
};

/// The most videos a session shows (the window's four video views).
constexpr int kMaxVideos = 4;

/// The files a session opens. Paths as given (relative to the working directory, or to the
/// session file when read from one). No trial and one video: the video analysed alone (one
/// camera, docs/one-camera.md), its camera from its calibration or, with none, from the bed.
struct SessionFiles {
  std::string trial;
  std::string athlete;  ///< empty: the default body of every door (pipeline::kDefaultHeightM…),
                        ///< with a warning
  std::vector<VideoFiles> videos;  ///< none to kMaxVideos
};

/// Where the session was left.
struct SessionView {
  int cursor_sample = 0;
  double speed = 1.0;
  std::string preset = "side";  ///< side, front, top
  bool follow = false;
  /// What the 3D view shows: ParseSceneShow's words, and "cameras" for the videos' cameras.
  std::string show = "mesh,skeleton,com";
  /// The 3D view turned about its target from the preset, and its distance scaled.
  double orbit_azimuth_deg = 0.0;
  double orbit_elevation_deg = 0.0;
  double orbit_distance_scale = 1.0;
};

/// No trial and one video: the video is analysed alone.
bool OneVideoAlone(const SessionFiles& files);

class Session {
 public:
  /// Called with (step, done, total); returns false to cancel.
  using Progress = std::function<bool(const std::string&, int, int)>;

  /// Reads the trial and the athlete, analyses the trial, opens each video and its camera, syncs
  /// them (automatically when a video's offset_s is empty) and checks the silhouettes — the
  /// pipeline's steps, as `analyze` runs them. Slow (seconds per video): off the window's thread.
  /// Throws acro::InputError naming the file and what is wrong, acro::Cancelled when the progress
  /// says stop.
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

  int num_videos() const { return static_cast<int>(videos_.size()); }
  bool has_video() const { return !videos_.empty(); }
  /// Video `k` (0-based, in the order of files().videos): its reader, camera, sync, and its
  /// athlete against the reconstructed one in every filmed flight frame, as `analyze --video`
  /// checks it. The jumps' median IoU in the analysis is the first video's.
  capture::VideoReader& video(int k = 0) { return videos_.at(size_t(k)).input->reader(); }
  const vision::Camera& camera(int k = 0) const { return videos_.at(size_t(k)).input->camera(); }
  const vision::VideoSync& sync(int k = 0) const { return videos_.at(size_t(k)).sync; }
  const analysis::SilhouetteCheck& silhouettes(int k = 0) const {
    return videos_.at(size_t(k)).silhouettes;
  }
  /// The frame of video `k` whose time is nearest the sample's (−1 without that video, or when
  /// the sample is more than half a frame outside it); the sample a frame of video `k` shows (−1
  /// outside the trial).
  int VideoFrameOf(int sample, int k = 0) const;
  int SampleOf(int video_frame, int k = 0) const;

 private:
  struct Video {
    std::unique_ptr<pipeline::VideoInput>
        input;  // the video opened once: reader, camera, background
    vision::VideoSync sync;
    analysis::SilhouetteCheck silhouettes;
  };
  Session() = default;
  // The inputs: the trial and its videos, or one video analysed alone (its keypoints the trial);
  // the one camera's options into `options`.
  pipeline::TrialInput OpenTrialAndVideos(const acro::Progress& steps);
  pipeline::TrialInput OpenOneVideo(const acro::Progress& steps,
                                    analysis::TrialAnalysisOptions* options);
  SessionFiles files_;
  std::unique_ptr<capture::Trial> trial_;
  analysis::AthleteBody body_;
  std::unique_ptr<analysis::TrialAnalysis> analysis_;
  std::unique_ptr<analysis::TrialScene> scene_;
  std::vector<Video> videos_;
  std::vector<std::string> warnings_;
};

/// What a SessionView::show list asks of the 3D view: the scene's parts (analysis::ParseSceneShow's
/// words) and whether "cameras", the studio's own word, is among them. Throws acro::InputError
/// (where "--show") for a word that is neither.
struct ShownParts {
  analysis::SceneShow scene;
  bool cameras = false;
};
ShownParts ParseShownParts(const std::string& list);

/// The session file (JSON, `.acrolab`): format "acrolab-session", version 2, the files (relative
/// to the session file's folder when they are below it; `videos` a list of {video, calibration,
/// camera, offset_s}), the view. Written atomically. Version 1 (one video's keys at the top
/// level) is read too.
void WriteSessionFile(const std::filesystem::path& path,
                      const SessionFiles& files,
                      const SessionView& view);
/// Reads one back, paths made relative to the working directory. Throws acro::InputError naming
/// the file and the field at fault.
std::pair<SessionFiles, SessionView> ReadSessionFile(const std::filesystem::path& path);

}  // namespace acro::studio
