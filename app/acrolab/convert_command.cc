#include <cstdio>

#include "acro/capture/trial_io.h"
#include "commands.h"

namespace acro::app {

int RunConvert(const std::vector<std::string>& args) {
  if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
    std::puts(
        "usage: acrolab convert IN OUT\n\n"
        "Converts a trial between C3D (.c3d, written as Intel float), TRC (.trc, mm) and "
        "Acrolab's\n"
        "marker CSV (.csv, m), chosen by the file extensions. The output is written completely or\n"
        "not at all.");
    return 0;
  }
  if (args.size() != 2) throw UsageError{"expected IN and OUT"};
  const capture::Trial trial = capture::ReadTrial(args[0]);
  capture::WriteTrial(trial, args[1]);
  for (const std::string& warning : trial.warnings)
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
  std::printf("%s -> %s: %d frames, %d points\n",
              args[0].c_str(),
              args[1].c_str(),
              trial.num_frames,
              trial.num_points());
  return 0;
}

}  // namespace acro::app
