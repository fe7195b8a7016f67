#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/de_leva.h"
#include "acro/athlete/motion.h"
#include "acro/athlete/standard_human.h"
#include "acro/assess/trial_analysis.h"
#include "acro/capture/trial_io.h"
#include "acro/report/analysis_report.h"
#include "commands.h"

namespace acro::app {

namespace {

constexpr const char* kAnalyzeHelp =
    "usage: acrolab analyze TRIAL [--athlete ATHLETE.yaml] [--static STATIC]\n"
    "                       [--markerset NAME|FILE.yaml] -o DIR [options]\n"
    "\n"
    "The main job: import, reconstruct, check the physics, measure every jump. Writes\n"
    "DIR/report.html (routine summary, per-jump table, verdict with its cause, plots),\n"
    "DIR/jumps.json, DIR/angles.mot, DIR/torques.sto, DIR/residuals.csv. docs/cli.md.\n"
    "  --athlete FILE       athlete profile (docs/formats/athlete.md); without it a de Leva\n"
    "                       athlete from --height (1.75) / --mass (65) / --sex (f), with a "
    "warning\n"
    "  --static FILE        static trial for scaling (otherwise a window of the motion)\n"
    "  --markerset NAME     plug_in_gait | helen_hayes | coco17 | trampoline | FILE.yaml\n"
    "                       (default: detected from the labels)\n"
    "  --cutoff HZ          marker low-pass cutoff (default: Winter's residual analysis)\n"
    "  --no-scale           keep the athlete's segment lengths and default marker offsets\n"
    "  --joint NAME         the joint whose angle and torque the report plots\n"
    "                       (default r_hip_flexion)\n"
    "  --bed X,Y,Z          centre of the trampoline bed (m), when the trial has no BED markers\n"
    "  --surface-height Z   height of the take-off surface (m) when the trial has no BED\n"
    "                       markers: 1.155 for a FIG trampoline over a floor at z = 0; the\n"
    "                       phases then come from the soles (default: from the centre of mass)\n"
    "  --no-force-plates    phases from the body's centre of mass even when plates exist\n"
    "  --no-images          the report without plots (no rendering at all)\n"
    "  --threads N          worker threads (default: all cores)\n"
    "  --quiet              no progress on stderr\n";

// "x,y,z" as three numbers.
Eigen::Vector3d ParseVector(const std::string& option, const std::string& text) {
  Eigen::Vector3d v;
  size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t comma = text.find(',', start);
    if ((k < 2) != (comma != std::string::npos))
      throw UsageError{option + " needs X,Y,Z, got '" + text + "'"};
    v[k] = OptionNumber(option, text.substr(start, comma - start));
    start = comma + 1;
  }
  return v;
}

}  // namespace

int RunAnalyze(const std::vector<std::string>& args) {
  // Arguments.
  TrialArguments common;
  bool images = true;
  analysis::TrialAnalysisOptions options;
  ui::AnalysisReportOptions report;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> const std::string& { return OptionValue(args, &i); };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kAnalyzeHelp, stdout);
      return 0;
    } else if (common.Take(args, &i, &options.reconstruction)) {
      continue;
    } else if (arg == "--joint") {
      report.joint = value();
    } else if (arg == "--bed") {
      analysis::BedGeometry bed;
      bed.centre_W = ParseVector(arg, value());
      bed.source = "option --bed";
      options.bed = bed;
    } else if (arg == "--surface-height") {
      options.surface_height_m = OptionNumber(arg, value());
    } else if (arg == "--no-force-plates") {
      options.use_force_plates = false;
    } else if (arg == "--no-images") {
      images = false;
    } else {
      throw UsageError{"unknown option '" + arg + "'"};
    }
  }
  common.Check();
  const bool quiet = common.quiet;
  std::string why;
  if (!options.IsValid(&why)) throw UsageError{why};

  // Inputs: trial, static trial, athlete.
  auto say = [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  const capture::Trial trial = capture::ReadTrial(common.trial_path);
  std::optional<capture::Trial> static_trial;
  if (!common.static_path.empty()) static_trial = capture::ReadTrial(common.static_path);
  const analysis::AthleteBody body = common.MakeBody("analyze", &report.athlete);

  // The plotted joint must exist before any work is done (and before any file is written).
  {
    const std::vector<std::string> names =
        analysis::MakeCoordinateNames(analysis::MakeStandardHumanModel(body));
    if (std::find(names.begin() + 7, names.end(), report.joint) == names.end())
      throw UsageError{"--joint: '" + report.joint +
                       "' is not a joint angle (e.g. r_hip_flexion, l_knee_flexion, "
                       "lumbar_flexion; docs/reconstruction.md)"};
  }

  // The analysis, with one progress line per step and the IK's frames.
  options.progress = say;
  if (!quiet) options.reconstruction.progress = MakeFrameProgress();
  const analysis::TrialAnalysis result =
      analysis::AnalyzeTrial(trial, static_trial ? &*static_trial : nullptr, body, options);
  for (const std::string& w : result.warnings)
    std::fprintf(stderr, "acrolab analyze: warning: %s\n", w.c_str());

  // Outputs: the tables, then the report (with plots when rendering works here).
  const std::filesystem::path dir(common.out_dir);
  std::filesystem::create_directories(dir);
  analysis::WriteAnalysisTables(result, dir);
  report.trial_path = common.trial_path;
  report.render_images = images;
  say("report: rendering plots");
  const ui::AnalysisReportOutcome outcome = ui::WriteAnalysisReport(result, dir, report);
  if (!outcome.images_rendered) say("report: no plots: " + outcome.reason);
  std::fputs(result.BriefReport().c_str(), stdout);
  std::printf("report: %s\n", (dir / "report.html").string().c_str());
  std::printf("wrote %s/{report.html,jumps.json,angles.mot,torques.sto,residuals.csv}\n",
              common.out_dir.c_str());
  return 0;
}

}  // namespace acro::app
