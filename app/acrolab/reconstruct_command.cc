#include <cstdio>
#include <filesystem>
#include <optional>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/reconstruct/motion_export.h"
#include "acro/reconstruct/reconstruction.h"
#include "acro/base/file_io.h"
#include "acro/capture/trial_io.h"
#include "commands.h"

namespace acro::app {

namespace {

constexpr const char* kReconstructHelp =
    "usage: acrolab reconstruct TRIAL [--static STATIC] [--athlete ATHLETE.yaml]\n"
    "                           [--markerset NAME|FILE.yaml] -o DIR [options]\n"
    "\n"
    "Markers or video keypoints (C3D, TRC, CSV) to the athlete's joint angles: marker set\n"
    "detection, gap filling, zero-lag low-pass filter, scaling, per-frame inverse kinematics.\n"
    "Writes DIR/<trial>.mot (OpenSim, degrees), DIR/<trial>_angles.csv, DIR/<trial>_model.c3d\n"
    "(processed markers + joint angles as Vicon-style angle points), DIR/<trial>_residuals.csv\n"
    "and DIR/<trial>_summary.txt; prints the summary. docs/reconstruction.md.\n"
    "  --static FILE        static trial for scaling (otherwise a window of the motion)\n"
    "  --athlete FILE       athlete profile (docs/formats/athlete.md); without it a de Leva\n"
    "                       athlete from --height (1.75) / --mass (65) / --sex (f), with a "
    "warning\n"
    "  --markerset NAME     plug_in_gait | helen_hayes | coco17 | trampoline | FILE.yaml\n"
    "                       (default: detected from the labels)\n"
    "  --cutoff HZ          low-pass cutoff (default: Winter's residual analysis); 0 = no filter\n"
    "  --order N            Butterworth order per pass (default 2)\n"
    "  --max-gap FRAMES     longest gap filled by a cubic spline (default 20)\n"
    "  --window A:B         frames (0-based) to scale to when there is no static trial\n"
    "  --no-scale           keep the athlete's segment lengths and default marker offsets\n"
    "  --no-swap-repair     do not exchange left/right markers that fit the other side better\n"
    "  --threads N          worker threads (default: all cores)\n"
    "  --quiet              no progress bar\n";

}  // namespace

int RunReconstruct(const std::vector<std::string>& args) {
  // Arguments.
  TrialArguments common;
  std::string window;
  analysis::ReconstructionOptions options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> const std::string& { return OptionValue(args, &i); };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kReconstructHelp, stdout);
      return 0;
    } else if (common.Take(args, &i, &options)) {
      continue;
    } else if (arg == "--order") {
      options.filter_order = static_cast<int>(OptionNumber(arg, value()));
    } else if (arg == "--max-gap") {
      options.gaps.max_spline_gap_frames = static_cast<int>(OptionNumber(arg, value()));
    } else if (arg == "--window") {
      window = value();
      const size_t colon = window.find(':');
      if (colon == std::string::npos) throw UsageError{"--window needs A:B"};
      options.scaling_first_frame = static_cast<int>(OptionNumber(arg, window.substr(0, colon)));
      options.scaling_last_frame = static_cast<int>(OptionNumber(arg, window.substr(colon + 1)));
    } else if (arg == "--no-swap-repair") {
      options.repair_swaps = false;
    } else {
      throw UsageError{"unknown option '" + arg + "'"};
    }
  }
  common.Check();
  std::string why;
  if (!options.IsValid(&why)) throw UsageError{why};

  // Inputs: trial, static trial, athlete.
  const capture::Trial trial = capture::ReadTrial(common.trial_path);
  std::optional<capture::Trial> static_trial;
  if (!common.static_path.empty()) static_trial = capture::ReadTrial(common.static_path);
  const analysis::AthleteBody body = common.MakeBody("reconstruct");
  const std::string& trial_path = common.trial_path;
  const std::string& out_dir = common.out_dir;

  // Reconstruction with a progress bar on stderr.
  if (!common.quiet) options.progress = MakeFrameProgress();
  const analysis::ReconstructionResult result =
      analysis::Reconstruct(trial, static_trial ? &*static_trial : nullptr, body, options);

  // Outputs.
  std::filesystem::create_directories(out_dir);
  const std::string stem = std::filesystem::path(trial_path).stem().string();
  const std::filesystem::path dir(out_dir);
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
  std::fputs(summary.c_str(), stdout);
  std::fprintf(stdout,
               "wrote %s/%s{.mot,_angles.csv,_model.c3d,_residuals.csv,_summary.txt}\n",
               out_dir.c_str(),
               stem.c_str());
  return 0;
}

}  // namespace acro::app
