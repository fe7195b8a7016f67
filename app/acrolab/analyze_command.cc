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
#include "acro/library/add_trial.h"
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
};

int RunAnalyze(AnalyzeArguments& args) {
  const TrialArguments& common = args.common;
  analysis::TrialAnalysisOptions& options = args.options;
  ui::AnalysisReportOptions& report = args.report;
  const bool images = args.images;
  const bool quiet = common.quiet;
  DemandValidCommandLine(options);
  CheckOutputDirectory(common.out_dir);  // before any work: a bad -o costs nothing

  // Inputs: trial, static trial, athlete.
  auto say = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  const auto [trial, static_trial] = common.ReadTrials("analyze");
  CheckCutoffBelowNyquist(options.reconstruction, trial);
  const analysis::AthleteBody body = common.MakeBody("analyze", &report.athlete);

  // The plotted joint must exist before any work is done (and before any file is written).
  {
    const std::vector<std::string> names =
        analysis::MakeCoordinateNames(analysis::MakeStandardHumanModel(body));
    if (std::find(names.begin() + dynamics::kRootNq, names.end(), report.joint) == names.end())
      throw UsageError{"--joint: '" + report.joint +
                       "' is not a joint angle (e.g. r_hip_flexion, l_knee_flexion, "
                       "lumbar_flexion; docs/reconstruction.md)"};
  }

  // The analysis, with one progress line per step and the IK's frames.
  options.progress = say;
  if (!quiet) options.reconstruction.progress = MakeFrameProgress();
  // The video and its camera before the work: a mistyped name costs nothing.
  std::optional<vision::Camera> camera_found;
  if (!args.video.video.empty() || !args.video.calibration.empty())
    camera_found = args.video.FindCamera();
  analysis::TrialAnalysis result =
      analysis::AnalyzeTrial(trial, static_trial ? &*static_trial : nullptr, body, options);
  for (const std::string& w : result.warnings)
    std::fprintf(stderr, "acrolab analyze: warning: %s\n", w.c_str());

  // Outputs: the video's (silhouettes, overlay), the tables, then the report (with plots when
  // rendering works here).
  // Written into a staging directory and moved into place when all are complete.
  OutputTransaction outputs(common.out_dir);
  const std::filesystem::path& dir = outputs.staging();
  if (camera_found) {
    const vision::Camera& camera = *camera_found;
    analysis::TrialScene scene(trial, result, body, analysis::MakeEllipsoidBodyMesh(body));
    vision::VideoSync sync;
    if (args.video.sync == "auto") {
      // From the image motion, then refined by the silhouettes to the trial's sample.
      vision::AutoSyncOptions motion;
      motion.rate = args.video.rate;
      motion.progress = MakeCancellableProgress("sync (image motion)", "frames");
      analysis::SilhouetteCheckOptions refine;
      refine.progress = MakeCancellableProgress("sync (silhouettes)", "frames");
      const analysis::AutoVideoSync found =
          analysis::SyncVideoAutomatically(scene, camera, args.video.video, motion, refine);
      say(fmt::format(
          "sync: video time = {:.4f} s + trial time (from the image motion: 1 − correlation "
          "{:.3f}, runner-up {:.3f})",
          found.motion.sync.offset_s,
          found.motion.cost,
          found.motion.runner_up_cost));
      sync = found.refined.sync;
      say(
          fmt::format("sync: video time = {:.4f} s + trial time (refined by the silhouettes, "
                      "median IoU {:.3f})",
                      sync.offset_s,
                      found.refined.median_iou));
    } else {
      sync = args.video.Sync(trial, camera, say);
    }
    // The silhouettes with the body's full mesh (what the video shows), the overlay with the
    // lighter one (drawn at video rate).
    {
      capture::VideoReader colour(args.video.video);
      analysis::SilhouetteCheckOptions check;
      check.sync = sync;
      check.progress = MakeCancellableProgress("silhouettes", "frames");
      const analysis::SilhouetteCheck silhouettes =
          analysis::CheckSilhouettes(colour, scene, camera, check);
      analysis::AttachSilhouetteCheck(silhouettes, &result);
      for (size_t k = 0; k < silhouettes.iou.size(); ++k) {
        report.silhouette_time_s.push_back(silhouettes.samples[k] / trial.point_rate_hz);
        report.silhouette_iou.push_back(silhouettes.iou[k]);
      }
      say(fmt::format("silhouettes: median IoU {:.3f} over {} flight frames",
                      silhouettes.median_iou,
                      silhouettes.iou.size()));
    }
#ifdef ACRO_HAVE_VIEWS
    std::optional<ui::XDisplay> display;
    try {
      display.emplace();
    } catch (const InputError& e) {
      say(std::string("overlay: not written: ") + e.what());
    }
    if (display) {
      analysis::TrialScene light(
          trial,
          result,
          body,
          analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()));
      capture::VideoReader video(args.video.video);
      capture::VideoReader frames(args.video.video);
      const vision::BackgroundModel background(frames);
      ui::SceneOverlayOptions overlay;
      overlay.show = analysis::ParseSceneShow("mesh,skeleton,com,mismatch");
      overlay.background = &background;
      overlay.sync = sync;
      overlay.progress = MakeCancellableProgress("overlay", "frames");
      ui::WriteSceneOverlay(video, light, camera, dir / "overlay.mp4", overlay);
      report.overlay_video = "overlay.mp4";
    }
#else
    say("overlay: not written (this acrolab was built without the 3D views, VTK)");
#endif
  }
