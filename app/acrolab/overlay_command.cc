// `acrolab overlay`: the trial — measured points, or the reconstructed athlete — drawn over a
// calibrated camera's video by the 3D views (ui/views). Built only with the views (VTK,
// ACRO_HAVE_VIEWS); without them the command says how to get them.

#include <cstdio>
#include <memory>
#include <optional>

#include "acro/base/file_io.h"
#include "acro/capture/detections.h"
#include "acro/pose/keypoints.h"
#include "acro/report/pose_sheet.h"
#include "commands.h"

#ifdef ACRO_HAVE_VIEWS
#include "acro/assess/trial_analysis.h"
#include "acro/athlete/body_mesh.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/pipeline/steps.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/scene_overlay.h"
#include "acro/vision/projection.h"
#include "acro/vision/silhouette.h"
#include "acro/vision/sync.h"
#endif

namespace acro::app {

namespace {

struct OverlayArguments {
  TrialArguments common;  // TRIAL, --athlete; -o is the output file here
  VideoArguments video;
  std::string axes = "xyz", show, frames, ghost, detections, keypoints = "body25b";
  int slow = 1, ghost_jump = 0;
  bool heads_up = true;
};

// "A:B" → [A, B]; "A:" → [A, end].
std::pair<int, int> ParseFrames(const std::string& text) {
  if (text.empty()) return {0, -1};
  int a = 0, b = -1;
  char end = 0;
  const int n = std::sscanf(text.c_str(), "%d:%d%c", &a, &b, &end);
  const bool open_end = text.back() == ':' && std::sscanf(text.c_str(), "%d:%c", &a, &end) == 1;
  if (!(n == 2 || open_end) || a < 0 || (n == 2 && b < a))
    throw UsageError{"--frames '" + text +
                     "' is not FIRST:LAST (video frames, 0-based, e.g. 120:480)"};
  return {a, open_end ? -1 : b};
}

// --detections: 2D keypoints (acrolab detect's folder, OpenPose JSON, a 2D TRC or CSV) drawn over
// the video itself — no trial, no calibration, no 3D views.
int RunDetectionOverlay(const OverlayArguments& args) {
  if (!args.common.trial_path.empty() || !args.video.calibration.empty())
    throw UsageError{"--detections draws 2D keypoints over --video alone: no TRIAL and no --calib"};
  if (args.video.video.empty()) throw UsageError{"--detections needs --video"};
  CheckVideoOutput(args.common.out_dir, /*mp4_only=*/true);
  const std::filesystem::path out(args.common.out_dir);
  // acrolab detect's folder for one video: its json/ inside.
  std::filesystem::path source = args.detections;
  if (IsDirectory(source / "json")) source /= "json";
  const capture::KeypointDetections detections = capture::ReadDetections(source, args.keypoints);
  capture::VideoReader video(args.video.video);
  const pose::Skeleton skeleton = pose::SkeletonOfNames(detections.names);
  const auto [first, last] = ParseFrames(args.frames);
  Progress progress;
  progress.report = [bar = MakeCancellableProgress("overlay", "frames")](
                        const std::string&, int done, int total) { return bar(done, total); };
  const int frames = ui::WriteDetectionOverlay(
      video, detections.frames, skeleton.edges, skeleton.sides, out, progress, 0.2, first, last);
  std::printf("%d frames with the detections of %s -> %s\n",
              frames,
              args.detections.c_str(),
              out.string().c_str());
  return 0;
}

#ifdef ACRO_HAVE_VIEWS
int RunOverlay(const OverlayArguments& args) {
  if (args.slow < 1 || args.slow > 64) throw UsageError{"--slow must be between 1 and 64"};
  const auto [first, last] = ParseFrames(args.frames);
  const bool athlete = !args.common.athlete_path.empty();
  if ((args.ghost_jump != 0 || !args.ghost.empty()) && !athlete)
    throw UsageError{"--ghost and --ghost-jump need --athlete (the analysed jumps)"};
  if (args.ghost_jump != 0 && !args.ghost.empty())
    throw UsageError{"--ghost and --ghost-jump: one ghost at a time"};
  analysis::SceneShow show;
  try {
    show = analysis::ParseSceneShow(
        !args.show.empty() ? args.show : (athlete ? "mesh,skeleton,com" : "skeleton,markers"));
  } catch (const InputError& e) {
    throw UsageError{e.what()};  // a bad option value: exit 2
  }
  if (show.mismatch && !athlete)
    throw UsageError{"--show mismatch needs --athlete (the athlete's silhouette to compare)"};
  CheckVideoOutput(args.common.out_dir);  // before any work: a bad -o costs nothing

  // The trial upright with its athlete, the video opened once (the pipeline, as every door).
  const bool auto_sync = args.video.sync == "auto";
  const pipeline::TrialInput input =
      OpenTrialFor("overlay", args.common.Request(), athlete || auto_sync);
  pipeline::VideoInput video = OpenVideoFor(args.video);
  const analysis::AthleteBody& body = input.athlete.body;

  std::optional<analysis::TrialAnalysis> result;
  std::optional<analysis::TrialScene> scene;
  if (athlete || auto_sync) {
    // The analysis: drawn with --athlete; --sync auto refines the sync by the athlete's
    // silhouettes (the default body's when no profile is given).
    analysis::TrialAnalysisOptions options;
    options.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    result = pipeline::Analyze(input, options);
  }
  if (athlete) {
    scene.emplace(input.trial,
                  *result,
                  body,
                  analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()));
    if (args.ghost_jump > 0) scene->SetGhostJump(args.ghost_jump);
    if (!args.ghost.empty()) {
      const analysis::SkillGhost design =
          analysis::ReadSkillGhost(args.ghost, analysis::MakeStandardHumanModel(body));
      if (input.athlete.name.rfind(design.athlete + ",", 0) != 0)
        std::fprintf(stderr,
                     "overlay: warning: the design was made for %s, drawn here on %s\n",
                     design.athlete.c_str(),
                     input.athlete.name.c_str());
      scene->SetGhostDesign(design, body);
    }
  } else {
    scene.emplace(input.trial, vision::ParseAxisMapping(args.axes));
  }
  vision::VideoSync sync;
  if (auto_sync) {
    analysis::TrialScene full(input.trial, *result, body, analysis::MakeEllipsoidBodyMesh(body));
    const pipeline::SyncOutcome& found = video.Sync(full, MakeStepProgress(false));
    for (const std::string& line : found.lines) std::fprintf(stderr, "%s\n", line.c_str());
    sync = found.sync;
  } else {
    sync = video.Sync(*scene).sync;
  }

