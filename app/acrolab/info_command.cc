#include <cstdio>
#include <memory>

#include "acro/capture/trial_info.h"
#include "acro/capture/trial_io.h"
#include "commands.h"

namespace acro::app {

namespace {

struct InfoArguments {
  std::string file;
  bool json = false;
};

int RunInfo(const InfoArguments& args) {
  const capture::Trial trial = capture::ReadTrial(args.file);
  const std::string report =
      args.json ? capture::FormatTrialInfoJson(trial) : capture::FormatTrialInfoText(trial);
  std::fputs(report.c_str(), stdout);
  return 0;
}

}  // namespace

void AddInfoCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<InfoArguments>();
  CLI::App* command = app.add_subcommand(
      "info",
      "What a C3D, TRC or CSV file holds: format, processor, frames, rates, markers with their "
      "gaps, analog channels, force plates, events and import warnings.");
  command->add_option("FILE", args->file, "the trial file")->required();
  command->add_flag("--json", args->json, "print one JSON object (docs/cli.md)");
  command->callback([args, run] { *run = [args] { return RunInfo(*args); }; });
}

}  // namespace acro::app
