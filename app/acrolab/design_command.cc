#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "acro/base/file_io.h"
#include "acro/base/text.h"
#include "acro/design/skill_file.h"
#include "acro/design/skill_from_code.h"
#include "acro/report/skill_report.h"
#include "commands.h"

namespace acro::app {

namespace {

struct DesignArguments {
  std::string code, athlete_path, out_dir, library;
  double flight_time_s = 0.0, takeoff_velocity_mps = 0.0;
  SkillRunArguments run;
};

// FormatSkillFromCode's lines without their indentation, for the report page.
std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t first = line.find_first_not_of(' ');
    if (first != std::string::npos) lines.push_back(line.substr(first));
  }
  return lines;
}

int RunDesign(DesignArguments& args) {
  namespace fs = std::filesystem;
  PrepareSkillRun(args.run, args.out_dir);
  analysis::SkillFromCodeOptions options;
  options.flight_time_s = args.flight_time_s;
  options.takeoff_vertical_velocity_mps = args.takeoff_velocity_mps;
  options.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
  std::fprintf(stderr,
               "acrolab design: %s for %s: shooting the flight\n",
               EscapeForTerminal(args.code).c_str(),
               EscapeForTerminal(args.athlete_path).c_str());
  const analysis::SkillFromCodeResult designed =
      analysis::DesignSkillFromCode(args.code, fs::absolute(args.athlete_path), options);
  const std::string summary = analysis::FormatSkillFromCode(designed);
  std::fprintf(stderr,
               "acrolab design: %zu keyframes; optimising (model %d)\n",
               designed.skill.keyframes.size(),
               analysis::SkillModelNumber(args.run.options.model));

  // The keyframes as a skill file in the output folder (the athlete's path relative to it).
  const fs::path skill_path = fs::absolute(args.out_dir) / "skill.yaml";
  analysis::Skill skill = designed.skill;
  skill.source = skill_path.string();
  const std::string skill_yaml = analysis::FormatSkillYaml(skill, fs::absolute(args.out_dir));
  ui::SkillReportExtras more;
  more.design_lines = Lines(summary);
  RunSkill("design", skill, args.run, args.out_dir, more, [&](const fs::path& staging) {
    WriteFileAtomically(staging / "skill.yaml", skill_yaml);
    WriteFileAtomically(staging / "design.json", ui::MakeSkillFromCodeJson(designed));
    WriteFileAtomically(staging / "design.txt", summary);
    return std::vector<std::string>{"skill.yaml", "design.json", "design.txt"};
  });
  std::printf("%s", summary.c_str());
  if (!args.library.empty()) StoreDesign(args.library, skill_path.string(), skill, args.out_dir);
  return 0;
}

}  // namespace

void AddDesignCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<DesignArguments>();
  args->run.options.model = analysis::SkillModel::kTrajectory;
  args->run.simulate = true;
  CLI::App* command = app.add_subcommand(
      "design",
      "Designs a skill from its FIG code for one athlete: keyframes sampled from a simulated "
      "flight (take-off, shape, where each somersault's half twists happen, the arm and hip "
      "actions that start them, opening, landing) written as DIR/skill.yaml, then optimised "
      "(Model 2, then Model 1 by default) and simulated; prints the take-off it needs, the "
      "difficulty and whether the athlete can do it (DIR/design.json, design.txt), and writes "
      "what `optimize --simulate` writes. Method: docs/skill-design.md, \"Skills from their "
      "code\".");
  command->add_option("CODE", args->code, "the FIG code, e.g. 42/, 800<, 821o, 12001o")->required();
  command->add_option("--athlete", args->athlete_path, "the athlete profile (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", args->out_dir, "output folder (created)")->required();
  CLI::Option* flight = command
                            ->add_option("--flight-time",
                                         args->flight_time_s,
                                         "flight time (s, 0.5–3; default: from the somersaults "
                                         "and twists, docs/skill-design.md)")
                            ->check(CLI::Range(0.5, 3.0));
  command
      ->add_option("--takeoff-velocity",
                   args->takeoff_velocity_mps,
                   "take-off vertical velocity of the centre of mass (m/s) instead of a flight "
                   "time")
      ->check(CLI::Range(2.45, 14.72))
      ->excludes(flight);
  args->run.Declare(command);
  command->add_flag_callback(
      "--no-simulate",
      [args] { args->run.simulate = false; },
      "do not simulate the flight with the optimised motion");
  command->add_option(
      "--library", args->library, "also store the design in this season library (docs/library.md)");
  command->callback([args, run] { *run = [args] { return RunDesign(*args); }; });
}

}  // namespace acro::app
