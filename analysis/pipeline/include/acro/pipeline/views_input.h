#pragma once

/// \file
/// The input of a door that starts from several calibrated cameras' 2D keypoints instead of a
/// motion-capture file (docs/markerless.md): each camera's detections read (OpenPose JSON folders,
/// CSV, Sports2D TRC), the cameras put on one time line (offsets given, or found from the
/// detections), the keypoints triangulated, and the result opened as every trial is — upright,
/// with its provenance and its athlete — so that reconstruct, assess and report run on it
/// unchanged.

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/assess/trial_analysis.h"
#include "acro/base/progress.h"
#include "acro/pipeline/trial_input.h"
#include "acro/pipeline/video_input.h"
#include "acro/pose/pose_models.h"
#include "acro/reconstruct/triangulation.h"
#include "acro/reconstruct/view_fit.h"
#include "acro/reconstruct/view_sync.h"
#include "acro/vision/bed_detection.h"

namespace acro::pipeline {

struct CameraSource {
  std::string camera;                ///< its name in the calibration
  std::filesystem::path detections;  ///< a folder of OpenPose JSON, a CSV or a 2D TRC
  /// Or its video: the athlete detected by Acrolab's own detector (kept in the video's
  /// PoseCacheDirectory, so a second run reads them back), the rate from the file.
  std::filesystem::path video;
  /// Its frame rate (Hz); 0: ViewsRequest::rate_hz.
  double rate_hz = 0;
  /// Where its frame 0 falls on the first camera's time line, in the first camera's frames; NaN:
  /// found from the detections (ViewsRequest::sync) or 0.
  double offset_frames = std::numeric_limits<double>::quiet_NaN();
};

struct ViewsRequest {
  std::vector<CameraSource> cameras;  ///< the first is the time line's reference
  std::filesystem::path calibration;
  /// The keypoint set of JSON detections (capture::KeypointSetNames); CSV and TRC name theirs.
  std::string keypoint_set = "body25b";
  /// The detections' frame rate (Hz), for the cameras that do not give their own: JSON files carry
  /// no time. Required (> 0).
  double rate_hz = 0;
  /// Offsets not given are found from the detections (analysis::SyncViews); false: taken as 0.
  bool sync = true;
  analysis::ViewSyncOptions sync_options;
  /// The detector's network for the cameras given by their videos.
  pose::LandmarkModel model = pose::LandmarkModel::kHeavy;
  analysis::TriangulationOptions triangulation;
  /// The calibration's up axis, as TrialRequest::up.
  std::string up = "auto";
  AthleteChoice athlete;
  int min_frames = 2;
  std::string use = "the analysis";
};

struct ViewsInput {
  /// The triangulated keypoints as a trial (path: the first camera's detections; sha256 over the
  /// calibration's and every detection file's bytes), upright, with the athlete.
  TrialInput input;
  analysis::Triangulation triangulation;
  /// The cameras' keypoints, posed in the trial's (upright) world: what
  /// ReconstructionOptions::views takes for the fit of the model to the views.
  std::shared_ptr<const analysis::ViewsToFit> views;
  std::vector<analysis::ViewOffset> offsets;  ///< per camera, as used (found or given)
  /// Per camera, where its offset comes from: "the time line" (the first camera), "found" (from
  /// the detections), "given", or "assumed" (0: not found, or --no-sync).
  std::vector<std::string> offset_origin;
  /// The time line's first frame in each camera's own frames (its frame f is the trial's sample
  /// (f − first_frame[v]) · the first camera's rate / its rate): how a door puts the trial on one
  /// camera's video (the sync of an overlay).
  std::vector<double> first_frame;
  std::vector<double> rates_hz;  ///< each camera's frame rate
  /// The trampoline's bed located from its detection in the videos' first frames
  /// (vision::LocateBedFromViews), when the cameras were given by their videos, at least two saw
  /// the bed, they agree, and the cameras' world is Z up as the trial (else a warning says why).
  std::optional<vision::BedFromViews> bed;
};

/// Reads, syncs and triangulates. Throws acro::InputError naming the file, camera or option at
/// fault: a camera missing from the calibration (naming those there are), two sources for one
/// camera, fewer than two cameras, detections whose keypoints differ from the set or from the
/// other cameras', no rate; a camera that sees nobody is a warning and the others are used.
/// `progress` as acro::Progress ("detect", "sync", "triangulate").
ViewsInput OpenViews(const ViewsRequest& request, const Progress& progress = {});

/// What an analysis of several cameras takes from them, the same for every door: the views the
/// model is fitted to and, with no bed in the options, the bed found in their first frames.
/// Returns the line saying where that bed is ("" when none was taken).
std::string UseViews(const ViewsInput& views, analysis::TrialAnalysisOptions* options);

/// The first camera's video as the analysis attaches it, on the time line the triangulation made.
VideoRequest FirstViewVideo(const ViewsInput& views, const std::filesystem::path& calibration);

/// A video as `analyze --video` takes it when several are given: "CAM=PATH", or a path whose file
/// name's stem is a camera's name or starts with it and '_', '-' or '.' ("side_camera.mp4" for
/// camera "side"; the longest such name). Throws acro::InputError (where "--video") naming the
/// calibration's cameras when none matches.
CameraSource VideoSource(const std::string& text,
                         const std::vector<vision::Camera>& cameras,
                         const std::string& calibration);

/// The SHA-256 of a detections source: of the file, or of a folder's JSON files' names and hashes
/// (in name order) — the bytes a door's provenance names.
std::string HashOfSource(const std::filesystem::path& path);

/// "CAM=PATH" as `--detections` takes it. Throws acro::InputError (where "--detections").
CameraSource ParseCameraSource(const std::string& text);

}  // namespace acro::pipeline
