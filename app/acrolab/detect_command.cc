// acrolab detect VIDEO… [--model lite|full|heavy] [--roi auto|bed|X,Y,W,H] [--frames A:B] [-j N]
// -o DIR: the athlete's 2D keypoints in every frame (docs/pose.md).

#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/parallel.h"
#include "acro/pipeline/detect.h"
#include "acro/pose/keypoints.h"
#include "acro/pose/video_poses.h"
#include "acro/report/pose_sheet.h"
#include "commands.h"

namespace acro::app {
namespace {

struct DetectArguments {
  std::vector<std::string> videos;
  std::string model = "heavy", roi = "auto", frames, sheet_frames, out_dir;
  int threads = 0;
  bool json = false, quiet = false, restart = false;
};

// --frames A:B (B exclusive; either side may be left out).
void ParseFrames(const std::string& text, pose::DetectVideoOptions* options) {
  if (text.empty()) return;
  const auto colon = text.find(':');
  int first = 0, end = -1;
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    if (colon > 0) first = std::stoi(text.substr(0, colon));
    if (colon + 1 < text.size()) end = std::stoi(text.substr(colon + 1));
  } catch (const std::exception&) {
    throw UsageError{fmt::format("--frames {}: expected A:B (frames A to B − 1)", text)};
  }
  if (first < 0 || (end >= 0 && end <= first))
    throw UsageError{fmt::format("--frames {}: not a range A:B with 0 ≤ A < B", text)};
  options->first_frame = first;
  options->end_frame = end;
}

// contact_sheet.png: up to 24 frames spread evenly over --sheet-frames (default: those detected),
// each with its skeleton, cropped around the athlete's path.
void WriteContactSheet(const pose::VideoPoses& r,
                       const std::string& sheet_frames,
                       const std::filesystem::path& dir) {
  pose::DetectVideoOptions range;
  range.first_frame = r.first_frame;
  range.end_frame = r.end_frame;
  ParseFrames(sheet_frames, &range);
  const int first = std::max(range.first_frame, r.first_frame);
  const int end = std::min(range.end_frame < 0 ? r.end_frame : range.end_frame, r.end_frame);
  if (end <= first)
    throw UsageError{fmt::format("--sheet-frames {} outside the frames detected", sheet_frames)};
  const int count = std::min(24, end - first);
  std::vector<int> frames;
  std::vector<capture::DetectedPerson> people;
  for (int k = 0; k < count; ++k) {
    const int f =
        first + static_cast<int>(std::lround(k * (end - first - 1) / std::max(1.0, count - 1.0)));
    frames.push_back(f);
    people.push_back(r.frames[f - r.first_frame].keypoints);
  }
  capture::VideoReader reader(r.video);
  ui::WritePoseContactSheet(reader,
                            frames,
                            people,
                            pose::BlazePoseEdges(),
                            pose::BlazePoseSides(),
                            dir / "contact_sheet.png");
}

// The tracker's region for one video: --roi X,Y,W,H, bed (found in the first frame detected), or
// auto (the bed when one is found, else none).
void ChooseRegion(const DetectArguments& args,
                  const std::string& video,
                  pose::DetectVideoOptions* options) {
  if (args.roi == "auto" || args.roi == "bed") {
    pipeline::RegionFromBed(video, options->first_frame, args.roi == "bed", &options->tracker);
    return;
  }
  const Eigen::VectorXd box = ParseCommaNumbers("--roi", args.roi, 4, "auto, bed or X,Y,W,H");
  options->tracker.box_px = Eigen::AlignedBox2d(box.head<2>(), box.head<2>() + box.tail<2>());
}

int RunDetect(const DetectArguments& args) {
  pose::DetectVideoOptions base;
  base.tracker.model = pose::ParseLandmarkModel(args.model);
  base.resume = !args.restart;
  ParseFrames(args.frames, &base);
  DemandValidCommandLine(base);
  CheckOutputDirectory(args.out_dir);
  // The networks are checked before any video is read: a missing model is said at once.
  pose::FindPoseModels(base.tracker.model);

  // Videos side by side, one thread each; the networks' own threads share what is left.
  const int workers = WorkerThreads(args.threads);
  const int at_once = std::min<int>(workers, static_cast<int>(args.videos.size()));
  pose::SetNetworkThreads(std::max(1, workers / at_once));

  // Every video read and every region checked before anything is written.
  std::vector<pose::DetectVideoOptions> options(args.videos.size(), base);
  for (std::size_t v = 0; v < args.videos.size(); ++v) {
    const capture::VideoInfo info = capture::VideoReader(args.videos[v]).info();
    if (base.first_frame >= info.num_frames || base.end_frame > info.num_frames)
      throw InputError(args.videos[v],
                       "--frames",
                       fmt::format("{} outside the video's {} frames (0:{})",
                                   args.frames,
                                   info.num_frames,
                                   info.num_frames));
    ChooseRegion(args, args.videos[v], &options[v]);
    const Eigen::AlignedBox2d frame(Eigen::Vector2d::Zero(),
                                    Eigen::Vector2d(info.width, info.height));
    if (options[v].tracker.box_px && !frame.contains(*options[v].tracker.box_px))
      throw InputError(
          args.videos[v],
          "--roi",
          fmt::format("{} is not inside the {}×{} frame", args.roi, info.width, info.height));
  }
  CreateOutputDirectory(args.out_dir);

  // One progress bar over every video's frames.
  std::mutex mutex;
  std::vector<int> done(args.videos.size(), 0), total(args.videos.size(), 0);
  const auto bar = MakeProgressBar("detect", "frames");
  std::vector<pose::VideoPoses> results(args.videos.size());
  ParallelFor(static_cast<int>(args.videos.size()), at_once, [&](int v) {
    Progress progress;
    progress.report = [&, v](const std::string&, int d, int t) {
      std::lock_guard<std::mutex> lock(mutex);
      done[v] = d;
      total[v] = t;
      int sum_done = 0, sum_total = 0;
      for (std::size_t k = 0; k < done.size(); ++k) {
        sum_done += done[k];
        sum_total += total[k];
      }
      if (!args.quiet && sum_total > 0) bar(sum_done, sum_total);
      return true;
    };
    const std::filesystem::path video = args.videos[v];
    const std::filesystem::path dir = pose::VideoOutputDirectory(args.out_dir, video);
    results[v] = pose::DetectVideoPoses(video, dir, options[v], progress);
    WriteContactSheet(results[v], args.sheet_frames, dir);
  });

  std::string json = "[\n";
  for (std::size_t v = 0; v < results.size(); ++v) {
    const pose::VideoPoses& r = results[v];
    for (const std::string& warning : r.warnings)
      std::fprintf(stderr, "acrolab detect: warning: %s\n", warning.c_str());
    if (args.json) {
      json += pose::FormatVideoPosesJson(r, options[v]) + (v + 1 < results.size() ? ",\n" : "");
      continue;
    }
    const int run = static_cast<int>(r.frames.size()) - r.frames_resumed;
    std::printf(
        "%s: %zu frames (%d resumed), %d with a pose, median confidence %.2f, %.0f ms per frame -> "
        "%s\n",
        r.video.string().c_str(),
        r.frames.size(),
        r.frames_resumed,
        r.frames_with_pose(),
        r.median_confidence(),
        run > 0 ? 1000.0 * r.elapsed_s / run : 0.0,
        pose::VideoOutputDirectory(args.out_dir, r.video).string().c_str());
  }
  if (args.json) std::printf("%s]\n", json.c_str());
  return 0;
}

}  // namespace

