// Report rendering: one 900 × 360 px chart of two 2000-point series (one with a NaN gap), three
// shaded phases and a reference line, drawn by Cairo and encoded as PNG or SVG in memory.
// Needs a display: run under xvfb-run -a (docs/performance.md).
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>

#include "acro/report/chart.h"

namespace {

using acro::ui::Chart;

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

// One report chart as PNG (Cairo: draw, then libpng's deflate) and as SVG.
void BM_RenderChartPng_900x360_2x2000(benchmark::State& state) {
  const Chart chart = MakeReportChart();
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<std::uint8_t> png = acro::ui::RenderChartPng(chart);
    bytes = png.size();
    benchmark::DoNotOptimize(png.data());
  }
  state.counters["png_kB"] = static_cast<double>(bytes) / 1000.0;
}
BENCHMARK(BM_RenderChartPng_900x360_2x2000)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderChartSvg_900x360_2x2000(benchmark::State& state) {
  const Chart chart = MakeReportChart();
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string svg = acro::ui::RenderChartSvg(chart);
    bytes = svg.size();
    benchmark::DoNotOptimize(svg.data());
  }
  state.counters["svg_kB"] = static_cast<double>(bytes) / 1000.0;
}
BENCHMARK(BM_RenderChartSvg_900x360_2x2000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
