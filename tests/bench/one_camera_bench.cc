// The athlete from one camera after detection (#40, docs/one-camera.md): the goal is a 10-skill
// routine at 60 fps in ≤ 60 s on two cores. The sample routine's motion capture reconstructed, its
// BODY_25B keypoints projected into the sample's side camera at 60 fps with 2 px of noise, the
// routine twice over (12 skills, 1266 frames, 21 s) — written once as a detections CSV; timed:
// pipeline::OpenMonocular (flights from the picture, depth from gravity, keypoints on the plane)
// and the reconstruction (scaling, inverse kinematics, the fit to the camera's rays), and with
// --flight-physics the free-flight refit as well.

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/standard_human.h"
#include "acro/capture/trial_io.h"
#include "acro/pipeline/monocular_input.h"
#include "acro/reconstruct/reconstruction.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/camera.h"
#include "refdata.h"

namespace {

using namespace acro;

std::filesystem::path Sample(const std::string& name) {
  return acro::testing::SourceDir() / "samples/trials/trampoline_routine" / name;
}

struct Setup {
  std::filesystem::path csv;
  vision::BedLine line;
  int frames = 0;
};

const Setup& TheSetup() {
  static const Setup setup = [] {
    Setup s;
    const capture::Trial trial = capture::ReadTrial(Sample("trampoline_routine.c3d"));
    const analysis::AthleteBody body = analysis::MakeDeLevaBody(1.75, 65.0, analysis::Sex::kFemale);
    const analysis::ReconstructionResult truth = analysis::Reconstruct(trial, nullptr, body, {});
    const std::vector<analysis::ModelMarker> keypoints =
        analysis::PlaceMarkers(analysis::BuiltinMarkerSet("body25b"), truth.model, body.height_m);
    analysis::InverseKinematics ik(truth.model, keypoints, truth.joint_limits, truth.ik_options);
    vision::Camera side;
    for (const vision::Camera& c : vision::ReadCameras(Sample("views.toml")))
      if (c.name == "side") side = c;
    s.line = vision::RestLineOfBed(vision::DetectBed(Sample("side_camera.mp4"), 0));
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / "acrolab_one_camera_bench";
    std::filesystem::create_directories(dir);
    s.csv = dir / "side.csv";
    std::ofstream out(s.csv);
    out << "frame,keypoint,u_px,v_px,confidence\n";
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 2.0);
    Eigen::Matrix3Xd p_WM;
    const int step = 2;  // 120 Hz → 60 fps
    for (int copy = 0; copy < 2; ++copy)
      for (int f = 0; f < truth.motion.num_frames(); f += step, ++s.frames) {
        ik.CalcMarkerPositions(truth.motion.q.col(f), p_WM);
        for (size_t j = 0; j < keypoints.size(); ++j) {
          const auto uv = side.Project(p_WM.col(Eigen::Index(j)));
          if (!uv) continue;
          out << s.frames << ',' << keypoints[j].name << ',' << uv->x() + noise(rng) << ','
              << uv->y() + noise(rng) << ",0.9\n";
        }
      }
    return s;
  }();
  return setup;
}

void Run(benchmark::State& state, bool physics) {
  const Setup& s = TheSetup();
  for (auto _ : state) {
    pipeline::MonocularRequest request;
    request.detections = s.csv;
    request.rate_hz = 60;
    request.bed_line = s.line;
    request.calibration = Sample("views.toml");
    request.camera = "side";
    const pipeline::MonocularInput in = pipeline::OpenMonocular(request);
    analysis::ReconstructionOptions options;
    options.views = in.views;
    for (const vision::ImageFlight& f : in.flights.flights)
      options.ballistic_flights_s.emplace_back(f.takeoff_s, f.landing_s);
    options.fit_flight_physics = physics;
    const analysis::ReconstructionResult r =
        analysis::Reconstruct(in.input.trial, nullptr, in.input.athlete.body, options);
    benchmark::DoNotOptimize(r.motion.q.data());
    state.counters["flights"] = double(in.flights.flights.size());
  }
  state.counters["frames"] = s.frames;
}

void BM_OneCameraTwelveSkills60fps(benchmark::State& state) {
  Run(state, false);
}
void BM_OneCameraTwelveSkills60fpsFlightPhysics(benchmark::State& state) {
  Run(state, true);
}

BENCHMARK(BM_OneCameraTwelveSkills60fps)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_OneCameraTwelveSkills60fpsFlightPhysics)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
