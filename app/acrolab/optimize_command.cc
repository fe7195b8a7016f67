#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/design/skill_optimization.h"
#include "acro/design/skill_simulation.h"
#include "acro/library/designs.h"
#include "acro/report/skill_report.h"
#include "commands.h"

#ifdef ACRO_HAVE_VIEWS
#include <fmt/format.h>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/body_mesh.h"
#include "acro/capture/frame_output.h"
#include "acro/dynamics/configuration.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/design_filmstrip.h"
#include "acro/views/display.h"
#endif

namespace acro::app {

namespace {

#ifdef ACRO_HAVE_VIEWS
// The paper's comparison (its Figure 8): the initial and the optimised timing one above the
// other at the same eight instants, DIR/filmstrip.png, and with `video` DIR/filmstrip.mp4. The
// 3D views are an extra here: without a display or Xvfb the page says why.
ui::SkillReportExtras DrawFilmstrips(const std::string& command,
                                     const analysis::SkillDesign& design,
                                     const analysis::SkillOptimizationResult& result,
                                     const std::filesystem::path& dir,
                                     bool video) {
  ui::SkillReportExtras extras;
  try {
    const ui::XDisplay display;
    const ui::DesignFilmstrip strip(
        design,
        {{"initial timing", result.initial},
         {fmt::format("optimised timing (model {})", analysis::SkillModelNumber(result.model)),
          result.optimized}});
    extras.filmstrip_times_s = strip.times_s();
    const ui::FilmstripOptions options = ui::DesignFilmstripOptions();
    CreateOutputDirectory(dir);
    const std::vector<std::uint8_t> png =
        capture::EncodeRgbPng(options.width, 2 * options.height, strip.Render(options));
    WriteFileAtomically(dir / "filmstrip.png", std::string(png.begin(), png.end()));
    extras.filmstrip = "filmstrip.png";
    if (video) {
      ui::FilmstripVideoOptions v;
      v.progress = MakeCancellableProgress("filmstrip", "frames");
      strip.WriteVideo(dir / "filmstrip.mp4", options, v);
      extras.filmstrip_video = "filmstrip.mp4";
    }
  } catch (const InputError& e) {
    extras.filmstrip.clear();
    extras.filmstrip_note = std::string("no filmstrip: ") + e.what();
    std::fprintf(stderr, "acrolab %s: %s\n", command.c_str(), extras.filmstrip_note.c_str());
  }
  return extras;
}
#endif

struct OptimizeArguments {
  std::string skill_path, out_dir, library;
  SkillRunArguments run;
};

int RunOptimize(OptimizeArguments& args) {
  PrepareSkillRun(args.run, args.out_dir);
  const analysis::Skill skill = analysis::ReadSkill(args.skill_path);
  std::fprintf(stderr,
               "acrolab optimize: %s, %zu keyframes, flight time %.3f s, model %d\n",
               skill.name.c_str(),
               skill.keyframes.size(),
               skill.flight_time_s,
               analysis::SkillModelNumber(args.run.options.model));
  RunSkill("optimize", skill, args.run, args.out_dir, {}, {});
  if (!args.library.empty()) StoreDesign(args.library, args.skill_path, skill, args.out_dir);
  return 0;
}

}  // namespace

void PrepareSkillRun(SkillRunArguments& args, const std::string& out_dir) {
  if (args.options.quadrature_intervals % 2 != 0)
    throw UsageError{"--intervals " + std::to_string(args.options.quadrature_intervals) +
                     " is odd; Simpson's rule needs an even number"};
  DemandValidCommandLine(args.options);
  CheckOutputDirectory(out_dir);  // before any work: a bad -o costs nothing
}

analysis::SkillOptimizationResult RunSkill(
    const std::string& command,
    const analysis::Skill& skill,
    SkillRunArguments& args,
    const std::string& out_dir,
    const ui::SkillReportExtras& more,
    const std::function<std::vector<std::string>(const std::filesystem::path&)>& write_more) {
  analysis::SkillOptimizationOptions& options = args.options;
  const analysis::SkillDesign design(skill);
  options.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  const analysis::SkillOptimizationResult result = analysis::OptimizeSkill(design, options);
  for (const analysis::SkillOptimizationSummary& s : result.stages)
    std::fprintf(stderr, "  solver: %s\n", s.BriefReport().c_str());
  std::optional<analysis::SkillSimulationResult> sim;
  if (args.simulate) {
    std::fprintf(stderr, "  simulating the flight\n");
    sim = analysis::SimulateSkill(design, result.optimized);
  }
  ui::SkillReportExtras extras = more;
  OutputTransaction outputs(out_dir);  // moved into place when all are complete
#ifdef ACRO_HAVE_VIEWS
  std::fprintf(stderr, "  drawing the filmstrip\n");
  const ui::SkillReportExtras strip =
      DrawFilmstrips(command, design, result, outputs.staging(), args.video);
  extras.filmstrip = strip.filmstrip;
  extras.filmstrip_video = strip.filmstrip_video;
  extras.filmstrip_note = strip.filmstrip_note;
  extras.filmstrip_times_s = strip.filmstrip_times_s;
#else
  if (args.video) NeedTheViews();
#endif
  std::vector<std::string> files =
      write_more ? write_more(outputs.staging()) : std::vector<std::string>{};
  for (std::string& f :
       ui::WriteSkillOutputs(outputs.staging(), design, result, sim ? &*sim : nullptr, extras))
    files.push_back(std::move(f));
  outputs.Commit();
  for (const std::string* f : {&extras.filmstrip, &extras.filmstrip_video})
    if (!f->empty()) files.push_back(*f);

  // Summary.
  std::printf("%s (model %d)\n", skill.name.c_str(), analysis::SkillModelNumber(result.model));
  std::printf("  J: %.6g -> %.6g (%.1f times smaller)\n",
              result.objective_initial,
              result.objective,
              result.objective_initial / result.objective);
  std::printf("  angular momentum variation: %.2f %% -> %.2f %%\n",
              100 * result.angular_momentum_variation_initial,
              100 * result.angular_momentum_variation);
  std::printf("  keyframe  initial (s)  optimised (s)  name\n");
  for (int i = 0; i < design.num_keyframes(); ++i)
    std::printf("  %8d  %11.3f  %13.3f  %s\n",
                i + 1,
                result.times_initial_s[i],
                result.optimized.times_s[i],
                skill.keyframes[static_cast<size_t>(i)].name.c_str());
  if (sim) std::printf("  simulation: %s\n", analysis::FormatSkillSimulation(*sim).c_str());
  if (sim)
    for (const std::string& line : sim->warnings)
      std::fprintf(stderr, "acrolab %s: warning: %s\n", command.c_str(), line.c_str());
  std::printf("  wrote %zu files to %s\n", files.size(), out_dir.c_str());
  return result;
}

void StoreDesign(const std::string& library_path,
                 const std::string& skill_path,
                 const analysis::Skill& skill,
                 const std::string& out_dir) {
  // The design kept in the season library, beside its folder.
  library::Library lib(library_path, library::Library::Mode::kReadWrite);
  const std::int64_t id = library::StoreSkillDesign(lib, skill_path, skill, out_dir);
  std::printf("  stored as design %lld of %s in %s\n",
              static_cast<long long>(id),
              skill.athlete.name.c_str(),
              library_path.c_str());
}

void SkillRunArguments::Declare(CLI::App* command) {
  const std::map<std::string, analysis::SkillModel> models = {
      {"1", analysis::SkillModel::kTrajectory}, {"2", analysis::SkillModel::kTiming}};
  command
      ->add_option("--model",
                   options.model,
                   "2: keyframe times only; 1: times and trajectory coefficients (default: 2 for "
                   "optimize, 1 for design)")
      ->transform(CLI::CheckedTransformer(models));
  command->add_flag_callback(
      "--fixed-joints",
      [this] { options.model1_vary_joints = false; },
      "Model 1 keeps the keyframe joint angles and varies the times and the root orientation only");
  command->add_flag("--video",
                    video,
                    "also write the filmstrip (initial and optimised timing) as DIR/filmstrip.mp4");
  command
      ->add_option("--intervals",
                   options.quadrature_intervals,
                   "quadrature intervals over the flight (even, 2–2000; default 40)")
      ->check(CLI::Range(2, 2000));
}

void AddOptimizeCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<OptimizeArguments>();
  CLI::App* command = app.add_subcommand(
      "optimize",
      "Finds when each keyframe of a skill must happen so that the motion obeys physics (Model 2: "
      "keyframe times), or also bends the trajectories within the keyframe tolerances (Model 1), "
      "and writes DIR/result.json, timing.csv/.svg/.png, angular_momentum.svg/.png, motion.c3d, "
      "motion.mot, filmstrip.png (with the 3D views) and report.html. Progress goes to stderr. "
      "Skill files: docs/formats/skill.md; "
      "method: docs/skill-design.md.");
  command->add_option("SKILL", args->skill_path, "the skill file (YAML)")->required();
  command->add_option("-o,--output", args->out_dir, "output folder (created)")->required();
  args->run.Declare(command);
  command->add_flag("--simulate",
                    args->run.simulate,
                    "also simulate the flight with the optimised motion (somersaults, landing)");
  command->add_option(
      "--library", args->library, "also store the design in this season library (docs/library.md)");
  command->callback([args, run] { *run = [args] { return RunOptimize(*args); }; });
}

}  // namespace acro::app
