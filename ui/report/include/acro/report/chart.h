#pragma once

// One 2D chart description for every report (analyze, optimize, body) and one renderer for it, on
// Cairo: PNG and SVG from the same drawing, anti-aliased, Unicode text (m/s², N·m), no display.
// The description is plain data, so the content of a report's figures is built and tested without
// rendering anything.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace acro::ui {

/// A colour with components in [0, 1].
struct Rgb {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
};

/// One polyline of a chart. A NaN in `y` (or `x`) is a gap: the line stops before it and starts
/// again after it.
struct LineSeries {
  std::string name;  ///< Shown in the legend (an empty name is left out of it).
  std::vector<double> x;
  std::vector<double> y;
  Rgb color{0.12, 0.47, 0.71};
  double width_px = 2.0;
  bool dashed = false;
  bool markers = false;  ///< A dot at each finite point.
  bool line = true;      ///< false: markers only.
};

/// A vertical band over [x0, x1] drawn behind the lines across the whole plot height (e.g. a flight
/// phase). Its label, when not empty, names the band's colour in the legend (once per distinct
/// label, so that all flight phases share one entry).
struct ShadedInterval {
  double x0 = 0.0;
  double x1 = 0.0;
  Rgb color{0.6, 0.6, 0.6};
  double alpha = 0.2;  ///< 0 transparent … 1 opaque.
  std::string label;
};

/// A horizontal line at `y` across the whole x range (e.g. a threshold), with an optional legend
/// label.
struct ReferenceLine {
  double y = 0.0;
  std::string label;
  Rgb color{0.3, 0.3, 0.3};
  bool dashed = true;
};

/// A closed value interval [min, max], min < max.
struct ValueRange {
  double min = 0.0;
  double max = 1.0;
};

/// What to draw in one 2D line chart.
struct Chart {
  std::string title;
  std::string x_label;  ///< With its unit, e.g. "time (s)".
  std::string y_label;  ///< With its unit, e.g. "force (body weights)".
  std::vector<LineSeries> series;
  std::vector<ShadedInterval> bands;
  std::vector<ReferenceLine> reference_lines;
  std::optional<ValueRange> y_range;  ///< Fixed y axis; automatic from the data when empty.
  std::optional<ValueRange> x_range;  ///< Fixed x axis; automatic from the data when empty.
  bool show_legend = true;
  int width_px = 900;
  int height_px = 360;

  /// True when the chart can be drawn: at least one series with at least one finite point, x and
  /// y of equal length in every series, sizes in 16..8192 px, line widths in (0, 100], colours and
  /// alpha in [0, 1], ordered finite ranges and bands. Otherwise false with the first fault in
  /// `why` (which may be null).
  bool IsValid(std::string* why) const;
};

/// Where the renderer put the plot area and the legend, in pixels from the top left (for tests
/// and for pages that annotate a chart).
struct ChartLayout {
  double plot_left = 0.0;
  double plot_top = 0.0;
  double plot_right = 0.0;
  double plot_bottom = 0.0;
  bool legend_drawn = false;
  bool legend_inside = false;  ///< inside the plot area, over a corner that holds no data
  double legend_left = 0.0;
  double legend_top = 0.0;
  double legend_right = 0.0;
  double legend_bottom = 0.0;
  ValueRange x_range;  ///< the axes' ranges as drawn
  ValueRange y_range;
};

/// The layout `RenderChartPng` and `RenderChartSvg` use for `chart`. Throws acro::InputError when
/// `!chart.IsValid()`.
ChartLayout MakeChartLayout(const Chart& chart);

/// The PNG file content of `chart`. Throws acro::InputError naming the chart and the field when
/// `!chart.IsValid()`, std::runtime_error when Cairo fails. Thread-safe.
std::vector<std::uint8_t> RenderChartPng(const Chart& chart);

/// The pixels of `chart` as RGB (3 bytes per pixel, rows top to bottom, width_px × height_px): the
/// PNG's drawing, for frames of a video. Throws as RenderChartPng.
std::vector<std::uint8_t> RenderChartRgb(const Chart& chart);

/// The SVG document of `chart` (the same drawing as the PNG; text as outlines). Thread-safe.
std::string RenderChartSvg(const Chart& chart);

/// The data of `chart` as CSV: "series,x,y", one row per point (gaps left out), every series in
/// turn.
std::string FormatChartCsv(const Chart& chart);
/// Writes `chart` to `path` as PNG, SVG or its data as CSV by the extension (".png", ".svg",
/// ".csv"), atomically: a reader
/// never sees a partial image, and nothing is left behind on failure. Throws acro::InputError for
/// another extension or an invalid chart.
void WriteChart(const Chart& chart, const std::filesystem::path& path);

}  // namespace acro::ui
