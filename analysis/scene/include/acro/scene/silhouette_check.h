#pragma once

// The virtual athlete against the real one without markers on the image: in every video frame of
// a flight, the athlete's silhouette cut out of the video by a background model against the
// reconstructed athlete's mesh projected by the camera model; their intersection over union per
// frame and per flight. A good reconstruction, sync and calibration give a high IoU; a sync a few
// frames off or a wrong calibration shows as a drop. (Issue "virtual against real", item 6;
// docs/overlay.md.)

#include <filesystem>
#include <functional>
#include <vector>

#include "acro/capture/video.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/silhouette.h"
#include "acro/vision/sync.h"
#include "acro/vision/video_sync.h"

namespace acro::analysis {

struct SilhouetteCheckOptions {
  vision::VideoSync sync;
  vision::BackgroundOptions background;
  /// Frames the background median is taken over, spread over the video.
  int background_frames = 25;
  /// A background model of this video built already (the pipeline's video input keeps one); null:
  /// one is built from `background_frames` frames.
  const vision::BackgroundModel* background_model = nullptr;
  /// The IoU is taken in the projected athlete's box grown by this fraction of its size on every
  /// side (what the video shows elsewhere — a coach walking by — does not count).
  double box_margin = 0.5;
  /// Called with (frames done, frames in all); returns false to cancel (acro::Cancelled).
  std::function<bool(int, int)> progress;
};

struct SilhouetteCheck {
  /// Per compared video frame (every frame whose synced sample is inside a flight).
  std::vector<int> frames;
  std::vector<int> samples;
  std::vector<int> flights;  ///< index into the analysis' flights
  std::vector<double> iou;
  /// Per flight of the analysis: the median IoU of its frames (NaN when none was filmed).
  std::vector<double> flight_median_iou;
  /// The median over every compared frame (NaN when none).
  double median_iou = 0.0;
};

/// Records `check` in the analysis it was made for: each jump's median IoU over its flight's frames
/// (JumpMetrics::silhouette_iou; left empty for a flight the video did not film).
void AttachSilhouetteCheck(const SilhouetteCheck& check, TrialAnalysis* analysis);

/// One frame's comparison with the video's foreground: the athlete's silhouette (the whole frame),
/// the box they are compared in — the athlete's silhouette box grown by `margin` of its size on
/// every side — and their intersection over union there.
struct SilhouetteFrame {
  vision::Mask athlete;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< [x0, x1) × [y0, y1); empty when not in view
  double iou = 0.0;                    ///< 0 when the athlete is not in view
};

/// Compares `real` (the video frame's foreground) with the athlete of `tf` seen by `camera` (its
/// pixels the video's).
void CompareSilhouettes(const vision::Mask& real,
                        const TrialFrame& tf,
                        const vision::Camera& camera,
                        double margin,
                        SilhouetteFrame* out);

/// The same with the video's frame: its foreground (`real`) worked out in the compared box only,
/// every pixel outside it 0 — the same IoU for a tenth of the work on a 1080p frame.
void CompareSilhouettes(const vision::BackgroundModel& background,
                        const capture::VideoFrame& frame,
                        const vision::BackgroundOptions& options,
                        const TrialFrame& tf,
                        const vision::Camera& camera,
                        double margin,
                        vision::Mask* real,
                        SilhouetteFrame* out);

/// Compares the video (an RGB reader: the background model and the foreground in colour; a grey
/// one works, less well) with the scene's athlete through `camera`. Throws std::invalid_argument
/// when the scene has no athlete, acro::InputError for video trouble, acro::Cancelled when the
/// progress says stop.
SilhouetteCheck CheckSilhouettes(capture::VideoReader& video,
                                 TrialScene& scene,
                                 const vision::Camera& camera,
                                 const SilhouetteCheckOptions& options = {});

/// The sync that makes the silhouettes agree best: the offsets from `options.sync` − `half_range_s`
/// to + `half_range_s` in steps of one trial sample (the poses are the trial's samples), each
/// scored by the median IoU over every `frame_stride`-th flight frame; the video's foregrounds are
/// computed once. A refinement of a sync found otherwise (from the image motion, within a frame):
/// at a somersault's speed a hand moves 8 cm in one sample at 120 Hz, which the silhouettes see.
struct SilhouetteSync {
  vision::VideoSync sync;
  double median_iou = 0.0;          ///< at the offset found
  std::vector<double> offsets_s;    ///< every offset tried
  std::vector<double> median_ious;  ///< and its score
};

SilhouetteSync RefineSyncBySilhouettes(capture::VideoReader& video,
                                       TrialScene& scene,
                                       const vision::Camera& camera,
                                       const SilhouetteCheckOptions& options,
                                       double half_range_s,
                                       int frame_stride = 3);

/// The sync of a video with a trial found from the video alone, as `analyze --sync auto` does it:
/// from the image motion in the athlete's box (vision::SyncFromImageMotion, within a frame), then
/// refined by the silhouettes to the trial's sample (RefineSyncBySilhouettes, a frame either way).
struct AutoVideoSync {
  vision::AutoSyncResult motion;  ///< the first step
  SilhouetteSync refined;         ///< the second; refined.sync is the answer
};

/// `motion.progress` and `silhouettes.progress` report each step (and cancel it: acro::Cancelled);
/// the one reader `video` serves both passes (grey for the motion, then as it was handed in —
/// colour — for the silhouettes). Throws acro::InputError for video trouble,
/// std::invalid_argument for a scene without an athlete.
AutoVideoSync SyncVideoAutomatically(TrialScene& scene,
                                     const vision::Camera& camera,
                                     capture::VideoReader& video,
                                     const vision::AutoSyncOptions& motion,
                                     SilhouetteCheckOptions silhouettes);

}  // namespace acro::analysis
