#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/athlete/motion.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/dynamics/configuration.h"
#include "acro/fig/rules.h"
#include "acro/pipeline/monocular_input.h"
#include "acro/pipeline/steps.h"
#include "acro/pose/pose_models.h"
#include "acro/report/analysis_report.h"
#include "acro/scene/silhouette_check.h"
#include "acro/scene/trial_scene.h"
#include "acro/vision/camera.h"
#include "acro/vision/sync.h"
#ifdef ACRO_HAVE_VIEWS
#include "acro/base/file_io.h"
#include "acro/capture/frame_output.h"
#include "acro/scene/compare_scene.h"
#include "acro/views/display.h"
#include "acro/views/filmstrip.h"
#include "acro/views/scene_overlay.h"
#endif
#include "commands.h"

namespace acro::app {

namespace {

struct AnalyzeArguments {
  TrialArguments common;
  bool images = true;
  // A calibrated video of the trial: silhouettes (and, with the 3D views, the overlay).
  VideoArguments video;
  analysis::TrialAnalysisOptions options;
  ui::AnalysisReportOptions report;
  std::string rules;  // a rule file (rules/*.yaml); empty: the FIG senior routine
  // One camera's detections made elsewhere (docs/one-camera.md), instead of TRIAL or a video.
  std::string detections, keypoints = "body25b", bed_line;
  double fps = 0;
  // One video with no calibration: the camera from the bed in its first frame (docs/one-camera.md,
  // "The camera from the video alone"), the intrinsics from a checkerboard's file if given.
  bool detect_bed = false;
  std::string intrinsics, bed_picture;
  // Videos without a trial: the detector (lite, full or heavy); the jumps' filmstrip videos.
  std::string model = "heavy";
  bool filmstrip_videos = true;
};

// The plotted joint must exist before any work is done (and before any file is written).
void CheckJoint(const analysis::AthleteBody& body, const std::string& joint) {
  const std::vector<std::string> names =
      analysis::MakeCoordinateNames(analysis::MakeStandardHumanModel(body));
  if (std::find(names.begin() + dynamics::kRootNq, names.end(), joint) == names.end())
    throw UsageError{"--joint: '" + joint +
                     "' is not a joint angle (e.g. r_hip_flexion, l_knee_flexion, lumbar_flexion; "
                     "docs/reconstruction.md)"};
}

// The video's share: the sync and the silhouettes (the pipeline), then the overlay (the views).
void AnalyzeVideo(pipeline::VideoInput& video,
                  const pipeline::TrialInput& input,
                  analysis::TrialAnalysis* result,
                  const std::filesystem::path& dir,
                  ui::AnalysisReportOptions* report,
                  bool quiet) {
  auto say = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  const pipeline::VideoCheck check =
      pipeline::AttachVideo(video, input, result, MakeStepProgress(quiet));
  for (const std::string& line : check.sync.lines) say(line);
  for (size_t k = 0; k < check.silhouettes.iou.size(); ++k) {
    report->silhouette_time_s.push_back(check.silhouettes.samples[k] / input.trial.point_rate_hz);
    report->silhouette_iou.push_back(check.silhouettes.iou[k]);
  }
  say(fmt::format("silhouettes: median IoU {:.3f} over {} flight frames",
                  check.silhouettes.median_iou,
                  check.silhouettes.iou.size()));
#ifdef ACRO_HAVE_VIEWS
  std::optional<ui::XDisplay> display;
  try {
    display.emplace();
  } catch (const InputError& e) {
    say(std::string("overlay: not written: ") + e.what());
    return;
  }
  // The overlay with the lighter mesh (drawn at video rate), the mismatch from the shared
  // background, on the one reader.
  analysis::TrialScene light(
      input.trial,
      *result,
      input.athlete.body,
      analysis::MakeEllipsoidBodyMesh(input.athlete.body, analysis::OverlayBodyMeshOptions()));
  ui::SceneOverlayOptions overlay;
  overlay.show = analysis::ParseSceneShow("mesh,skeleton,com,mismatch");
  overlay.background = &video.Background();
  overlay.sync = check.sync.sync;
  overlay.progress = MakeCancellableProgress("overlay", "frames");
  ui::WriteSceneOverlay(video.reader(), light, video.camera(), dir / "overlay.mp4", overlay);
  report->overlay_video = "overlay.mp4";
#else
  say("overlay: not written (this acrolab was built without the 3D views, VTK)");
#endif
}

// A filmstrip per complete jump, when the 3D views can render here (they are extras: without a
// display or Xvfb the report says why and goes on).
void AnalyzeFilmstrips(const pipeline::TrialInput& input,
                       const analysis::TrialAnalysis& result,
                       const std::filesystem::path& dir,
                       bool videos,
                       ui::AnalysisReportOptions* report) {
#ifdef ACRO_HAVE_VIEWS
  try {
    const ui::XDisplay display;
    analysis::AthleteScene athlete(
        input.athlete.body,
        analysis::MakeEllipsoidBodyMesh(input.athlete.body, analysis::OverlayBodyMeshOptions()),
        result.reconstruction.motion,
        result.reconstruction.model);
    const ui::JumpFilmstrips strips = ui::WriteJumpFilmstrips(
        athlete, result, dir, videos, MakeCancellableProgress("filmstrip", "frames"));
    report->filmstrips = strips.pictures;
    report->filmstrip_videos = strips.videos;
  } catch (const InputError& e) {
    report->filmstrips.clear();
    report->filmstrip_videos.clear();
    report->filmstrip_note = std::string("no filmstrips: ") + e.what();
    std::fprintf(stderr, "%s\n", report->filmstrip_note.c_str());
  }
#else
  (void)input, (void)result, (void)dir, (void)videos, (void)report;
#endif
}

// The options a video without TRIAL cannot take.
void CheckVideosWithoutTrial(const VideoArguments& v,
                             const TrialArguments& common,
                             bool detect_bed = false) {
  if (v.calibration.empty() && !detect_bed)
    throw UsageError{
        "--video without TRIAL needs --calib (the cameras) or, for one video, --detect-bed; "
        "`acrolab video flights VIDEO -o DIR` times one video's flights with neither"};
  if (!v.sync.empty() || !v.event.empty() || v.offset_s != 0.0 || v.rate != 1.0)
    throw UsageError{
        "--sync, --event, --offset-s and --rate set one video's sync against a trial: without "
        "TRIAL the video is the time line"};
  if (!common.static_path.empty()) throw UsageError{"--static goes with TRIAL"};
}

// One calibrated camera as the pipeline opens it (docs/one-camera.md): its video, or its
// detections made elsewhere (with their rate and the bed's line: no picture to find it in).
pipeline::MonocularInput OpenOneCameraFor(const AnalyzeArguments& args,
                                          const TrialArguments& common,
                                          pipeline::MonocularRequest* opened) {
  const VideoArguments& v = args.video;
  pipeline::MonocularRequest& request = *opened;
  if (!args.detections.empty()) {
    if (!v.video.empty())
      throw UsageError{"give --detections or --video, not both: the detections are of one camera"};
    if (v.calibration.empty()) throw UsageError{"--detections needs --calib (its camera)"};
    if (!(args.fps > 0)) throw UsageError{"--detections needs --fps (their frame rate, Hz)"};
    if (args.bed_line.empty())
      throw UsageError{
          "--detections needs --bed-line Y0,SLOPE: the bed's rest line in their picture (px), "
          "with no video to find the bed in"};
    request.detections = args.detections;
    request.keypoint_set = args.keypoints;
    request.rate_hz = args.fps;
    request.bed_line = ParseBedLine(args.bed_line);
  } else {
    request.video = v.video;
    if (!args.bed_line.empty()) request.bed_line = ParseBedLine(args.bed_line);
  }
  if (args.detect_bed) {
    if (!args.detections.empty())
      throw UsageError{"--detect-bed finds the bed in a video: detections have no picture"};
    if (!v.calibration.empty())
      throw UsageError{
          "give --calib or --detect-bed, not both (with intrinsics from a checkerboard: "
          "--detect-bed --intrinsics C)"};
    if (!args.bed_line.empty())
      throw UsageError{"--detect-bed finds the bed's line itself: --bed-line goes without it"};
  } else if (!args.intrinsics.empty()) {
    throw UsageError{"--intrinsics goes with --detect-bed (with --calib, the camera is known)"};
  } else if (!args.bed_picture.empty()) {
    throw UsageError{"--bed-picture goes with --detect-bed"};
  }
  CheckVideosWithoutTrial(v, common, args.detect_bed);
  request.calibration = v.calibration;
  request.camera = v.camera;
  request.detect_bed = args.detect_bed;
  request.intrinsics = args.intrinsics;
  request.bed_picture = args.bed_picture;
  request.model = pose::ParseLandmarkModel(args.model);
  request.athlete = common.Request().athlete;
  pipeline::MonocularInput mono = pipeline::OpenMonocular(request, MakeStepProgress(common.quiet));
  if (!common.quiet) std::fputs(mono.Report().c_str(), stderr);
  std::vector<std::string> lines = mono.input.warnings;  // the flights' (a jump out of the picture)
  if (!mono.input.athlete.warning.empty()) lines.push_back(mono.input.athlete.warning);
  for (const std::string& w : lines)
    std::fprintf(stderr, "acrolab analyze: warning: %s\n", w.c_str());
  return mono;
}

// Several cameras' videos as the pipeline opens them: each video named after its camera (or
// CAM=PATH), the sync found from the detections.
pipeline::ViewsInput OpenVideosFor(const AnalyzeArguments& args, const TrialArguments& common) {
  const VideoArguments& v = args.video;
  CheckVideosWithoutTrial(v, common);
  if (!v.camera.empty())
    throw UsageError{"--camera names one video's camera: several videos are named after theirs"};
  const std::vector<vision::Camera> cameras = vision::ReadCameras(v.calibration);
  pipeline::ViewsRequest request;
  std::vector<std::string> all = {v.video};
  all.insert(all.end(), v.more_videos.begin(), v.more_videos.end());
  for (const std::string& path : all)
    request.cameras.push_back(pipeline::VideoSource(path, cameras, v.calibration));
  request.calibration = v.calibration;
  request.up = common.up;
  request.model = pose::ParseLandmarkModel(args.model);
  request.athlete = common.Request().athlete;
  request.use = "the analysis";
  return OpenViewsFor("analyze", request, common.quiet);
}

int RunAnalyze(AnalyzeArguments& args) {
  const TrialArguments& common = args.common;
  DemandValidCommandLine(args.options);
  // The options of videos without a trial, refused where nothing would read them.
  const bool one_video =
      common.trial_path.empty() && args.video.more_videos.empty() && !args.video.video.empty();
  if (!args.bed_picture.empty() && !(one_video && args.detect_bed))
    throw UsageError{"--bed-picture goes with one video and --detect-bed"};
  if (args.model != "heavy" && !(common.trial_path.empty() && !args.video.video.empty()))
    throw UsageError{"--model chooses the detector of videos analysed without a trial"};
  CheckOutputDirectory(common.out_dir);  // before any work: a bad -o costs nothing
  if (!args.rules.empty()) args.options.rules = fig::LoadRules(args.rules);
  // The input: a trial, or several calibrated cameras' videos (docs/markerless.md) — the athlete
  // detected in each, the cameras synced and the keypoints triangulated by the pipeline.
  std::optional<pipeline::VideoInput> video;
  std::optional<pipeline::ViewsInput> views;
  std::optional<pipeline::MonocularInput> mono;
  pipeline::MonocularRequest mono_request;
  pipeline::TrialInput input;
  if (common.trial_path.empty()) {
    if (args.video.video.empty() && args.detections.empty())
      throw UsageError{
          "give TRIAL (markers or keypoints), calibrated videos (--video A [--video B …] "
          "--calib C), or one camera's detections (--detections DIR --calib C --fps HZ "
          "--bed-line Y0,SLOPE)"};
    if (!args.detections.empty() || args.video.more_videos.empty()) {
      mono = OpenOneCameraFor(args, common, &mono_request);
      input = std::move(mono->input);
      pipeline::UseOneCamera(*mono, mono_request, &args.options);
    } else {
      views = OpenVideosFor(args, common);
      const std::string bed = pipeline::UseViews(*views, &args.options);
      if (!common.quiet && !bed.empty()) std::fprintf(stderr, "%s\n", bed.c_str());
      // The first camera's video, on the time line the triangulation made.
      video.emplace(pipeline::FirstViewVideo(*views, args.video.calibration));
      input = std::move(views->input);
    }
  } else {
    if (!args.detections.empty())
      throw UsageError{"give TRIAL or --detections (one camera's keypoints), not both"};
    input = OpenTrialFor("analyze", common.Request());
  }
  CheckCutoffBelowNyquist(args.options.reconstruction, input.trial);
  CheckJoint(input.athlete.body, args.report.joint);
  // The video and its camera before the work: a mistyped name costs nothing.
  if (mono) {
    if (auto request = pipeline::OneCameraVideo(*mono, mono_request)) video.emplace(*request);
  } else if (!views && (!args.video.video.empty() || !args.video.calibration.empty())) {
    video.emplace(OpenVideoFor(args.video));
  }

  // The analysis, with one progress line per step and the IK's frames.
  if (!common.quiet) {
    args.options.progress = [](const std::string& line) {
      std::fprintf(stderr, "%s\n", line.c_str());
    };
    args.options.reconstruction.progress = MakeFrameProgress();
  }
  analysis::TrialAnalysis result = pipeline::Analyze(input, args.options);
  for (const std::string& w : result.warnings)
    std::fprintf(stderr, "acrolab analyze: warning: %s\n", w.c_str());
  pipeline::DemandAFlight(input, result);  // nothing written for a trial with no jump

  // Outputs, written into a staging directory and moved into place when all are complete.
  OutputTransaction outputs(common.out_dir);
  const std::filesystem::path& dir = outputs.staging();
  ui::AnalysisReportOptions& report = args.report;
  report.athlete = input.athlete.name;
  if (video) AnalyzeVideo(*video, input, &result, dir, &report, common.quiet);
  if (args.images)
    AnalyzeFilmstrips(input, result, dir, video.has_value() && args.filmstrip_videos, &report);
  analysis::WriteAnalysisTables(result, dir);
  // Which Acrolab analysed which content (for acrolab library add --analysis).
  WriteFileAtomically(dir / "analysis.json", pipeline::FormatAnalysisProvenance(input));
  report.trial_path = views || mono ? input.trial.source.path : common.trial_path;
  report.render_images = args.images;
  if (!common.quiet) std::fprintf(stderr, "report: rendering plots\n");
  const ui::AnalysisReportOutcome outcome = ui::WriteAnalysisReport(result, dir, report);
  if (!outcome.images_rendered && !common.quiet)
    std::fprintf(stderr, "report: no plots: %s\n", outcome.reason.c_str());
  outputs.Commit();
  std::fputs(result.BriefReport().c_str(), stdout);
  std::printf("report: %s\n", (outputs.dir() / "report.html").string().c_str());
  std::printf(
      "wrote "
      "%s/{report.html,jumps.json,score.json,angles.mot,torques.sto,residuals.csv,analysis.json}\n",
      common.out_dir.c_str());
  return 0;
}

}  // namespace

void AddAnalyzeCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<AnalyzeArguments>();
  CLI::App* command = app.add_subcommand(
      "analyze",
      "The main job: import (or, with no TRIAL, several calibrated cameras' videos: --video A "
      "--video B … --calib C — the athlete detected, the cameras synced, the keypoints "
      "triangulated; docs/markerless.md), reconstruct, check the physics, measure every jump. "
      "Writes "
      "DIR/report.html (routine summary, per-jump table, verdict with its cause, charts as PNG and "
      "SVG, the score sheet), DIR/jumps.json, DIR/score.json, DIR/angles.mot, DIR/torques.sto, "
      "DIR/residuals.csv. docs/cli.md.");
  args->common.Declare(command, &args->options.reconstruction, /*trial_required=*/false);
  command->add_option("--joint",
                      args->report.joint,
                      "the joint whose angle and torque the report plots (default r_hip_flexion)");
  command->add_option_function<std::string>(
      "--bed",
      [args](const std::string& text) {
        analysis::BedGeometry bed;
        bed.centre_W = ParseCommaNumbers("--bed", text, 3, "X,Y,Z");
        bed.source = "option --bed";
        args->options.bed = bed;
      },
      "X,Y,Z: centre of the trampoline bed (m), when the trial has no BED markers");
  command->add_option(
      "--surface-height",
      args->options.surface_height_m,
      "height of the take-off surface (m) when the trial has no BED markers: "
      "1.155 for a FIG trampoline over a floor at z = 0; the phases then come "
      "from the soles (default: the bed or floor estimated from the motion, docs/metrics.md)");
  command
      ->add_option(
          "--rules",
          args->rules,
          "the routine rules the score sheet follows (rules/*.yaml: FIG senior, age groups, a "
          "league; default the FIG senior routine; docs/scoring.md)")
      ->check(CLI::ExistingFile);
  command->add_flag_callback(
      "--no-force-plates",
      [args] { args->options.use_force_plates = false; },
      "phases from the body's centre of mass even when plates exist");
  command->add_flag_callback(
      "--no-images", [args] { args->images = false; }, "the report without charts");
  command->add_flag_callback(
      "--no-filmstrip-videos",
      [args] { args->filmstrip_videos = false; },
      "with a video: each jump's filmstrip as a picture only, not also as a video");
  command
      ->add_option("--model",
                   args->model,
                   "videos without TRIAL: the detector, lite, full or heavy (default heavy, the "
                   "most accurate; full is about 3× faster, docs/pose.md)")
      ->check(CLI::IsMember({"lite", "full", "heavy"}));
  args->video.Declare(command, false);
  command->add_option("--detections",
                      args->detections,
                      "instead of TRIAL or a video: one camera's 2D keypoints made elsewhere (a "
                      "folder of OpenPose JSON, a CSV or a Sports2D TRC), with --calib, --fps and "
                      "--bed-line (docs/one-camera.md)");
  command->add_option("--keypoints",
                      args->keypoints,
                      "with --detections: the JSON files' keypoint set (default body25b)");
  command->add_option("--fps", args->fps, "with --detections: their frame rate (Hz)")
      ->check(CLI::PositiveNumber);
  command->add_flag("--detect-bed",
                    args->detect_bed,
                    "one video with no --calib: the camera's pose (and, without --intrinsics, its "
                    "focal length) from the trampoline's bed in the first frame, a FIG bed "
                    "(docs/one-camera.md)");
  command->add_option("--intrinsics",
                      args->intrinsics,
                      "with --detect-bed: the camera's intrinsics from a checkerboard "
                      "(acrolab calibrate intrinsics), --camera naming it in a file of several");
  command
      ->add_option("--bed-picture",
                   args->bed_picture,
                   "with --detect-bed: find the bed in this picture (or video) of the same camera "
                   "instead of the video's first frame — a still of the empty trampoline")
      ->check(CLI::ExistingFile);
  command->add_option("--bed-line",
                      args->bed_line,
                      "with --detections (or one video whose first frame does not show the bed): "
                      "Y0,SLOPE, the bed's rest line in the picture, y = Y0 + SLOPE·x (px)");
  command->callback([args, run] { *run = [args] { return RunAnalyze(*args); }; });
}

}  // namespace acro::app
