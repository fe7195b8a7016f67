#pragma once

// A small toolkit-free line plot: a description (title, axes, series) rendered as SVG text or as a
// PNG image (OpenCV's drawing and encoder, private to analysis). For report pages and the CLI until
// the ui layer draws charts with VTK.

#include <cstdint>
#include <string>
#include <vector>

namespace acro::analysis {

struct PlotSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  std::uint32_t rgb = 0x1f77b4;  ///< 0xRRGGBB
  bool markers = false;          ///< draw a dot at each point
  bool dashed = false;
};

struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
  int width_px = 800;
  int height_px = 450;
};

/// The plot as a standalone SVG document.
std::string MakeSvgPlot(const LinePlot& plot);

/// The plot as PNG file bytes.
std::vector<std::uint8_t> RenderPngPlot(const LinePlot& plot);

}  // namespace acro::analysis
