// `acrolab synchro A B -o DIR`: a synchro pair — two trials of two athletes on two trampolines,
// each analysed as `analyze` does, then compared element by element (docs/scoring.md, "Synchro").
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "acro/assess/trial_analysis.h"
#include "acro/base/file_io.h"
#include "acro/fig/rules.h"
#include "acro/fig/synchro.h"
#include "acro/pipeline/steps.h"
#include "commands.h"

namespace acro::app {

namespace {

struct SynchroArguments {
  std::string a, b, athlete_a, athlete_b, rules, out_dir;
  double offset_s = 0.0;
};

// One athlete's routine, analysed as every door analyses a trial.
analysis::TrialAnalysis AnalyseSide(const std::string& path,
                                    const std::string& athlete,
                                    const fig::RoutineRules& rules) {
  std::fprintf(stderr, "analysing %s\n", path.c_str());
  pipeline::TrialRequest request;
  request.trial = path;
  request.athlete.profile = athlete;
  const pipeline::TrialInput input = OpenTrialFor("synchro", request);
  analysis::TrialAnalysisOptions options;
  options.rules = rules;
  analysis::TrialAnalysis result = pipeline::Analyze(input, options);
  for (const std::string& w : result.warnings)
    std::fprintf(stderr, "acrolab synchro: warning: %s\n", w.c_str());
  pipeline::DemandAFlight(input, result);
  return result;
}

int RunSynchro(const SynchroArguments& args) {
  CheckOutputDirectory(args.out_dir);  // before any work: a bad -o costs nothing
  const fig::RoutineRules rules =
      args.rules.empty() ? fig::RoutineRules::FigSenior() : fig::LoadRules(args.rules);
  const analysis::TrialAnalysis a = AnalyseSide(args.a, args.athlete_a, rules);
  const analysis::TrialAnalysis b =
      AnalyseSide(args.b, args.athlete_b.empty() ? args.athlete_a : args.athlete_b, rules);
  const fig::SynchroScore s = fig::ScoreSynchro(rules.synchro, a.score, b.score, args.offset_s);

  OutputTransaction outputs(args.out_dir);  // moved into place when complete
  WriteFileAtomically(outputs.staging() / "synchro.json",
                      analysis::FormatSynchroJson(s, a.score, b.score));
  outputs.Commit();

  std::printf("synchro: A %s, B %s (%s)\n", args.a.c_str(), args.b.c_str(), rules.name.c_str());
  std::printf("   #  A      B      skills  shapes  landing B-A (ms)  points\n");
  for (const fig::SynchroElement& e : s.elements)
    std::printf("  %2d  %-5s  %-5s  %-6s  %-6s  %16.1f  %s\n",
                e.element,
                e.code_a.c_str(),
                e.code_b.c_str(),
                e.skills_match ? "same" : "DIFFER",
                e.shapes_match ? "same" : "DIFFER",
                1000 * e.landing_difference_s,
                e.counted ? std::to_string(e.points).substr(0, 5).c_str() : "-");
  if (!s.ending.empty()) std::printf("  %s\n", s.ending.c_str());
  std::printf("  S %.3f over %d elements: mean |difference| %.1f ms, largest %.1f ms\n",
              s.score,
              s.elements_counted,
              1000 * s.mean_abs_difference_s,
              1000 * s.max_abs_difference_s);
  std::printf("  conversion: %s\n", s.source.c_str());
  std::printf("wrote %s/synchro.json\n", args.out_dir.c_str());
  return 0;
}

}  // namespace

void AddSynchroCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<SynchroArguments>();
  CLI::App* command = app.add_subcommand(
      "synchro",
      "A synchro pair: two trials (two athletes on two trampolines, recorded together), each "
      "analysed as analyze does, compared element by element — landing-time difference, same "
      "skill and shape — with the synchronisation score. Writes DIR/synchro.json. "
      "docs/scoring.md.");
  command->add_option("A", args->a, "the first athlete's trial")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("B", args->b, "the second athlete's trial")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--athlete", args->athlete_a, "athlete profile of A (and of B)")
      ->check(CLI::ExistingFile);
  command->add_option("--athlete-b", args->athlete_b, "athlete profile of B, when another")
      ->check(CLI::ExistingFile);
  command
      ->add_option(
          "--rules",
          args->rules,
          "the rules both routines and the synchronisation follow (rules/*.yaml; default the FIG "
          "senior routine)")
      ->check(CLI::ExistingFile);
  command
      ->add_option(
          "--offset-s",
          args->offset_s,
          "seconds added to B's clock to put it on A's, when the two were not recorded together "
          "(default 0)")
      ->check(CLI::Range(-3600.0, 3600.0));
  command->add_option("-o,--output", args->out_dir, "output directory")->required();
  command->callback([args, run] { *run = [args] { return RunSynchro(*args); }; });
}

}  // namespace acro::app
