// The hall's loop (#42, docs/live.md): what one live camera costs per frame. The goal: a 1080p
// camera at 60 fps watched on one of the two cores with room left for the recording and the
// routines' analysis — decoding, scaling and watching a frame in well under its 16.7 ms.
// The counter "fps": frames a second one core gets through.
//   BM_DecodeAndScale: capture::LiveSource reading the sample's side video (1080p, 30 fps) as fast
//     as it decodes, one decoder thread, recorded to MPEG-TS: per frame, the frame handed out RGB
//     at 640 px.
//   BM_WebcamMjpeg: the same for a webcam's MJPEG (the side video as MJPEG, 1080p, made once by
//     the ffmpeg command): decoded, handed out, and encoded as H.264 for the recording (x264
//     ultrafast, one thread) — what a USB webcam costs. Goal: a 1080p webcam at 30 fps in at
//     most half a core, ≤ 16.7 ms a frame.
//   BM_WatchFrame: vision::MotionFlightWatcher on those frames (the background's rebuilds every
//     ~0.4 s of stream included): per frame.

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "acro/capture/live_source.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/motion_flights.h"
#include "refdata.h"

namespace {

using namespace acro;

std::filesystem::path SideVideo() {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4";
}

// `video` read by capture::LiveSource as fast as it decodes, recorded, each timed run in a fresh
// folder; the counter "fps": frames a second.
void ReadLive(benchmark::State& state, const std::filesystem::path& video) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "acrolab_live_bench";
  long long frames = 0;
  int run = 0;
  for (auto _ : state) {
    std::filesystem::remove_all(dir);
    capture::LiveSourceOptions options;
    options.pace_files = false;
    options.record_prefix = dir / ("run" + std::to_string(run++));
    capture::LiveSource source(video.string(), options);
    capture::LiveFrame frame;
    while (source.Next(&frame)) ++frames;
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}

void BM_DecodeAndScale(benchmark::State& state) {
  ReadLive(state, SideVideo());
}
BENCHMARK(BM_DecodeAndScale)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_WebcamMjpeg(benchmark::State& state) {
  const std::filesystem::path mjpeg =
      std::filesystem::temp_directory_path() / "acrolab_live_bench_webcam.avi";
  if (!std::filesystem::exists(mjpeg)) {
    // (made under another name and renamed whole: an interrupted run leaves no half file)
    const std::filesystem::path part = mjpeg.string() + ".part.avi";
    const std::string make = "ffmpeg -v error -y -i '" + SideVideo().string() +
                             "' -an -c:v mjpeg -q:v 3 '" + part.string() + "' && mv '" +
                             part.string() + "' '" + mjpeg.string() + "'";
    if (std::system(make.c_str()) != 0) {
      state.SkipWithError("the MJPEG input could not be made (is ffmpeg installed?)");
      return;
    }
  }
  ReadLive(state, mjpeg);
}
BENCHMARK(BM_WebcamMjpeg)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_WatchFrame(benchmark::State& state) {
  static const std::vector<capture::LiveFrame> frames = [] {
    std::vector<capture::LiveFrame> out;
    capture::LiveSourceOptions options;
    options.pace_files = false;
    capture::LiveSource source(SideVideo().string(), options);
    capture::LiveFrame f;
    while (source.Next(&f)) out.push_back(f);
    return out;
  }();
  const vision::BedDetection bed = vision::DetectBed(SideVideo(), 0);
  long long n = 0, jumps = 0;
  for (auto _ : state) {
    vision::MotionFlightWatcher watcher(bed);
    for (const capture::LiveFrame& f : frames) jumps += watcher.Add(f.picture, f.arrival_s).size();
    n += static_cast<long long>(frames.size());
  }
  state.counters["jumps"] = static_cast<double>(jumps) / state.iterations();
  state.counters["fps"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WatchFrame)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
