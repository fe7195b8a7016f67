#pragma once

/// \file
/// The input of a door that starts from one calibrated camera's video (docs/one-camera.md, "The
/// athlete from one camera"): the athlete detected, the flights found in the picture, the
/// athlete's distance from the camera told by gravity — in flight the centre of mass falls at g,
/// which the picture shows as g·f/Z px/s² — and every keypoint put where its ray meets the
/// vertical plane at that distance, square to the camera: a trial of keypoints opened as every
/// trial is (upright, hashed, with its athlete), with the camera's keypoints for the fit of the
/// model to its rays.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acro/assess/trial_analysis.h"
#include "acro/base/progress.h"
#include "acro/pipeline/trial_input.h"
#include "acro/pipeline/video_input.h"
#include "acro/pose/pose_models.h"
#include "acro/reconstruct/view_fit.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/camera.h"
#include "acro/vision/image_flights.h"

namespace acro::pipeline {

struct MonocularRequest {
  /// The camera's video; or `detections` made elsewhere.
  std::filesystem::path video;
  /// One camera's 2D keypoints made elsewhere (a folder of OpenPose JSON, a CSV or a Sports2D
  /// TRC: capture::ReadDetections) at `rate_hz`, with `bed_line` (no picture to find the bed in).
  std::filesystem::path detections;
  std::string keypoint_set = "body25b";
  double rate_hz = 0;
  /// The bed's rest line in the picture; empty: found in the video's first frame.
  std::optional<vision::BedLine> bed_line;
  std::filesystem::path calibration;
  /// Its camera in the calibration; empty: the only one, or the one the video's name starts with.
  std::string camera;
  /// The camera from the video alone, instead of `calibration`: its pose from the bed found in
  /// the first frame (a FIG bed, vision::CalibrateFromBed), its intrinsics from `intrinsics` (a
  /// checkerboard's calibration, `camera` naming one of its cameras) or, with none, its focal
  /// length from the bed's perspective too (vision::CalibrateFromBedUnknownFocal). The world is
  /// then the bed's: its centre at the origin, its long axis x, Z up.
  bool detect_bed = false;
  std::filesystem::path intrinsics;
  /// With `detect_bed`: the bed found in this picture (or this video's first frame) of the same
  /// camera, the same size — a still of the empty trampoline — instead of the video's first frame
  /// (where an athlete may stand on it).
  std::filesystem::path bed_picture;
  pose::LandmarkModel model = pose::LandmarkModel::kHeavy;
  vision::ImageFlightOptions flights;
  AthleteChoice athlete;
  int min_frames = 2;
  std::string use = "the analysis";
};

struct MonocularInput {
  /// The keypoints on the athlete's plane as a trial (path: the video; sha256 over the
  /// calibration's and the video's bytes), upright, with the athlete.
  TrialInput input;
  vision::Camera camera;  ///< as fitted to the video's size
  /// The camera's keypoints, posed in the trial's world (ReconstructionOptions::views).
  std::shared_ptr<const analysis::ViewsToFit> views;
  vision::ImageFlights flights;  ///< from the picture (image_flights.h)
  /// The athlete's distance along the camera's axis (m): the median over the complete flights of
  /// g·f / (the centre of mass's acceleration in the picture); with the bed located
  /// (`detect_bed`), the bed's middle line's (`bed_depth_m`), gravity's then in gravity_depth_m.
  double depth_m = 0.0;
  double gravity_depth_m = 0.0;
  std::vector<double> depth_per_flight_m;
  /// The bed's surface at rest (m, the trial's Z): the picture's rest line under the landings met
  /// with the athlete's plane — the surface the analysis times the flights against
  /// (TrialAnalysisOptions::surface_height_m).
  double bed_height_m = 0.0;
  /// How the camera was had: "the calibration C.toml, camera side", or from the bed with the
  /// focal length found and how well the picture tells it.
  std::string camera_source;
  /// With `detect_bed`: the focal length's search (focal_px 0 when the intrinsics were given),
  /// and the athlete's distance the bed tells (the camera's to the bed's long middle line, along
  /// its axis), beside the one gravity tells.
  std::optional<vision::BedFocalCalibration> bed_focal;
  double bed_depth_m = 0.0;
  /// The camera's own warnings (a focal length the bed tells poorly), also in input.warnings.
  std::vector<std::string> camera_warnings;
  std::string Report() const;
};

/// Throws acro::InputError naming the file or option at fault: no bed in the first frame with
/// `detect_bed` (or detections, which have no picture), a camera not in the calibration, a
/// calibration whose world is not Z up (gravity is −Z), no bed in the first frame (or, from
/// detections, no bed line or no rate given), no complete flight to weigh the depth with.
/// `progress` as acro::Progress ("detect").
MonocularInput OpenMonocular(const MonocularRequest& request, const Progress& progress = {});

/// What an analysis of one camera takes from it, the same for every door (`analyze`, the studio):
/// the views the model is fitted to, the bed's surface at rest (unless the options already hold a
/// bed or a surface), the flights the picture's soles timed (given, and fitted as free flights),
/// and — the camera posed on the bed (`request.detect_bed`) and no bed in the options — that FIG
/// bed, centred at the origin along x.
void UseOneCamera(const MonocularInput& mono,
                  const MonocularRequest& request,
                  analysis::TrialAnalysisOptions* options);

/// The one camera's video as the analysis attaches it (silhouettes, overlay): on its own time line
/// (the trial's clock is the video's), with the camera fitted to it. Empty for detections made
/// elsewhere, which have no video.
std::optional<VideoRequest> OneCameraVideo(const MonocularInput& mono,
                                           const MonocularRequest& request);

}  // namespace acro::pipeline
