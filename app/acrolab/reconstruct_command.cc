#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/base/file_io.h"
#include "acro/capture/trial_io.h"
#include "acro/reconstruct/motion_export.h"
#include "acro/reconstruct/reconstruction.h"
#include "commands.h"

namespace acro::app {

namespace {

struct ReconstructArguments {
  TrialArguments common;
  ViewsArguments views;
  analysis::ReconstructionOptions options;
};

// "A:B" frames (0-based) to scale to.
void ParseWindow(const std::string& text, analysis::ReconstructionOptions* options) {
  int first = 0, last = 0;
  char colon = 0;
  std::istringstream in(text);
  if (!(in >> first >> colon >> last) || colon != ':' || !in.eof())
    throw CLI::ValidationError("--window", "needs frames A:B, got '" + text + "'");
  options->scaling_first_frame = first;
  options->scaling_last_frame = last;
}

int RunReconstruct(ReconstructArguments& args) {
  const TrialArguments& common = args.common;
  analysis::ReconstructionOptions& options = args.options;
  DemandValidCommandLine(options);
  CheckOutputDirectory(common.out_dir);  // before any work: a bad -o costs nothing

  // Inputs: a trial, or several cameras' keypoints triangulated — opened as every door opens
  // them (the pipeline).
  std::optional<pipeline::ViewsInput> views;
  pipeline::TrialInput input;
  if (args.views.given()) {
    pipeline::ViewsRequest request = args.views.Request(common);
    request.min_frames = 1;
    request.use = "the reconstruction";
    views = OpenViewsFor("reconstruct", request, common.quiet);
    input = std::move(views->input);
    options.views = views->views;
  } else {
    if (common.trial_path.empty())
      throw UsageError{"give TRIAL (markers or keypoints) or --detections CAM=PATH… --calib C"};
    pipeline::TrialRequest request = common.Request();
    request.min_frames = 1;  // joint angles of a single pose are still joint angles
    request.use = "the reconstruction";
    input = OpenTrialFor("reconstruct", request);
  }
  const capture::Trial& trial = input.trial;
  const std::optional<capture::Trial>& static_trial = input.static_trial;
  CheckCutoffBelowNyquist(options, trial);
  const analysis::AthleteBody& body = input.athlete.body;
  const std::string trial_path = views ? "triangulated" : common.trial_path;
  const std::string& out_dir = common.out_dir;

  // Reconstruction with a progress bar on stderr.
  if (!common.quiet) options.progress = MakeFrameProgress();
  const analysis::ReconstructionResult result =
      analysis::Reconstruct(trial, static_trial ? &*static_trial : nullptr, body, options);

  // Outputs.
  const std::string stem = std::filesystem::path(trial_path).stem().string();
  OutputTransaction outputs(out_dir);  // moved into place when all are complete
  const std::filesystem::path& dir = outputs.staging();
  if (views) {
    // The triangulated keypoints as a Pose2Sim user expects them, and how they were made.
    capture::WriteTrial(trial, dir / (stem + ".trc"));
    std::string text = views->triangulation.BriefReport();
    for (size_t v = 0; v < views->offsets.size(); ++v)
      text += fmt::format("  {}: offset {:.2f} frames ({}){}\n",
                          views->offsets[v].camera,
                          views->offsets[v].offset_frames,
                          views->offset_origin[v],
                          views->offset_origin[v] == "found"
                              ? fmt::format(", epipolar distance {:.1f} px, next best {:.1f} px",
                                            views->offsets[v].cost_px,
                                            views->offsets[v].runner_up_cost_px)
                              : "");
    WriteFileAtomically(dir / (stem + "_triangulation.txt"), text);
    std::fputs(text.c_str(), stdout);
  }
  analysis::WriteMotionMot(result.motion, dir / (stem + ".mot"));
  analysis::WriteMotionCsv(result.motion, dir / (stem + "_angles.csv"));
  analysis::WriteMotionC3d(result, trial, dir / (stem + "_model.c3d"));
  WriteFileAtomically(dir / (stem + "_residuals.csv"),
                      analysis::FormatMarkerResidualsCsv(result.motion));
  const std::string summary = "trial " + trial_path + " (" + std::to_string(trial.num_frames) +
                              " frames at " + std::to_string(trial.point_rate_hz) + " Hz)\n" +
                              "athlete " + body.model + ", " + std::to_string(body.height_m) +
                              " m\n" + result.summary.BriefReport();
  WriteFileAtomically(dir / (stem + "_summary.txt"), summary);
  outputs.Commit();
  std::fputs(summary.c_str(), stdout);
  std::fprintf(
      stdout,
      views
          ? "wrote "
            "%s/"
            "%s{.trc,_triangulation.txt,.mot,_angles.csv,_model.c3d,_residuals.csv,_summary.txt}\n"
          : "wrote %s/%s{.mot,_angles.csv,_model.c3d,_residuals.csv,_summary.txt}\n",
      out_dir.c_str(),
      stem.c_str());
  return 0;
}

}  // namespace

void AddReconstructCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<ReconstructArguments>();
  CLI::App* command = app.add_subcommand(
      "reconstruct",
      "Markers or video keypoints (C3D, TRC, CSV) — or several calibrated cameras' 2D keypoints "
      "(--detections, triangulated; writes DIR/triangulated.trc too) — to the athlete's joint "
      "angles: marker set "
      "detection, gap filling, zero-lag low-pass filter, scaling, per-frame inverse kinematics. "
      "Writes DIR/<trial>.mot (OpenSim, degrees), <trial>_angles.csv, <trial>_model.c3d "
      "(processed markers and joint angles as Vicon-style angle points), <trial>_residuals.csv "
      "and <trial>_summary.txt; prints the summary. docs/reconstruction.md.");
  args->common.Declare(command, &args->options, /*trial_required=*/false);
  args->views.Declare(command);
  command
      ->add_option("--order", args->options.filter_order, "Butterworth order per pass (default 2)")
      ->check(CLI::Range(1, 8));
  command
      ->add_option("--max-gap",
                   args->options.gaps.max_spline_gap_frames,
                   "longest gap filled by a cubic spline, frames (default 20)")
      ->check(CLI::NonNegativeNumber);
  command->add_option_function<std::string>(
      "--window",
      [args](const std::string& text) { ParseWindow(text, &args->options); },
      "frames A:B (0-based) to scale to when there is no static trial");
  command->add_flag_callback(
      "--no-swap-repair",
      [args] { args->options.repair_swaps = false; },
      "do not exchange left/right markers that fit the other side better");
  command->callback([args, run] { *run = [args] { return RunReconstruct(*args); }; });
}

}  // namespace acro::app
