#include <cstdio>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acro/capture/video.h"
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
    throw UsageError{fmt::format("--time {} s is outside the video's 0 … {:.3f} s", *args.time_s, duration)};
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
  frame_command->callback([frame, run] {
    if (!frame->frame && !frame->time_s)
      throw CLI::ValidationError("--frame or --time", "give one");
    *run = [frame] { return RunVideoFrame(*frame); };
  });
}

}  // namespace acro::app
