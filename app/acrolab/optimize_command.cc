#include <cstdio>
#include <optional>
#include <string>

#include "acro/report/skill_report.h"
#include "acro/design/timing_optimization.h"
#include "commands.h"

namespace acro::app {

namespace {

constexpr const char* kOptimizeHelp =
    "usage: acrolab optimize SKILL.yaml [--model 1|2] [--fixed-joints] [--simulate] [--intervals "
    "N]\n"
    "                        -o DIR\n"
    "\n"
    "Finds when each keyframe of a skill must happen so that the motion obeys physics (Model 2:\n"
    "keyframe times), or also bends the trajectories within the keyframe tolerances (Model 1),\n"
    "and writes DIR/result.json, timing.csv/.svg/.png, angular_momentum.svg/.png, motion.c3d,\n"
    "motion.mot and report.html. Progress goes to stderr.\n"
    "  --model 1|2     2 (default): times only; 1: times and trajectory coefficients\n"
    "  --fixed-joints  Model 1 keeps the keyframe joint angles and varies the times and the root\n"
    "                  orientation only\n"
    "  --simulate      also simulate the flight with the optimised motion (somersaults, landing)\n"
    "  --intervals N   quadrature intervals over the flight (even; default 40)\n"
    "  -o DIR          output folder (created)\n"
    "Skill files: docs/formats/skill.md; method: docs/skill-design.md.\n";

}  // namespace

int RunOptimize(const std::vector<std::string>& args) {
  // Arguments.
  std::string skill_path, out_dir;
  bool simulate = false;
  analysis::TimingOptimizationOptions options;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    auto value = [&]() -> const std::string& { return OptionValue(args, &i); };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kOptimizeHelp, stdout);
      return 0;
    } else if (arg == "--model") {
      const std::string& m = value();
      if (m != "1" && m != "2") throw UsageError{"--model is 1 or 2, got '" + m + "'"};
      options.model = m == "1" ? 1 : 2;
    } else if (arg == "--fixed-joints") {
      options.model1_vary_joints = false;
    } else if (arg == "--simulate") {
      simulate = true;
    } else if (arg == "--intervals") {
      const std::string& n = value();
      try {
        options.quadrature_intervals = std::stoi(n);
      } catch (...) {
        throw UsageError{"--intervals needs an even integer, got '" + n + "'"};
      }
    } else if (arg == "-o" || arg == "--output") {
      out_dir = value();
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError{"unknown option " + arg};
    } else if (skill_path.empty()) {
      skill_path = arg;
    } else {
      throw UsageError{"more than one skill file"};
    }
  }
  if (skill_path.empty()) throw UsageError{"no skill file"};
  if (out_dir.empty()) throw UsageError{"no output folder (-o DIR)"};
  std::string why;
  if (!options.IsValid(&why)) throw UsageError{why};

  // Read, optimise, simulate, write.
  const analysis::Skill skill = analysis::ReadSkill(skill_path);
  std::fprintf(stderr,
               "acrolab optimize: %s, %zu keyframes, flight time %.3f s, model %d\n",
               skill.name.c_str(),
               skill.keyframes.size(),
               skill.flight_time_s,
               options.model);
  const analysis::SkillDesign design(skill);
  options.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  const analysis::TimingOptimizationResult result = analysis::OptimizeSkillTiming(design, options);
  for (const analysis::TimingOptimizationSummary& s : result.stages)
    std::fprintf(stderr, "  solver: %s\n", s.BriefReport().c_str());
  std::optional<analysis::SkillSimulationResult> sim;
  if (simulate) {
    std::fprintf(stderr, "  simulating the flight\n");
    sim = analysis::SimulateSkill(design, result.optimized);
  }
  const std::vector<std::string> files =
      ui::WriteSkillOutputs(out_dir, design, result, sim ? &*sim : nullptr);

  // Summary.
  std::printf("%s (model %d)\n", skill.name.c_str(), result.model);
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
  if (sim)
    std::printf(
        "  simulation: %.3f somersaults (designed %.3f), landing %.1f deg from the last keyframe\n",
        sim->somersault_turns,
        sim->intended_somersault_turns,
        sim->final_orientation_error_rad * 180.0 / 3.14159265358979323846);
  if (sim)
    for (const std::string& line : sim->warnings)
      std::fprintf(stderr, "acrolab optimize: warning: %s\n", line.c_str());
  std::printf("  wrote %zu files to %s\n", files.size(), out_dir.c_str());
  return 0;
}

}  // namespace acro::app
