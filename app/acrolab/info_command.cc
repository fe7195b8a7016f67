#include <cstdio>

#include "acro/capture/trial_info.h"
#include "acro/capture/trial_io.h"
#include "commands.h"

namespace acro::app {

int RunInfo(const std::vector<std::string>& args) {
  std::string file;
  bool json = false;
  for (const std::string& arg : args) {
    if (arg == "--json") {
      json = true;
    } else if (arg == "--help" || arg == "-h") {
      std::puts(
          "usage: acrolab info FILE [--json]\n\n"
          "Prints format, processor, frames, rates, markers with their gaps, analog channels,\n"
          "force plates, events and import warnings. --json prints one JSON object (docs/cli.md).");
      return 0;
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError{"unknown option '" + arg + "'"};
    } else if (file.empty()) {
      file = arg;
    } else {
      throw UsageError{"one FILE only, got '" + file + "' and '" + arg + "'"};
    }
  }
  if (file.empty()) throw UsageError{"missing FILE"};
  const capture::Trial trial = capture::ReadTrial(file);
  const std::string report =
      json ? capture::FormatTrialInfoJson(trial) : capture::FormatTrialInfoText(trial);
  std::fputs(report.c_str(), stdout);
  return 0;
}

}  // namespace acro::app
