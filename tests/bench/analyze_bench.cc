// The main job, `acrolab analyze`, on a 10.5 s, 200 Hz trial of 39 Plug-in Gait markers (plus the
// four bed corners): the sample routine's six skills simulated again at 200 Hz
// (tools/sample_routine.h), its noise-free motion seen through the Plug-in Gait set with 1 mm of
// marker noise, written as C3D in memory with a 1 s static trial in the reference pose.
// BM_AnalyzeNumbers: C3D import → reconstruction (scaling to the static trial,
// filter, IK) → inverse dynamics and the check → metrics (goal ≤ 0.5 s). BM_AnalyzeWithReport:
// the same plus the tables and report.html with its six PNG charts (goal ≤ 3 s; needs a display:
// run under xvfb-run -a). Run: build/bench/analyze_bench (docs/performance.md).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>

#include "acro/assess/trial_analysis.h"
#include "acro/athlete/athlete_profile.h"
#include "acro/capture/c3d.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"
#include "acro/reconstruct/markerset.h"
#include "acro/report/analysis_report.h"
#include "refdata.h"
#include "sample_routine.h"

namespace {

namespace fs = std::filesystem;

struct Scene {
  acro::analysis::AthleteBody body;
  std::vector<std::uint8_t> c3d;
  std::vector<std::uint8_t> static_c3d;
  int frames = 0;
};

const Scene& GetScene() {
  static const Scene scene = [] {
    const fs::path athlete = acro::testing::SourceDir() / "samples/athletes/sample_athlete.yaml";
    acro::samples::SampleRoutineOptions options;
    options.point_rate_hz = 200.0;
    options.substeps_per_frame = 12;
    const acro::samples::SampleRoutine routine =
        acro::samples::MakeSampleRoutine(athlete, "sample_athlete.yaml", options);
    Scene s;
    s.body = acro::analysis::MakeAthleteBody(acro::analysis::ReadAthleteProfile(athlete));
    // The routine's motion through the Plug-in Gait markers, and its bed corners.
    const acro::dynamics::Model<double>& model = routine.model;
    const std::vector<acro::analysis::ModelMarker> markers = acro::analysis::PlaceMarkers(
        acro::analysis::BuiltinMarkerSet("plug_in_gait"), model, s.body.height_m);
    const acro::capture::Trial& source = routine.trial;
    std::vector<int> bed;
    for (int p = 0; p < source.num_points(); ++p)
      if (source.points[size_t(p)].label.rfind("BED", 0) == 0) bed.push_back(p);
    acro::capture::Trial trial;
    trial.point_rate_hz = source.point_rate_hz;
    trial.num_frames = source.num_frames;
    for (const auto& m : markers)
      trial.points.push_back({m.name, "", acro::capture::PointType::kMarker, "m"});
    for (int p : bed) trial.points.push_back(source.points[size_t(p)]);
    const int P = trial.num_points();
    trial.positions.resize(3, static_cast<Eigen::Index>(trial.num_frames) * P);
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 1e-3);
    acro::dynamics::Workspace<double> ws(model);
    for (int f = 0; f < trial.num_frames; ++f) {
      acro::dynamics::CalcForwardKinematics(model, ws, Eigen::VectorXd(routine.q.col(f)));
      for (size_t m = 0; m < markers.size(); ++m)
        trial.positions.col(Eigen::Index(f) * P + Eigen::Index(m)) =
            ws.X_WB[size_t(markers[m].segment)] * markers[m].p_BoM_B +
            Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      for (size_t b = 0; b < bed.size(); ++b)
        trial.positions.col(Eigen::Index(f) * P + Eigen::Index(markers.size() + b)) =
            source.positions.col(Eigen::Index(f) * source.num_points() + bed[b]);
    }
    s.frames = trial.num_frames;
    s.c3d = acro::capture::WriteC3dToMemory(trial);
    // A 1 s static trial, standing in the reference pose, for the scaling (as a lab records one).
    acro::capture::Trial still = trial;
    still.num_frames = static_cast<int>(trial.point_rate_hz);
    still.positions.resize(3, static_cast<Eigen::Index>(still.num_frames) * P);
    Eigen::VectorXd q = acro::dynamics::MakeNeutralConfiguration(model);
    q.head<3>() << 0.0, 2.0, 0.9;
    acro::dynamics::CalcForwardKinematics(model, ws, q);
    for (int f = 0; f < still.num_frames; ++f) {
      for (size_t m = 0; m < markers.size(); ++m)
        still.positions.col(Eigen::Index(f) * P + Eigen::Index(m)) =
            ws.X_WB[size_t(markers[m].segment)] * markers[m].p_BoM_B +
            Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      for (size_t b = 0; b < bed.size(); ++b)
        still.positions.col(Eigen::Index(f) * P + Eigen::Index(markers.size() + b)) =
            trial.positions.col(Eigen::Index(markers.size() + b));
    }
    s.static_c3d = acro::capture::WriteC3dToMemory(still);
    return s;
  }();
  return scene;
}

acro::analysis::TrialAnalysis Analyze(const Scene& s) {
  const acro::capture::Trial trial = acro::capture::ReadC3dFromMemory(s.c3d, "bench.c3d");
  const acro::capture::Trial still = acro::capture::ReadC3dFromMemory(s.static_c3d, "static.c3d");
  return acro::analysis::AnalyzeTrial(trial, &still, s.body);
}

void BM_AnalyzeNumbers(benchmark::State& state) {
  const Scene& s = GetScene();
  for (auto _ : state) {
    const acro::analysis::TrialAnalysis a = Analyze(s);
    benchmark::DoNotOptimize(a.total_difficulty);
    if (a.jumps.size() != 6 || !a.check.pass) state.SkipWithError(a.BriefReport().c_str());
  }
  state.counters["frames"] = s.frames;
}
BENCHMARK(BM_AnalyzeNumbers)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_AnalyzeWithReport(benchmark::State& state) {
  const Scene& s = GetScene();
  const fs::path dir = fs::temp_directory_path() / "acrolab_analyze_bench";
  fs::create_directories(dir);
  for (auto _ : state) {
    const acro::analysis::TrialAnalysis a = Analyze(s);
    acro::analysis::WriteAnalysisTables(a, dir);
    const acro::ui::AnalysisReportOutcome outcome =
        acro::ui::WriteAnalysisReport(a, dir, acro::ui::AnalysisReportOptions{});
    if (!outcome.images_rendered) state.SkipWithError(outcome.reason.c_str());
  }
  fs::remove_all(dir);
}
BENCHMARK(BM_AnalyzeWithReport)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
