#include <cstdio>
#include <memory>

#include "acro/base/input_error.h"
#include "acro/capture/trial_io.h"
#include "commands.h"

namespace acro::app {

namespace {

struct ConvertArguments {
  std::string in, out;
};

int RunConvert(const ConvertArguments& args) {
  const capture::Trial trial = capture::ReadTrial(args.in);
  for (const std::string& warning : trial.warnings)
    std::fprintf(stderr, "acrolab convert: warning: %s\n", warning.c_str());
  if (trial.num_frames < 1)
    throw InputError(args.in, "", "the trial has no frame; convert needs 1 at least");
  capture::WriteTrial(trial, args.out);
  std::printf("%s -> %s: %d frames, %d points\n",
              args.in.c_str(),
              args.out.c_str(),
              trial.num_frames,
              trial.num_points());
  return 0;
}

}  // namespace

void AddConvertCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<ConvertArguments>();
  CLI::App* command = app.add_subcommand(
      "convert",
      "Converts a trial between C3D (.c3d, written as Intel float), TRC (.trc, mm) and Acrolab's "
      "marker CSV (.csv, m), chosen by the file extensions. The output is written completely or "
      "not at all.");
  command->add_option("IN", args->in, "the trial to read")->required();
  command->add_option("OUT", args->out, "the file to write")->required();
  command->callback([args, run] { *run = [args] { return RunConvert(*args); }; });
}

}  // namespace acro::app
