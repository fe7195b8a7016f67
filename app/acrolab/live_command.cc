// acrolab live SOURCE… -o DIR [--duration S] [--rest S] [--open-timeout S] [--stall-timeout S]
// [--segment S] [--as-fast-as-decoded]: live cameras and streams recorded, every jump's line as it
// lands, every routine cut into its own folder (docs/live.md).

#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include "acro/base/process.h"
#include "acro/base/text.h"
#include "acro/pipeline/live.h"
#include "acro/pipeline/live_analyses.h"
#include "commands.h"

namespace acro::app {
namespace {

struct LiveArguments {
  std::vector<std::string> sources;
  std::string out_dir;
  double duration_s = 0, rest_s = 1.5, open_timeout_s = 10, stall_timeout_s = 5, segment_s = 60,
         reconnect_s = 30;
  bool unpaced = false, quiet = false, no_analysis = false;
  std::string analysis_model = "heavy";
  std::string athlete, library;    // each routine analysed for the athlete, stored in the library
  std::string intrinsics, camera;  // the cameras' intrinsics (their poses from the bed)
};

int RunLiveCommand(const LiveArguments& args) {
  pipeline::LiveRequest request;
  request.sources = args.sources;
  request.out_dir = args.out_dir;
  request.rest_s = args.rest_s;
  request.source.open_timeout_s = args.open_timeout_s;
  request.source.stall_timeout_s = args.stall_timeout_s;
  request.source.segment_s = args.segment_s;
  request.reconnect_s = args.reconnect_s;
  request.source.pace_files = !args.unpaced;
  request.intrinsics = args.intrinsics;
  request.camera = args.camera;
  if (args.duration_s > 0) request.duration_s = args.duration_s;
  std::mutex print;
  const auto line = [&print](const std::string& text) {
    const std::lock_guard<std::mutex> lock(print);
    std::printf("%s\n", EscapeForTerminal(text).c_str());
    std::fflush(stdout);
  };
  request.on_line = line;
  std::string why;
  if (!request.IsValid(&why)) throw UsageError{why};
  if (!args.library.empty() && args.athlete.empty())
    throw UsageError{"--library stores each routine under an athlete: give --athlete A.yaml"};
  if (args.no_analysis && (!args.library.empty() || !args.athlete.empty()))
    throw UsageError{
        "--athlete and --library are for each routine's analysis: not with "
        "--no-analysis"};
  if (!args.camera.empty() && args.intrinsics.empty())
    throw UsageError{"--camera names a camera of --intrinsics: give --intrinsics C"};
  std::optional<pipeline::RoutineAnalysisQueue> analyses;
  if (!args.no_analysis) {
    pipeline::RoutineAnalysisOptions o;
    o.acrolab = CurrentExecutable();
    o.model = args.analysis_model;
    o.athlete = args.athlete;
    o.library = args.library;
    o.intrinsics = args.intrinsics;
    o.camera = args.camera;
    o.on_line = line;
    analyses.emplace(o);
    request.on_routine = [&analyses](const pipeline::LiveRoutine& r) { analyses->Add(r); };
  }
  const pipeline::LiveSummary summary = pipeline::RunLive(request);
  analyses.reset();  // the routines' analyses finished
  int failed = 0;
  for (const pipeline::LiveSourceSummary& s : summary.sources)
    if (!s.failure.empty()) ++failed;
  if (!args.quiet)
    std::printf(
        "%zu jump%s, %zu routine%s: %s\n",
        summary.jumps.size(),
        summary.jumps.size() == 1 ? "" : "s",
        summary.routines.size(),
        summary.routines.size() == 1 ? "" : "s",
        EscapeForTerminal((std::filesystem::path(args.out_dir) / "live.json").string()).c_str());
  // Every source refused: nothing was recorded, which is a failure; some refused: said in their
  // lines, the others' recordings kept.
  return failed == static_cast<int>(summary.sources.size()) ? 1 : 0;
}

}  // namespace

void AddLiveCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<LiveArguments>();
  CLI::App* command = app.add_subcommand(
      "live",
      "Live cameras and streams (V4L2 devices, udp://, rtsp://, srt://, … or a file played at its "
      "own pace) recorded frame-exact, every jump's time of flight and landing zone printed as "
      "it lands (jumps.jsonl), every routine cut into its own folder with its clip "
      "(docs/live.md). Stops when the sources end, after --duration, or on Ctrl-C (what was "
      "recorded is kept).");
  command->add_option("SOURCE", args->sources, "cameras, stream URLs or files")->required();
  command->add_option("-o,--output", args->out_dir, "a new or empty output folder")
      ->required()
      ->check(kNotEmpty);
  command->add_option("--duration", args->duration_s, "stop after this many seconds")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--rest",
                   args->rest_s,
                   "a routine ends when the athlete stays on the bed this long (s, default 1.5)")
      ->check(CLI::Range(0.1, 59.0));
  command
      ->add_option("--open-timeout",
                   args->open_timeout_s,
                   "a source that sends nothing this long is refused (s, default 10)")
      ->check(CLI::Range(0.1, 3600.0));
  command
      ->add_option("--stall-timeout",
                   args->stall_timeout_s,
                   "a source that stops sending this long has ended (s, default 5)")
      ->check(CLI::Range(0.1, 3600.0));
  command
      ->add_option("--reconnect",
                   args->reconnect_s,
                   "a stream or camera that stopped is waited for this long to come back (s, "
                   "default 30; 0: its stop is its end)")
      ->check(CLI::Range(0.0, 3600.0));
  command
      ->add_option("--segment",
                   args->segment_s,
                   "the recording starts a new file after this many seconds (default 60)")
      ->check(CLI::Range(1.0, 86400.0));
  command->add_flag("--as-fast-as-decoded",
                    args->unpaced,
                    "read files as fast as they decode instead of at their own pace");
  command
      ->add_option("--analysis-model",
                   args->analysis_model,
                   "the detector of each routine's analysis: heavy (default, the most accurate), "
                   "full (about 3× faster; on the sample its time of flight came 0.38 s longer) "
                   "or lite (docs/live.md)")
      ->check(CLI::IsMember({"lite", "full", "heavy"}));
  command
      ->add_option("--athlete",
                   args->athlete,
                   "the athlete jumping (their profile, YAML): each routine analysed for them")
      ->check(CLI::ExistingFile);
  command->add_option(
      "--library",
      args->library,
      "store each routine's analysis in this season library under --athlete (docs/library.md)");
  command
      ->add_option("--intrinsics",
                   args->intrinsics,
                   "the cameras' intrinsics (a calibration in any format, e.g. calibrate "
                   "intrinsics' from a checkerboard): focal length and distortion known, the pose "
                   "found on the bed; without it the focal length is estimated from the bed too")
      ->check(CLI::ExistingFile);
  command->add_option(
      "--camera", args->camera, "which camera of --intrinsics (when it has several)");
  command->add_flag("--no-analysis",
                    args->no_analysis,
                    "cut routines but do not analyse them (`acrolab analyze --video clip.ts "
                    "--detect-bed` each, one after the other, as they end)");
  command->add_flag("--quiet", args->quiet, "no summary line");
  command->callback([args, run] { *run = [args] { return RunLiveCommand(*args); }; });
}

}  // namespace acro::app