  ui::SceneOverlayOptions options;
  if (show.mismatch) {
    std::fprintf(stderr, "overlay: the video's background (for the silhouettes)\n");
    options.background = &video.Background();
  }
  options.show = show;
  options.sync = sync;
  options.first_frame = first;
  options.last_frame = last;
  options.slow = args.slow;
  options.heads_up = args.heads_up;
  options.progress = MakeCancellableProgress("overlay", "frames");
  const ui::OverlayTiming t =
      ui::WriteSceneOverlay(video.reader(), *scene, video.camera(), args.common.out_dir, options);
  std::printf(
      "wrote %s (%d frames; decode %.1f s, scene %.1f s, render %.1f s, composite %.1f s, "
      "encode %.1f s)\n",
      args.common.out_dir.c_str(),
      t.frames_written,
      t.decode_s,
      t.scene_s,
      t.render_s,
      t.composite_s,
      t.encode_s);
  return 0;
}
#endif

}  // namespace

void AddOverlayCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<OverlayArguments>();
  CLI::App* command = app.add_subcommand(
      "overlay",
      "Draws the trial over a calibrated camera's video with the 3D views: the measured markers "
      "or keypoints as a skeleton, or with --athlete the reconstructed athlete (mesh, skeleton, "
      "centre of mass, residual force) and a heads-up line per frame. docs/overlay.md.");
  command->add_option("TRIAL", args->common.trial_path, "markers or keypoints: C3D, TRC or CSV");
  args->video.Declare(command, false);
  command->add_option("--detections",
                      args->detections,
                      "instead of TRIAL: 2D keypoints drawn over --video (acrolab detect's folder, "
                      "OpenPose JSON per frame, a 2D TRC or CSV; docs/pose.md)");
  command->add_option(
      "--keypoints", args->keypoints, "with --detections: the JSON files' keypoint set (body25b)");
  command->add_option("--athlete",
                      args->common.athlete_path,
                      "athlete profile: reconstruct and analyse the trial, draw the athlete");
  command->add_option("--axes", args->axes, "without --athlete: the trial's axes (zxy: Y-up TRC)");
  command->add_option("--show",
                      args->show,
                      "mesh,skeleton,markers,com,residual,mismatch (default: mesh,skeleton,com "
                      "with --athlete, skeleton,markers without; mismatch: where the filmed and "
                      "the modelled silhouettes differ, red and yellow, with their IoU)");
  command->add_option("--ghost",
                      args->ghost,
                      "with --athlete: a designed skill (acrolab optimize's output folder: "
                      "result.json, motion.mot) drawn as an orange ghost in every flight, placed "
                      "at its take-off (feet, heading, time)");
  command->add_option("--ghost-jump",
                      args->ghost_jump,
                      "with --athlete: jump N (as in jumps.json) drawn as an orange ghost in every "
                      "other flight, placed at its take-off (feet, heading, time)");
  command->add_option("--frames", args->frames, "FIRST:LAST video frames only (0-based)")
      ->check(kNotEmpty);
  command->add_option("--slow", args->slow, "write each flight frame K times (slow motion)");
  command->add_flag_callback(
      "--no-hud", [args] { args->heads_up = false; }, "no heads-up line");
  command->add_option("-o,--output", args->common.out_dir, "OUT.mp4 or a directory of PNG frames")
      ->required();
  command->callback([args, run] {
    if (!args->detections.empty()) {
      *run = [args] { return RunDetectionOverlay(*args); };
      return;
    }
    if (args->common.trial_path.empty() || args->video.video.empty() ||
        args->video.calibration.empty())
      throw CLI::ValidationError("TRIAL, --video and --calib",
                                 "required (or --detections with --video)");
#ifdef ACRO_HAVE_VIEWS
    *run = [args] { return RunOverlay(*args); };
#else
    *run = NeedTheViews;
#endif
  });
}

}  // namespace acro::app