void AddDetectCommand(CLI::App& app, CommandRunner* run) {
  auto args = std::make_shared<DetectArguments>();
  CLI::App* command = app.add_subcommand(
      "detect",
      "The athlete's 2D keypoints in every frame of each video, with Acrolab's own BlazePose "
      "detector and tracking (docs/pose.md): OpenPose JSON per frame, a 2D TRC and a CSV per "
      "video. Resumes an interrupted run.");
  command->add_option("VIDEO", args->videos, "the videos")->required();
  command
      ->add_option(
          "--model", args->model, "lite, full or heavy (default: heavy, the most accurate)")
      ->check(CLI::IsMember({"lite", "full", "heavy"}));
  command->add_option("--roi",
                      args->roi,
                      "where the athlete is: auto (the trampoline's bed when found, else the whole "
                      "frame), bed (the bed must be found), or a box X,Y,W,H in pixels");
  command->add_option("--frames", args->frames, "frames A:B (A to B − 1; default: all)")
      ->check(kNotEmpty);
  command
      ->add_option("--sheet-frames",
                   args->sheet_frames,
                   "the frames A:B whose skeletons contact_sheet.png shows (up to 24 of them)")
      ->check(kNotEmpty);
  command->add_option("-j,--threads", args->threads, "threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("-o,--output", args->out_dir, "output folder (one folder per video)")
      ->required();
  command->add_flag("--json", args->json, "print a JSON summary per video");
  command->add_flag("--restart", args->restart, "ignore an earlier run's frames");
  command->add_flag("--quiet", args->quiet, "no progress bar");
  command->callback([args, run] { *run = [args] { return RunDetect(*args); }; });
}

}  // namespace acro::app
