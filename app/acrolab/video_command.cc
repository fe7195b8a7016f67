#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/video.h"
#include "acro/pipeline/video_flights.h"
#include "acro/report/flights_chart.h"
#include "acro/report/image.h"
#include "commands.h"

namespace acro::app {

namespace {

struct VideoInfoArguments {
  std::string file;
  bool json = false;
};

struct VideoFrameArguments {
  std::string file, out;
  std::optional<int> frame;
  std::optional<double> time_s;
};

struct VideoFlightsArguments {
  std::string file, out_dir, model = "heavy", bed_line;
  bool quiet = false;
};

int RunVideoFlights(const VideoFlightsArguments& args) {
  CheckOutputDirectory(args.out_dir);  // before any work: a bad -o costs nothing
  pipeline::VideoFlightsRequest request;
  request.video = args.file;
  request.model = pose::ParseLandmarkModel(args.model);
  if (!args.bed_line.empty()) request.bed_line = ParseBedLine(args.bed_line);
  pipeline::VideoFlights result;
  try {
    result = pipeline::FindFlightsInVideo(request, MakeStepProgress(args.quiet));
  } catch (const InputError& e) {
    // No bed in the first frame: say what to give instead.
    if (request.bed_line || std::string(e.what()).find(": bed: ") == std::string::npos) throw;
    throw InputError(
        "", "", std::string(e.what()) + "; give the bed's rest line: --bed-line Y0,SLOPE (px)");
  }
  const vision::ImageFlights& f = result.flights;
  for (const std::string& w : f.warnings)
    std::fprintf(stderr, "acrolab video flights: warning: %s\n", w.c_str());
  OutputTransaction outputs(args.out_dir);
  WriteFileAtomically(outputs.staging() / "flights.json",
                      pipeline::FormatVideoFlightsJson(result, args.file));
  if (f.sole_y_px.array().isFinite().any())
    ui::WriteChart(ui::MakeImageFlightsChart(f), outputs.staging() / "flights.png");
  outputs.Commit();
  std::printf("bed: %s (y = %.1f px %+.4f x)\n", f.bed.source.c_str(), f.bed.y0_px, f.bed.slope);
  int index = 0;
  for (const vision::ImageFlight& flight : f.flights) {
    ++index;
    if (flight.partial()) {
      std::printf("flight %d: partial (the video %s in the air)\n",
                  index,
                  flight.last_contact_frame < 0 ? "starts" : "ends");
      continue;
    }
    std::printf(
        "flight %d: take-off %.3f s, landing %.3f s, time of flight %.3f s (frames %d–%d; "
        "timed by the %s, the %s)\n",
        index,
        flight.takeoff_s,
        flight.landing_s,
        flight.time_of_flight_s(),
        flight.last_contact_frame,
        flight.first_contact_frame,
        flight.takeoff_method.c_str(),
        flight.landing_method.c_str());
  }
  std::printf("time of flight: %.3f s over the complete flights, T %.3f\n",
              f.TotalTimeOfFlight(),
              result.time_of_flight_score);
  std::printf("wrote %s/{flights.json,flights.png}\n", args.out_dir.c_str());
  return 0;
}

int RunVideoInfo(const VideoInfoArguments& args) {
  const capture::VideoReader reader(args.file);
  const std::string text = args.json ? capture::FormatVideoInfoJson(reader.info())
                                     : capture::FormatVideoInfoText(reader.info());
  std::fputs(text.c_str(), stdout);
  return 0;
}

int RunVideoFrame(const VideoFrameArguments& args) {
  capture::VideoReader reader(args.file);
  const double duration = reader.info().duration_s;
  if (args.time_s && !(*args.time_s >= 0 && *args.time_s <= duration))
    throw UsageError{
        fmt::format("--time {} s is outside the video's 0 … {:.3f} s", *args.time_s, duration)};
  const int index = args.frame ? *args.frame : reader.FrameAt(*args.time_s);
  const capture::VideoFrame frame = reader.Frame(index);
  ui::WriteRgbPng(frame.width, frame.height, frame.pixels, args.out);
  std::printf("frame %d at %.6f s (%d x %d) -> %s\n",
              frame.index,
              frame.time_s,
              frame.width,
              frame.height,
              args.out.c_str());
  return 0;
}

}  // namespace

void AddVideoCommand(CLI::App& app, CommandRunner* run) {
  CLI::App* video = app.add_subcommand(
      "video", "Video files: what they hold, and any frame as a picture (docs/formats/video.md).");
  video->require_subcommand(1);

  auto info = std::make_shared<VideoInfoArguments>();
  CLI::App* info_command = video->add_subcommand(
      "info",
      "Container, codec, display size and rotation, exact frame count from the packet index, "
      "average and declared frame rate and whether it varies, duration, start time, keyframes, "
      "audio tracks.");
  info_command->add_option("FILE", info->file, "the video")->required();
  info_command->add_flag("--json", info->json, "print one JSON object (docs/cli.md)");
  info_command->callback([info, run] { *run = [info] { return RunVideoInfo(*info); }; });

  auto frame = std::make_shared<VideoFrameArguments>();
  CLI::App* frame_command = video->add_subcommand(
      "frame", "One frame as a PNG, upright (a phone's rotation applied), decoded exactly.");
  frame_command->add_option("FILE", frame->file, "the video")->required();
  CLI::Option* index =
      frame_command->add_option("--frame", frame->frame, "frame index, 0-based, presentation order")
          ->check(CLI::NonNegativeNumber);
  CLI::Option* time = frame_command->add_option(
      "--time", frame->time_s, "seconds from the first frame: the frame shown then");
  index->excludes(time);
  frame_command->add_option("-o,--output", frame->out, "the PNG to write")->required();
  auto flights = std::make_shared<VideoFlightsArguments>();
  CLI::App* flights_command = video->add_subcommand(
      "flights",
      "Every jump's take-off, landing and time of flight from the picture alone (one camera "
      "beside the trampoline, no calibration): the athlete detected, the soles against the bed's "
      "rest line found in the first frame, each crossing timed from the flight's arc. Writes "
      "DIR/flights.json and DIR/flights.png. docs/one-camera.md.");
  flights_command->add_option("VIDEO", flights->file, "the video")
      ->required()
      ->check(CLI::ExistingFile);
  flights_command->add_option("-o,--output", flights->out_dir, "the output directory")->required();
  flights_command->add_option(
      "--model", flights->model, "the detector: lite, full or heavy (default)");
  flights_command->add_option(
      "--bed-line",
      flights->bed_line,
      "Y0,SLOPE: the bed's rest line in the picture, y = Y0 + SLOPE·x (px), when the bed is not "
      "found in the first frame");
  flights_command->add_flag("--quiet", flights->quiet, "no progress on stderr");
  flights_command->callback(
      [flights, run] { *run = [flights] { return RunVideoFlights(*flights); }; });

  frame_command->callback([frame, run] {
    if (!frame->frame && !frame->time_s)
      throw CLI::ValidationError("--frame or --time", "give one");
    *run = [frame] { return RunVideoFrame(*frame); };
  });
}

}  // namespace acro::app