#ifdef ACRO_HAVE_VIEWS
  // A filmstrip per complete jump, when the 3D views can render here (they are extras: without a
  // display or Xvfb the report says why and goes on).
  if (images) {
    try {
      const ui::XDisplay display;
      analysis::AthleteScene athlete(
          body,
          analysis::MakeEllipsoidBodyMesh(body, analysis::OverlayBodyMeshOptions()),
          result.reconstruction.motion,
          result.reconstruction.model);
      for (const analysis::JumpMetrics& j : result.jumps) {
        if (j.partial()) continue;
        const std::vector<int> frames =
            ui::EvenlySpacedFrames(j.flight.takeoff_frame, j.flight.landing_frame - 1, 8);
        const std::vector<std::uint8_t> rgb =
            ui::RenderFilmstrip(athlete, frames, analysis::FindTakeoff(result, j.index).heading_W);
        const ui::FilmstripOptions size;
        const std::vector<std::uint8_t> png = capture::EncodeRgbPng(size.width, size.height, rgb);
        const std::string file = fmt::format("filmstrip_jump_{}.png", j.index);
        WriteFileAtomically(dir / file, std::string(png.begin(), png.end()));
        report.filmstrips.emplace_back(j.index, file);
        if (!args.video.video.empty()) {
          // With a video, the strip as a video too (it fills in as the flight goes).
          const std::string mp4 = fmt::format("filmstrip_jump_{}.mp4", j.index);
          ui::FilmstripRow row;
          row.scene = &athlete;
          row.frames = frames;
          row.rate_hz = result.reconstruction.motion.rate_hz;
          ui::FilmstripVideoOptions video;
          video.progress = MakeCancellableProgress(mp4, "frames");
          ui::WriteFilmstripVideo(
              {row}, analysis::FindTakeoff(result, j.index).heading_W, dir / mp4, size, video);
          report.filmstrip_videos.emplace_back(j.index, mp4);
        }
      }
    } catch (const InputError& e) {
      report.filmstrips.clear();
      report.filmstrip_videos.clear();
      report.filmstrip_note = std::string("no filmstrips: ") + e.what();
      say(report.filmstrip_note);
    }
  }
#endif
  analysis::WriteAnalysisTables(result, dir);
  // Which Acrolab analysed which content (for acrolab library add --analysis).
  WriteFileAtomically(dir / "analysis.json",
                      library::FormatAnalysisProvenance(common.trial_path, report.athlete));
  report.trial_path = common.trial_path;
  report.render_images = images;
  say("report: rendering plots");
  const ui::AnalysisReportOutcome outcome = ui::WriteAnalysisReport(result, dir, report);
  if (!outcome.images_rendered) say("report: no plots: " + outcome.reason);
  outputs.Commit();
  std::fputs(result.BriefReport().c_str(), stdout);
  std::printf("report: %s\n", (outputs.dir() / "report.html").string().c_str());
  std::printf(
      "wrote %s/{report.html,jumps.json,angles.mot,torques.sto,residuals.csv,analysis.json}\n",
      common.out_dir.c_str());
  return 0;
}

}  // namespace

void AddAnalyzeCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<AnalyzeArguments>();
  CLI::App* command = app.add_subcommand(
      "analyze",
      "The main job: import, reconstruct, check the physics, measure every jump. Writes "
      "DIR/report.html (routine summary, per-jump table, verdict with its cause, charts as PNG and "
      "SVG), DIR/jumps.json, DIR/angles.mot, DIR/torques.sto, DIR/residuals.csv. docs/cli.md.");
  args->common.Declare(command, &args->options.reconstruction);
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
  command->add_flag_callback(
      "--no-force-plates",
      [args] { args->options.use_force_plates = false; },
      "phases from the body's centre of mass even when plates exist");
  command->add_flag_callback(
      "--no-images", [args] { args->images = false; }, "the report without charts");
  args->video.Declare(command, false);
  command->callback([args, run] { *run = [args] { return RunAnalyze(*args); }; });
}

}  // namespace acro::app
