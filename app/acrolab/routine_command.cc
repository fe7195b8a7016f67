#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/design/routine_design.h"
#include "acro/fig/rules.h"
#include "acro/fig/score_sheet.h"
#include "acro/report/routine_report.h"
#include "commands.h"

#ifdef ACRO_HAVE_VIEWS
#include <fmt/format.h>

#include "acro/capture/frame_output.h"
#include "acro/views/design_filmstrip.h"
#include "acro/views/display.h"
#endif

namespace acro::app {

namespace {

struct RoutineArguments {
  std::string routine_path, codes, athlete_path, out_dir, rules;
  double marker_noise_mm = 0.0;
  double max_push_deg = 0.0;
  int threads = 0;
  bool video = false;
};

#ifdef ACRO_HAVE_VIEWS
// One filmstrip per skill, DIR/filmstrip_NN.png; without a display or Xvfb the page says why.
ui::RoutineReportExtras DrawFilmstrips(const analysis::RoutineDesignResult& result,
                                       const std::filesystem::path& dir,
                                       bool video) {
  ui::RoutineReportExtras extras;
  try {
    const ui::XDisplay display;
    ui::FilmstripOptions options = ui::DesignFilmstripOptions();
    const std::vector<std::vector<std::uint8_t>> strips = ui::RenderRoutineFilmstrips(
        result.simulation, result.skills.front().skill.athlete, options);
    CreateOutputDirectory(dir);
    for (size_t i = 0; i < strips.size(); ++i) {
      const std::string name = fmt::format("filmstrip_{:02d}.png", i + 1);
      const std::vector<std::uint8_t> png =
          capture::EncodeRgbPng(options.width, options.height, strips[i]);
      WriteFileAtomically(dir / name, std::string(png.begin(), png.end()));
      extras.filmstrips.push_back(name);
    }
    if (video) {
      std::vector<std::string> labels;
      for (const analysis::SkillFromCodeResult& s : result.skills) labels.push_back(s.skill.name);
      ui::RoutineVideoOptions v;
      v.progress = MakeCancellableProgress("routine video", "frames");
      ui::WriteRoutineVideo(
          result.simulation, result.skills.front().skill.athlete, labels, dir / "routine.mp4", v);
      extras.video = "routine.mp4";
    }
  } catch (const InputError& e) {
    extras.filmstrips.clear();
    extras.filmstrip_note = std::string("no filmstrips: ") + e.what();
    std::fprintf(stderr, "acrolab routine: %s\n", extras.filmstrip_note.c_str());
  }
  return extras;
}
#endif

int RunRoutine(RoutineArguments& args) {
  if (args.routine_path.empty() == args.codes.empty())
    throw UsageError{"give either a routine file or --codes"};
  if (!args.codes.empty() && args.athlete_path.empty()) throw UsageError{"--codes needs --athlete"};
  CheckOutputDirectory(args.out_dir);  // before any work: a bad -o costs nothing
  const fig::RoutineRules rules =
      args.rules.empty() ? fig::RoutineRules::FigSenior() : fig::LoadRules(args.rules);
  analysis::RoutineSpec spec = args.codes.empty()
                                   ? analysis::ReadRoutineSpec(args.routine_path)
                                   : analysis::RoutineSpecFromCodes(args.codes, args.athlete_path);
  if (!args.athlete_path.empty()) spec.athlete_path = std::filesystem::absolute(args.athlete_path);
  analysis::RoutineDesignOptions options;
  options.threads = args.threads;
  if (args.max_push_deg > 0)
    options.max_push_rad = args.max_push_deg * 3.14159265358979323846 / 180;
  options.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  std::fprintf(stderr, "acrolab routine: designing %zu skills\n", spec.skills.size());
  const analysis::RoutineDesignResult result = analysis::DesignRoutine(spec, options);

  OutputTransaction outputs(args.out_dir);  // moved into place when all are complete
  ui::RoutineReportExtras extras;
#ifdef ACRO_HAVE_VIEWS
  std::fprintf(stderr, "  drawing the filmstrips\n");
  extras = DrawFilmstrips(result, outputs.staging(), args.video);
#else
  if (args.video) NeedTheViews();
#endif
  ui::RoutineMarkerOptions markers;
  markers.noise_sd_m = args.marker_noise_mm / 1000.0;
  std::vector<std::string> files = ui::WriteRoutineOutputs(
      outputs.staging(), std::filesystem::absolute(args.out_dir), result, markers, extras);
  outputs.Commit();

  // Summary.
  const analysis::SimulatedRoutine& sim = result.simulation;
  std::printf("%s: %zu skills, DD %.1f, time of flight %.3f s\n",
              spec.name.empty() ? "routine" : spec.name.c_str(),
              result.skills.size(),
              result.difficulty,
              result.time_of_flight_s);
  std::printf("   #  code     DD  take-off (s)  ToF (s)  apex (m)  push (deg)  skill\n");
  for (size_t i = 0; i < result.skills.size(); ++i) {
    const analysis::RoutineFlightTruth& f = sim.flights[i];
    std::printf("  %2zu  %-6s  %3.1f  %12.3f  %7.3f  %8.2f  %10.0f  %s\n",
                i + 1,
                f.fig_code.c_str(),
                result.skills[i].difficulty.total(),
                f.takeoff_s,
                f.landing_s - f.takeoff_s,
                f.apex_com_z_m - sim.options.bed_centre_m.z(),
                sim.contacts[i].push_rad * 180 / 3.14159265358979323846,
                result.skills[i].skill.name.c_str());
  }
  for (const std::string& note : result.notes) std::printf("  note: %s\n", note.c_str());
  // Against the rules (docs/scoring.md): what a panel would count, and what the routine misses.
  const fig::RoutineScore score = fig::ScoreRoutine(rules, analysis::DesignedFlights(result));
  std::printf("  %s: D %.1f, T %.3f; %s\n",
              score.rules_name.c_str(),
              score.difficulty,
              score.time_of_flight,
              score.valid() ? "valid" : "not valid:");
  if (score.interrupted) std::printf("    %s\n", score.interruption.c_str());
  for (const std::string& m : score.requirements_missing)
    std::printf("    requirement missing: %s\n", m.c_str());
  for (const std::string& b : score.rule_breaks) std::printf("    %s\n", b.c_str());
  if (score.difficulty_capped)
    std::printf(
        "    difficulty %.1f capped at %.1f\n", score.difficulty_uncapped, score.difficulty);
  std::printf("  wrote %zu files to %s\n",
              files.size() + extras.filmstrips.size() + (extras.video.empty() ? 0 : 1),
              args.out_dir.c_str());
  return 0;
}

}  // namespace

void AddRoutineCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<RoutineArguments>();
  CLI::App* command = app.add_subcommand(
      "routine",
      "Designs a routine from its FIG codes for one athlete: every skill from its code (as "
      "`design`), checked against the FIG composition (no skill repeated; ten skills) and the "
      "athlete's reach, flown one after the other through bed contacts; writes DIR/routine.json, "
      "routine.c3d (trampoline marker set), routine.mot, height.svg/.png, skills/NN.yaml, the "
      "filmstrips and report.html. Method: docs/skill-design.md, \"Routines\".");
  command->add_option("ROUTINE", args->routine_path, "a routine file (docs/formats/routine.md)")
      ->check(CLI::ExistingFile);
  command
      ->add_option(
          "--rules",
          args->rules,
          "the routine rules it is checked against (rules/*.yaml; default the FIG senior routine; "
          "docs/scoring.md)")
      ->check(CLI::ExistingFile);
  command->add_option("--codes", args->codes, "the skills' FIG codes, e.g. \"40o 41/ 42/ 800<\"");
  command->add_option("--athlete", args->athlete_path, "the athlete profile (YAML)")
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", args->out_dir, "output folder (created)")->required();
  command
      ->add_option("--marker-noise-mm",
                   args->marker_noise_mm,
                   "Gaussian noise on every marker coordinate of routine.c3d (mm; default 0)")
      ->check(CLI::Range(0.0, 50.0));
  command
      ->add_option("--max-push-deg",
                   args->max_push_deg,
                   "the largest push of a bed contact the athlete gives (deg of hip flexion, knees "
                   "twice as much; default 60)")
      ->check(CLI::Range(1.0, 90.0));
  command->add_flag(
      "--video",
      args->video,
      "also write the routine as a video, DIR/routine.mp4 (from the side, real time)");
  command->add_option("--threads", args->threads, "skills designed at once (default: every core)")
      ->check(CLI::Range(0, 256));
  command->callback([args, run] { *run = [args] { return RunRoutine(*args); }; });
}

}  // namespace acro::app
