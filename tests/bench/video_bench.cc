// Video decoding against the ffmpeg command line, in the same run (docs/performance.md, "Video"):
// a sequential pass over the Pose2Sim H.264 and VP9 files and over a 10 s 1080p 30 fps H.264 file
// this benchmark writes once (4 s groups of pictures), by our reader (RGB frames) and by
// `ffmpeg -threads N -i X -f null -` (decode only) and `… -pix_fmt rgb24 -f null -` (decode and
// the same colour conversion); and random access to a frame 2 s after a keyframe at 1080p, by our
// reader and by `ffmpeg -ss`.
// Run: build/bench/video_bench --benchmark_repetitions=5 (the ffmpeg command must be installed).

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "acro/capture/video.h"
#include "bench_video.h"
#include "refdata.h"

namespace {

namespace fs = std::filesystem;
constexpr int kThreads = 2;

fs::path File(int which) {
  if (which == 0) return acro::testing::RefdataFile("pose2sim-demo/videos/cam01.mp4");
  if (which == 1) return acro::testing::RefdataFile("pose2sim-demo/videos/cam02.mp4");
  return acro::testing::Generated1080pVideo();
}

const char* kNames[] = {"pose2sim_h264_1080x1920", "pose2sim_vp9_1080x1920", "h264_1920x1080"};

// Our reader: every frame in order, to RGB (second argument 0) or to grey (1: luma only, what
// calibration and the image-motion sync read).
void BM_DecodeSequential(benchmark::State& state) {
  const fs::path path = File(static_cast<int>(state.range(0)));
  if (path.empty() || !fs::exists(path)) {
    state.SkipWithError("input missing");
    return;
  }
  int frames = 0;
  for (auto _ : state) {
    const auto pixels =
        state.range(1) ? acro::capture::VideoPixels::kGrey : acro::capture::VideoPixels::kRgb;
    acro::capture::VideoReader reader(path, {.num_threads = kThreads, .pixels = pixels});
    acro::capture::VideoFrame frame;
    frames = 0;
    while (reader.ReadNext(&frame)) ++frames;
  }
  state.SetLabel(std::string(kNames[state.range(0)]) + (state.range(1) ? " grey" : " rgb"));
  state.counters["fps"] = benchmark::Counter(static_cast<double>(frames),
                                             benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DecodeSequential)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The command line on the same file and threads: decode only (range 1 = 0) or with the RGB
// conversion (1).
void BM_FfmpegCommand(benchmark::State& state) {
  const fs::path path = File(static_cast<int>(state.range(0)));
  if (path.empty() || !fs::exists(path)) {
    state.SkipWithError("input missing");
    return;
  }
  const std::string command = "ffmpeg -v error -threads " + std::to_string(kThreads) + " -i '" +
                              path.string() + "' " + (state.range(1) ? "-pix_fmt rgb24 " : "") +
                              "-f null - 2>/dev/null";
  const int frames = acro::capture::VideoReader(path).num_frames();
  for (auto _ : state) {
    if (std::system(command.c_str()) != 0) state.SkipWithError("ffmpeg failed");
  }
  state.SetLabel(std::string(kNames[state.range(0)]) +
                 (state.range(1) ? " rgb24" : " decode only"));
  state.counters["fps"] = benchmark::Counter(static_cast<double>(frames),
                                             benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FfmpegCommand)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Random access at 1080p: frame 60 (2 s after the keyframe at 0) from a reader positioned
// elsewhere (frame 200, the next group), so that every access seeks and decodes 61 frames.
void BM_RandomAccess2sAfterKeyframe1080p(benchmark::State& state) {
  const fs::path& path = acro::testing::Generated1080pVideo();
  if (path.empty()) {
    state.SkipWithError("could not write the 1080p file");
    return;
  }
  acro::capture::VideoReader reader(path, {.num_threads = kThreads});
  for (auto _ : state) {
    state.PauseTiming();
    reader.Frame(200);
    state.ResumeTiming();
    benchmark::DoNotOptimize(reader.Frame(60).pixels.data());
  }
}
BENCHMARK(BM_RandomAccess2sAfterKeyframe1080p)->Unit(benchmark::kMillisecond)->UseRealTime();

// The command line's random access to the same frame: `ffmpeg -ss T -i X -frames:v 1` with T the
// frame's time (range 60: 2 s) or 0 (range 0: the keyframe itself). The difference of the two is
// what the command line spends getting from the keyframe to the frame (its accurate seek decodes
// every frame on the way); its start-up and the first frame are in both.
void BM_FfmpegRandomAccess1080p(benchmark::State& state) {
  const fs::path& path = acro::testing::Generated1080pVideo();
  if (path.empty()) {
    state.SkipWithError("could not write the 1080p file");
    return;
  }
  const int frame = static_cast<int>(state.range(0));
  const std::string command = "ffmpeg -v error -threads " + std::to_string(kThreads) + " -ss " +
                              std::to_string(frame / 30.0) + " -i '" + path.string() +
                              "' -frames:v 1 -f null - 2>/dev/null";
  for (auto _ : state) {
    if (std::system(command.c_str()) != 0) state.SkipWithError("ffmpeg failed");
  }
  state.SetLabel("frame " + std::to_string(frame));
}
BENCHMARK(BM_FfmpegRandomAccess1080p)
    ->Arg(0)
    ->Arg(60)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
