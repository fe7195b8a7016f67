#include "acro/report/overlay.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <system_error>

#include <fmt/format.h>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/base/temporaries.h"
#include "acro/report/image.h"
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

bool IsFrameFileName(const std::string& name) {
  return name.size() == 16 && name.rfind("frame_", 0) == 0 && name.substr(12) == ".png" &&
         std::all_of(
             name.begin() + 6, name.begin() + 12, [](char c) { return c >= '0' && c <= '9'; });
}

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
  namespace fs = std::filesystem;
  const capture::VideoInfo& info = video.info();
  const std::vector<double>& times = video.frame_times_s();
  const std::vector<vision::ProjectedPoint> points =
      vision::ProjectTrialOnFrames(trial, camera, times, options.sync, options.axes);
  const double radius = options.radius_px > 0
                            ? options.radius_px
                            : std::max(3.0, 0.004 * std::hypot(info.width, info.height));
  const bool mp4 = output.extension() == ".mp4";

  std::optional<capture::VideoWriter> writer;
  fs::path staging;
  if (mp4) {
    capture::VideoWriterOptions w;
    w.fps = info.average_fps > 0 ? info.average_fps : 30.0;
    writer.emplace(output, info.width, info.height, w);
  } else {
    if (fs::exists(output)) {
      if (!fs::is_directory(output))
        throw InputError(output.string(), "", "exists and is not a directory (frames go into one)");
      for (const auto& entry : fs::directory_iterator(output))
        if (!IsFrameFileName(entry.path().filename().string()))
          throw InputError(output.string(),
                           "",
                           "holds " + entry.path().filename().string() +
                               ", not only frame_NNNNNN.png: not replaced");
    }
    std::random_device rd;
    staging = output;
    staging += fmt::format(".tmp-{:08x}", rd());
    std::error_code ec;
    if (!fs::create_directories(staging, ec))
      throw InputError(staging.string(), "", "cannot create the directory: " + ec.message());
  }
  // On any failure the staging directory goes (the MP4 writer removes its own temporary file), and
  // an interrupt removes it too.
  std::optional<ScopedTemporary> registered;
  if (!staging.empty()) registered.emplace(staging);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      if (!dir.empty()) fs::remove_all(dir, ec);
    }
  } cleanup{staging};

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
    if (writer) {
      writer->Write(frame.pixels);
    } else {
      WriteRgbPng(frame.width,
                  frame.height,
                  frame.pixels,
                  staging / fmt::format("frame_{:06d}.png", frame.index));
    }
    ++written;
    if (options.progress && !options.progress(written, info.num_frames))
      throw InputError(output.string(), "", "cancelled; nothing written");
  }
  if (writer) {
    writer->Finish();
  } else {
    std::error_code ec;
    if (fs::exists(output)) fs::remove_all(output, ec);
    fs::rename(staging, output, ec);
    if (ec)
      throw InputError(output.string(), "", "cannot move the frames into place: " + ec.message());
    cleanup.dir.clear();
  }
  return written;
}

}  // namespace acro::ui
