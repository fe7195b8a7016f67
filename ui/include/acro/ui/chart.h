#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "acro/ui/offscreen.h"

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
  std::string name;  ///< Shown in the legend.
  std::vector<double> x;
  std::vector<double> y;
  Rgb color{0.12, 0.47, 0.71};
  double width_px = 2.0;
  bool dashed = false;
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

/// What to draw in one 2D line chart: plain data, no toolkit types, so the content of a report's
/// figures can be built and tested without a display.
struct Chart {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<LineSeries> series;
  std::vector<ShadedInterval> bands;
  std::vector<ReferenceLine> reference_lines;
  std::optional<ValueRange> y_range;  ///< Fixed y axis; automatic from the data when empty.
  std::optional<ValueRange> x_range;  ///< Fixed x axis; automatic from the data when empty.
  bool show_legend = true;
  int width_px = 900;
  int height_px = 360;

  /// True when the chart can be drawn: at least one series with at least one finite point, x and
  /// y of equal length in every series, finite positive sizes and widths, alpha in [0, 1], ordered
  /// finite ranges and bands. Otherwise false with the first fault in `why` (which may be null).
  bool IsValid(std::string* why) const;
};

/// Renders charts to PNG offscreen, reusing one VTK render window across calls. Not thread-safe;
/// use one renderer per thread.
class ChartRenderer {
 public:
  /// Throws RenderingUnavailable (before touching any VTK window) when OffscreenRenderingStatus()
  /// says rendering is not possible here.
  ChartRenderer();
  ~ChartRenderer();
  ChartRenderer(const ChartRenderer&) = delete;
  ChartRenderer& operator=(const ChartRenderer&) = delete;

  /// The PNG file content of `chart`. Throws acro::InputError naming the chart and the field when
  /// `!chart.IsValid()`, std::runtime_error when rendering or encoding fails.
  std::vector<std::uint8_t> RenderPngBytes(const Chart& chart);

  /// Writes the PNG of `chart` to `path` atomically (temporary file beside it, then rename): a
  /// reader never sees a partial image, and nothing is left behind on failure.
  void RenderPng(const Chart& chart, const std::filesystem::path& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-off: RenderPng with a fresh ChartRenderer.
void RenderChartPng(const Chart& chart, const std::filesystem::path& path);

/// Renders charts[i] to paths[i] with one render window. Throws std::invalid_argument when the
/// sizes differ; stops at the first failing chart (files already written stay).
void RenderChartsPng(std::span<const Chart> charts, std::span<const std::filesystem::path> paths);

}  // namespace acro::ui
