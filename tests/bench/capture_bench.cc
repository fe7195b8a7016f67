// Capture read benchmarks (docs/performance.md, "Capture"): the largest C3D of the reference
// suites, and a generated 10 s trial (60 markers at 200 Hz, 16 analog channels at 2 kHz, float
// storage) written once with WriteC3d into a temporary file.

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "acro/capture/c3d.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

fs::path GeneratedTrialPath() {
  static const fs::path path = [] {
    Trial t;
    t.source.format = "generated";
    t.point_rate_hz = 200;
    t.num_frames = 2000;
    for (int p = 0; p < 60; ++p)
      t.points.push_back({"M" + std::to_string(p), "", PointType::kMarker, "m"});
    t.positions.resize(3, std::int64_t(t.num_frames) * 60);
    for (Eigen::Index i = 0; i < t.positions.cols(); ++i) {
      t.positions.col(i) << 0.001 * (i % 977), 1.0 + 0.3 * std::sin(0.001 * i),
          0.9 + 1e-4 * (i % 60);
    }
    t.residuals = Eigen::ArrayXXf::Constant(60, t.num_frames, 0.5f);
    t.camera_masks =
        Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>::Constant(60, t.num_frames, 7);
    t.analog_rate_hz = 2000;
    for (int c = 0; c < 16; ++c)
      t.analog_channels.push_back({"A" + std::to_string(c), "", "V", 1.0, 0.0, 0.0});
    t.analog.resize(16, std::int64_t(t.num_frames) * 10);
    for (Eigen::Index i = 0; i < t.analog.size(); ++i) t.analog.data()[i] = std::sin(0.01 * i);
    const fs::path out = fs::temp_directory_path() / "acrolab_capture_bench_10s.c3d";
    WriteC3d(t, out);
    return out;
  }();
  return path;
}

void ReadFile(benchmark::State& state, const fs::path& path) {
  if (!fs::exists(path)) {
    state.SkipWithError(("missing " + path.string()).c_str());
    return;
  }
  const auto bytes = static_cast<std::int64_t>(fs::file_size(path));
  for (auto _ : state) {
    Trial t = ReadC3d(path);
    benchmark::DoNotOptimize(t.positions.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["file_MB"] = bytes / 1e6;
}

void BM_ReadC3d_Generated10s(benchmark::State& state) {
  ReadFile(state, GeneratedTrialPath());
}
BENCHMARK(BM_ReadC3d_Generated10s)->Unit(benchmark::kMillisecond);

// The largest C3D of the suites: c3d.org sample 33 (bigparlove.c3d, 1.35 MB, 205 points, 5 plates).
void BM_ReadC3d_LargestSuiteFile(benchmark::State& state) {
  ReadFile(state, acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_33/bigparlove.c3d"));
}
BENCHMARK(BM_ReadC3d_LargestSuiteFile)->Unit(benchmark::kMillisecond);

void BM_WriteC3dToMemory_Generated10s(benchmark::State& state) {
  const Trial t = ReadC3d(GeneratedTrialPath());
  std::int64_t bytes = 0;
  for (auto _ : state) {
    std::vector<std::uint8_t> out = WriteC3dToMemory(t);
    bytes = static_cast<std::int64_t>(out.size());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(state.iterations() * bytes);
}
BENCHMARK(BM_WriteC3dToMemory_Generated10s)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace acro::capture

BENCHMARK_MAIN();
