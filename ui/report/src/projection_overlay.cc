#include "acro/report/projection_overlay.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "acro/base/demand.h"
#include "acro/base/progress.h"
#include "acro/base/input_error.h"
#include "acro/capture/frame_output.h"
#include "rgb_surface.h"

namespace acro::ui {

namespace {

// Ten colours that stay apart on grey gym walls and blue trampoline beds (the Tableau 10 hues).
constexpr double kPalette[10][3] = {{0.12, 0.47, 0.71},
                                    {1.00, 0.50, 0.05},
                                    {0.17, 0.63, 0.17},
                                    {0.84, 0.15, 0.16},
                                    {0.58, 0.40, 0.74},
                                    {0.55, 0.34, 0.29},
                                    {0.89, 0.47, 0.76},
                                    {0.50, 0.50, 0.50},
                                    {0.74, 0.74, 0.13},
                                    {0.09, 0.75, 0.81}};

}  // namespace

void DrawPoints(int width,
                int height,
                const std::vector<Eigen::Vector2d>& points_px,
                const std::vector<int>& colour_index,
                double radius_px,
                std::vector<std::uint8_t>* rgb) {
  if (points_px.empty()) return;
  cairo_surface_t* surface = internal::SurfaceFromRgb(width, height, *rgb);
  cairo_t* cr = cairo_create(surface);
  cairo_set_line_width(cr, std::max(1.0, radius_px / 3.0));
  for (size_t i = 0; i < points_px.size(); ++i) {
    const int c = i < colour_index.size() ? std::abs(colour_index[i]) % 10 : 0;
    cairo_new_path(cr);
    cairo_arc(cr, points_px[i].x(), points_px[i].y(), radius_px, 0.0, 2.0 * M_PI);
    cairo_set_source_rgb(cr, kPalette[c][0], kPalette[c][1], kPalette[c][2]);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
    cairo_stroke(cr);
  }
  cairo_destroy(cr);
  internal::RgbFromSurface(surface, rgb);
  cairo_surface_destroy(surface);
}

int WriteProjectionOverlay(capture::VideoReader& video,
                           const capture::Trial& trial,
                           const vision::Camera& camera,
                           const std::filesystem::path& output,
                           const OverlayVideoOptions& options) {
  const capture::VideoInfo& info = video.info();
  const std::vector<double>& times = video.frame_times_s();
  const std::vector<vision::ProjectedPoint> points =
      vision::ProjectTrialOnFrames(trial, camera, times, options.sync, options.axes);
  const double radius = options.radius_px > 0
                            ? options.radius_px
                            : std::max(3.0, 0.004 * std::hypot(info.width, info.height));
  capture::VideoWriterOptions w;
  w.fps = info.average_fps > 0 ? info.average_fps : 30.0;
  capture::FrameOutput out(output, info.width, info.height, w);

  capture::VideoFrame frame;
  size_t next = 0;
  std::vector<Eigen::Vector2d> uv;
  std::vector<int> colour;
  int written = 0;
  while (video.ReadNext(&frame)) {
    ACRO_DEMAND(frame.channels == 3);  // the caller opened the reader for RGB
    uv.clear();
    colour.clear();
    while (next < points.size() && points[next].frame < frame.index) ++next;
    for (; next < points.size() && points[next].frame == frame.index; ++next) {
      uv.push_back(points[next].uv_px);
      colour.push_back(points[next].marker);
    }
    DrawPoints(frame.width, frame.height, uv, colour, radius, &frame.pixels);
    out.Write(frame.index, frame.pixels);
    ++written;
    if (options.progress && !options.progress(written, info.num_frames))
      throw Cancelled(output.string() + ": cancelled; nothing written");
  }
  out.Finish();
  return written;
}

}  // namespace acro::ui
