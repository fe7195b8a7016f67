// Report rendering: one 900 × 360 px chart of two 2000-point series (one with a NaN gap), three
// shaded phases and a reference line, rendered offscreen by VTK and encoded as PNG in memory.
// Needs a display: run under xvfb-run -a (docs/performance.md).
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>

#include "acro/ui/chart.h"

namespace {

using acro::ui::Chart;
using acro::ui::ChartRenderer;

// 10 s at 200 Hz: a COM-height-like bounce and a residual-like noise, three flight bands.
Chart MakeReportChart() {
  Chart chart;
  chart.title = "COM height";
  chart.x_label = "time (s)";
  chart.y_label = "height (m)";
  acro::ui::LineSeries com{"COM", {}, {}, {0.84, 0.15, 0.16}, 2.0, false};
  acro::ui::LineSeries other{"feet", {}, {}, {0.12, 0.47, 0.71}, 1.5, true};
  for (int i = 0; i < 2000; ++i) {
    const double t = 0.005 * i;
    com.x.push_back(t);
    com.y.push_back(1.0 + 3.0 * std::abs(std::sin(0.9 * t)));
    other.x.push_back(t);
    other.y.push_back(i > 900 && i < 950 ? std::numeric_limits<double>::quiet_NaN()
                                         : 0.2 + 3.0 * std::abs(std::sin(0.9 * t + 0.1)));
  }
  chart.series = {com, other};
  chart.bands = {{0.5, 3.0, {0.6, 0.8, 1.0}, 0.3, "flight"},
                 {4.0, 6.5, {0.6, 0.8, 1.0}, 0.3, "flight"},
                 {7.5, 9.8, {0.6, 0.8, 1.0}, 0.3, "flight"}};
  chart.reference_lines = {{1.0, "bed", {0.4, 0.4, 0.4}, true}};
  return chart;
}

// The report's case: one renderer (window and OpenGL context) reused for every chart.
void BM_RenderChartPng_900x360_2x2000(benchmark::State& state) {
  const acro::ui::RenderingStatus status = acro::ui::OffscreenRenderingStatus();
  if (!status.available) {
    state.SkipWithError(status.reason.c_str());
    return;
  }
  const Chart chart = MakeReportChart();
  ChartRenderer renderer;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<std::uint8_t> png = renderer.RenderPngBytes(chart);
    bytes = png.size();
    benchmark::DoNotOptimize(png.data());
  }
  state.counters["png_kB"] = static_cast<double>(bytes) / 1000.0;
}
BENCHMARK(BM_RenderChartPng_900x360_2x2000)->Unit(benchmark::kMillisecond)->UseRealTime();

// A one-off chart: a fresh renderer each time, so window and context creation are included.
void BM_RenderChartPng_FreshRenderer(benchmark::State& state) {
  const acro::ui::RenderingStatus status = acro::ui::OffscreenRenderingStatus();
  if (!status.available) {
    state.SkipWithError(status.reason.c_str());
    return;
  }
  const Chart chart = MakeReportChart();
  for (auto _ : state) {
    ChartRenderer renderer;
    benchmark::DoNotOptimize(renderer.RenderPngBytes(chart).data());
  }
}
BENCHMARK(BM_RenderChartPng_FreshRenderer)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
