#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/detections.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/report/sync_report.h"
#include "acro/vision/sync.h"
#include "commands.h"

namespace acro::app {

namespace {

struct SyncArguments {
  std::string trial, calibration, camera, axes = "xyz", keypoints = "body25b", search = "-2:2", csv,
                                          plot;
  std::vector<std::string> videos, detections;
  double fps = 0.0, rate = 1.0;
};

// "CAM=PATH" → (CAM, PATH) when CAM names a camera of the calibration; else ("", the whole text).
std::pair<std::string, std::string> SplitCameraPath(const std::string& text,
                                                    const std::vector<vision::Camera>& cameras) {
  const size_t eq = text.find('=');
  if (eq != std::string::npos) {
    const std::string name = text.substr(0, eq);
    for (const vision::Camera& c : cameras)
      if (c.name == name) return {name, text.substr(eq + 1)};
  }
  return {"", text};
}

int RunSync(const SyncArguments& args) {
  const capture::Trial trial = capture::ReadTrial(args.trial);
  const std::vector<vision::Camera> cameras = vision::ReadCameras(args.calibration);
  vision::AutoSyncOptions options;
  options.axes = vision::ParseAxisMapping(args.axes);
  options.rate = args.rate;
  char end = 0;
  if (std::sscanf(
          args.search.c_str(), "%lf:%lf%c", &options.min_offset_s, &options.max_offset_s, &end) !=
      2)
    throw UsageError{"--search-s '" + args.search + "' is not MIN:MAX, e.g. -2:2"};
  DemandValidCommandLine(options);

  // The camera of an argument: its CAM= prefix, else --camera, else the only one.
  auto camera_of = [&](const std::string& prefix) -> const vision::Camera& {
    return vision::FindCamera(cameras, prefix.empty() ? args.camera : prefix, args.calibration);
  };
  std::vector<std::pair<const vision::Camera*, std::string>> videos;
  for (const std::string& v : args.videos) {
    const auto [name, path] = SplitCameraPath(v, cameras);
    videos.emplace_back(&camera_of(name), path);
  }

  vision::AutoSyncResult result;
  if (!args.detections.empty()) {
    std::deque<capture::KeypointDetections> detections;  // stable addresses
    std::vector<vision::CameraDetections> per_camera;
    for (const std::string& d : args.detections) {
      const auto [name, path] = SplitCameraPath(d, cameras);
      vision::CameraDetections c;
      c.camera = &camera_of(name);
      detections.push_back(capture::ReadDetections(path, args.keypoints, c.camera->name));
      c.detections = &detections.back();
      for (const std::string& w : c.detections->warnings)
        std::fprintf(stderr, "acrolab sync: warning: %s\n", w.c_str());
      for (const auto& [camera, video] : videos)
        if (camera == c.camera) c.frame_times_s = capture::VideoReader(video).frame_times_s();
      if (c.frame_times_s.empty()) {
        if (!(args.fps > 0))
          throw UsageError{"detections of " + c.camera->name +
                           " need the camera's --video (frame times) or --fps"};
        for (int k = 0; k < c.detections->num_frames(); ++k)
          c.frame_times_s.push_back(k / args.fps);
      }
      per_camera.push_back(std::move(c));
    }
    result = vision::SyncFromDetections(trial, per_camera, options);
  } else {
    if (videos.size() != 1)
      throw UsageError{"without --detections, give one --video to sync from its image motion"};
    capture::VideoReader video(videos[0].second, {.pixels = capture::VideoPixels::kGrey});
    std::string note;
    const vision::Camera camera = vision::FitCameraToVideo(
        *videos[0].first, video.info().width, video.info().height, videos[0].second, &note);
    if (!note.empty()) std::fprintf(stderr, "acrolab sync: warning: %s\n", note.c_str());
    options.progress = MakeCancellableProgress("image motion", "frames");
    result = vision::SyncFromImageMotion(trial, camera, video, options);
  }
  const double frame_s =
      result.offsets_s.size() > 1 ? result.offsets_s[1] - result.offsets_s[0] : 0.0;
  std::printf("sync from %s: offset %.4f s (%+.2f frames), rate %g\n",
              result.method.c_str(),
              result.sync.offset_s,
              frame_s > 0 ? result.sync.offset_s / frame_s : 0.0,
              result.sync.rate);
  std::printf("  cost %.4f at the offset (%s), next best %.4f two or more frames away; %d %s\n",
              result.cost,
              result.method == "detections" ? "mean px, truncated" : "1 − correlation",
              result.runner_up_cost,
              result.pairs,
              result.method == "detections" ? "point–detection pairs" : "frames");
  if (result.offsets_s.front() >= result.sync.offset_s - frame_s ||
      result.offsets_s.back() <= result.sync.offset_s + frame_s)
    std::printf("  warning: the offset is at the edge of --search-s %s: widen it\n",
                args.search.c_str());
  std::printf("use: --offset-s %.4f\n", result.sync.offset_s);
  if (!args.plot.empty()) {
    ui::WriteChart(ui::MakeSyncCostChart(result, frame_s), args.plot);
    std::printf("wrote %s\n", args.plot.c_str());
  }
  if (!args.csv.empty()) {
    std::string text = "offset_s,cost\n";
    for (size_t i = 0; i < result.offsets_s.size(); ++i)
      text += fmt::format("{:.6f},{:.6f}\n", result.offsets_s[i], result.costs[i]);
    WriteFileAtomically(args.csv, text);
    std::printf("wrote %s\n", args.csv.c_str());
  }
  return 0;
}

}  // namespace

void AddSyncCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<SyncArguments>();
  CLI::App* command = app.add_subcommand(
      "sync",
      "Finds the offset between a trial and its video(s), to a fraction of a frame: from 2D "
      "keypoint detections (OpenPose JSON) when given, else from the image motion inside the "
      "athlete's projected box. docs/sync.md.");
  command->add_option("TRIAL", args->trial, "markers or keypoints: C3D, TRC or CSV")->required();
  command->add_option("--calib", args->calibration, "cameras: .toml, .qca, OpenCV .yml/.xml")
      ->required();
  command->add_option(
      "--camera", args->camera, "the camera of a --video or --detections without CAM=");
  command->add_option("--video", args->videos, "[CAM=]FILE: a camera's video");
  command->add_option("--detections",
                      args->detections,
                      "[CAM=]DIR|FILE.csv: a camera's OpenPose JSON files, or a CSV of "
                      "frame,marker,u_px,v_px[,confidence] rows");
  command->add_option("--keypoints",
                      args->keypoints,
                      "the detections' keypoint set: body25, body25b (default), coco17, halpe26");
  command->add_option("--fps", args->fps, "frame rate of detections without a --video")
      ->check(CLI::Range(1.0, 10000.0));
  command->add_option(
      "--axes", args->axes, "how the trial's axes map to the lab's (zxy: Y-up TRC)");
  command->add_option(
      "--search-s", args->search, "offsets searched, MIN:MAX seconds (default -2:2)");
  command->add_option("--rate", args->rate, "video seconds per trial second (default 1)");
  command->add_option("--csv", args->csv, "write the cost at every offset searched");
  command->add_option(
      "--plot", args->plot, "draw the cost at every offset searched (.png or .svg)");
  command->callback([args, run] { *run = [args] { return RunSync(*args); }; });
}

}  // namespace acro::app
