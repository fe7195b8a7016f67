// The overlay pipeline (docs/performance.md, "Overlay"): 10 s of 1080p 30 fps H.264 (the file
// video_bench writes, ffmpeg's testsrc2), the sample routine's athlete drawn over it through a
// 1920 × 1080 camera with lens distortion 10 m beside the trampoline: decode + pose + render +
// read-back + composite + encode (H.264, x264 superfast, as `acrolab overlay`), with the skeleton
// and with the mesh. The goal (issue "virtual against real"): ≥ 1.5× real time with the
// skeleton, ≥ 0.5× with the mesh, on the 2-core machine. Counters: realtime (video seconds per
// wall second) and the split per frame in ms.
// Run: build/bench/overlay_bench --benchmark_repetitions=3 (needs the ffmpeg command for the input
// and Xvfb or a display).

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/body_mesh.h"
#include "acro/capture/trial_io.h"
#include "acro/capture/video.h"
#include "acro/scene/silhouette_check.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/display.h"
#include "acro/views/scene_overlay.h"
#include "acro/vision/silhouette.h"
#include "bench_video.h"
#include "refdata.h"

namespace {

namespace fs = std::filesystem;

struct Routine {
  acro::capture::Trial trial;
  acro::analysis::AthleteBody body;
  acro::analysis::TrialAnalysis analysis;
  acro::vision::Camera camera;
};

const Routine& SampleRoutine() {
  static const Routine routine = [] {
    const fs::path source = acro::testing::SourceDir();
    Routine r;
    r.trial = acro::capture::ReadTrial(source /
                                       "samples/trials/trampoline_routine/trampoline_routine.c3d");
    r.body = acro::analysis::MakeAthleteBody(
        acro::analysis::ReadAthleteProfile(source / "samples/athletes/sample_athlete.yaml"));
    r.analysis = acro::analysis::AnalyzeTrial(r.trial, nullptr, r.body);
    // 10 m beside the bed's centre (across its long axis), 2 m up, looking level at 2 m.
    const Eigen::Vector3d target =
        r.analysis.check.frames.com_W.rowwise().mean() + Eigen::Vector3d(0, 0, 0.5);
    const Eigen::Vector3d centre = target - Eigen::Vector3d(0, 10, 0);
    acro::vision::Camera& c = r.camera;
    c.name = "side";
    c.width_px = 1920;
    c.height_px = 1080;
    c.K << 1400, 0, 955.3, 0, 1398, 541.7, 0, 0, 1;
    c.distortion = {-0.08, 0.02, 0.0005, -0.0003};
    Eigen::Matrix3d R_WK;  // camera axes in W: x right (+x), y down, z forward (+y)
    R_WK.col(0) = Eigen::Vector3d::UnitX();
    R_WK.col(1) = -Eigen::Vector3d::UnitZ();
    R_WK.col(2) = Eigen::Vector3d::UnitY();
    c.R_KW = R_WK.transpose();
    c.t_KW = -c.R_KW * centre;
    return r;
  }();
  return routine;
}

void BM_Overlay(benchmark::State& state, const char* show) {
  const fs::path video_path = acro::testing::Generated1080pVideo();
  if (video_path.empty() || !fs::exists(video_path)) {
    state.SkipWithError("the input video could not be made (is ffmpeg installed?)");
    return;
  }
  const Routine& routine = SampleRoutine();
  const acro::ui::XDisplay display;
  const fs::path out = fs::temp_directory_path() / "acrolab_overlay_bench.mp4";
  acro::ui::OverlayTiming t;
  int triangles = 0;
  for (auto _ : state) {
    acro::analysis::TrialScene scene(routine.trial,
                                     routine.analysis,
                                     routine.body,
                                     acro::analysis::MakeEllipsoidBodyMesh(
                                         routine.body, acro::analysis::OverlayBodyMeshOptions()));
    acro::capture::VideoReader video(video_path);
    acro::ui::SceneOverlayOptions options;
    options.show = acro::analysis::ParseSceneShow(show);
    t = acro::ui::WriteSceneOverlay(video, scene, routine.camera, out, options);
    triangles = acro::analysis::MakeEllipsoidBodyMesh(routine.body,
                                                      acro::analysis::OverlayBodyMeshOptions())
                    .num_triangles();
  }
  const double frames = t.frames_read;
  const double total = t.decode_s + t.scene_s + t.render_s + t.composite_s + t.encode_s;
  state.counters["realtime"] = (frames / 30.0) / total;
  state.counters["decode_ms"] = 1e3 * t.decode_s / frames;
  state.counters["scene_ms"] = 1e3 * t.scene_s / frames;
  state.counters["render_readback_ms"] = 1e3 * t.render_s / frames;
  state.counters["composite_ms"] = 1e3 * t.composite_s / frames;
  state.counters["encode_ms"] = 1e3 * t.encode_s / frames;
  state.counters["triangles"] = std::string(show).find("mesh") != std::string::npos ? triangles : 0;
  fs::remove(out);
}

BENCHMARK_CAPTURE(BM_Overlay, skeleton, "skeleton,com")
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Overlay, mesh, "mesh,com")
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

// One flight frame's silhouette check (what `analyze`'s silhouettes and the overlay's mismatch do
// per frame): the video's foreground against the athlete drawn through the camera. Argument 0:
// the foreground of the whole 1080p frame, then the comparison (before 2026-12-08); 1: the
// foreground in the compared box only (CompareSilhouettes with the background, now). Same IoU.
void BM_SilhouetteCheckFrame(benchmark::State& state) {
  const fs::path video_path = acro::testing::Generated1080pVideo();
  if (video_path.empty() || !fs::exists(video_path)) {
    state.SkipWithError("the input video could not be made (is ffmpeg installed?)");
    return;
  }
  const Routine& routine = SampleRoutine();
  acro::analysis::TrialScene scene(routine.trial,
                                   routine.analysis,
                                   routine.body,
                                   acro::analysis::MakeEllipsoidBodyMesh(
                                       routine.body, acro::analysis::OverlayBodyMeshOptions()));
  int sample = 0;
  while (sample < scene.num_samples() && scene.FlightAt(sample) < 0) ++sample;
  sample += 60;  // into the flight
  acro::analysis::TrialFrame tf;
  scene.Frame(sample, &tf);
  acro::capture::VideoReader video(video_path);
  const acro::vision::BackgroundModel background(video, 15);
  const acro::capture::VideoFrame frame = video.Frame(100);
  const acro::vision::BackgroundOptions options;
  acro::vision::Mask real;
  acro::analysis::SilhouetteFrame compared;
  for (auto _ : state) {
    if (state.range(0) == 0) {
      real = background.Foreground(frame, options);
      acro::analysis::CompareSilhouettes(real, tf, routine.camera, 0.1, &compared);
    } else {
      acro::analysis::CompareSilhouettes(
          background, frame, options, tf, routine.camera, 0.1, &real, &compared);
    }
    // (read only: benchmark 1.7's DoNotOptimize of a writable double puts it through an integer
    // register and writes garbage back)
    const double iou = compared.iou;
    benchmark::DoNotOptimize(iou);
  }
  state.counters["iou"] = compared.iou;
  state.counters["box_px"] = double(compared.x1 - compared.x0) * (compared.y1 - compared.y0);
}
BENCHMARK(BM_SilhouetteCheckFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
