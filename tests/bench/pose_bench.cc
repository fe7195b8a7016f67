// The detector's speed (docs/performance.md, "Pose detection"; issue #38's goals: full ≤ 50 ms
// and heavy ≤ 130 ms per 1080p frame on one core). One iteration is one frame of the sample
// routine's 1080p side video, decoded and tracked (the athlete followed: one landmark run, the
// person detector only when the track is lost); counters give the time per frame of each share —
// decode, crop, network, post-processing. /1: OpenCV's DNN on one thread; /2: on two (the
// decoder is on the calling thread here, so the per-frame figure is the sum of both).

#include <benchmark/benchmark.h>

#include <chrono>

#include "acro/capture/video.h"
#include "acro/pose/pose_tracker.h"
#include "acro/pose/video_poses.h"
#include "refdata.h"

namespace {

void BM_PoseFrame1080p(benchmark::State& state) {
  using namespace acro;
  const auto model = static_cast<pose::LandmarkModel>(state.range(0));
  pose::SetNetworkThreads(static_cast<int>(state.range(1)));
  const auto path = acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";
  capture::VideoReaderOptions options;
  options.num_threads = 1;
  capture::VideoReader video(path, options);
  pose::PoseTrackerOptions tracking;
  tracking.model = model;
  pose::PoseTracker tracker(tracking);
  // Warm up: find the athlete (frames 0–9, not timed).
  capture::VideoFrame frame;
  for (int k = 0; k < 10; ++k) {
    video.ReadNext(&frame);
    tracker.Track(frame);
  }
  const pose::PoseTiming before = tracker.timing();
  double decode_s = 0.0;
  int frames = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!video.ReadNext(&frame)) {
      state.PauseTiming();
      frame = video.Frame(10);
      state.ResumeTiming();
    }
    decode_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    benchmark::DoNotOptimize(tracker.Track(frame));
    ++frames;
  }
  const pose::PoseTiming& after = tracker.timing();
  state.counters["decode_ms"] = 1000.0 * decode_s / frames;
  state.counters["crop_ms"] = 1000.0 * (after.crop_s - before.crop_s) / frames;
  state.counters["network_ms"] = 1000.0 * (after.network_s - before.network_s) / frames;
  state.counters["post_ms"] = 1000.0 * (after.post_s - before.post_s) / frames;
  state.counters["landmark_runs"] = static_cast<double>(after.landmark_runs - before.landmark_runs) / frames;
  state.SetLabel(pose::LandmarkModelName(model));
}
BENCHMARK(BM_PoseFrame1080p)
    ->ArgsProduct({{0, 1, 2}, {1, 2}})
    ->ArgNames({"model", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(60)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
