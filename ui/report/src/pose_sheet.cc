#include "acro/report/pose_sheet.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/base/input_error.h"
#include "acro/report/image.h"
#include "rgb_surface.h"

namespace acro::ui {
namespace {

void SideColour(cairo_t* cr, int side) {
  if (side > 0)
    cairo_set_source_rgb(cr, 0.15, 0.55, 1.0);  // left: blue
  else if (side < 0)
    cairo_set_source_rgb(cr, 1.0, 0.55, 0.1);  // right: orange
  else
    cairo_set_source_rgb(cr, 0.95, 0.95, 0.95);
}

// The box around a person's confident keypoints, widened by a fifth of its size (empty: none).
bool PersonBox(const capture::DetectedPerson& p, double min_confidence, Eigen::AlignedBox2d* box) {
  Eigen::AlignedBox2d b;
  for (int k = 0; k < p.cols(); ++k)
    if (p(2, k) >= min_confidence && p.col(k).allFinite())
      b.extend(Eigen::Vector2d(p(0, k), p(1, k)));
  if (b.isEmpty()) return false;
  const double margin = 0.2 * b.sizes().maxCoeff() + 10.0;
  b.extend(b.min() - Eigen::Vector2d::Constant(margin));
  b.extend(b.max() + Eigen::Vector2d::Constant(margin));
  *box = b;
  return true;
}

}  // namespace

void DrawSkeleton(int width,
                  int height,
                  const capture::DetectedPerson& person,
                  const std::vector<std::pair<int, int>>& edges,
                  const std::vector<int>& side,
                  double min_confidence,
                  std::vector<std::uint8_t>* rgb) {
  cairo_surface_t* surface = internal::SurfaceFromRgb(width, height, *rgb);
  cairo_t* cr = cairo_create(surface);
  Eigen::AlignedBox2d box;
  const double scale = PersonBox(person, min_confidence, &box) ? box.sizes().maxCoeff() : 200.0;
  const double line = std::clamp(scale / 120.0, 1.5, 8.0);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  auto ok = [&](int k) {
    return k < person.cols() && person(2, k) >= min_confidence && person.col(k).allFinite();
  };
  for (const auto& [a, b] : edges) {
    if (!ok(a) || !ok(b)) continue;
    const int s = (a < static_cast<int>(side.size()) && b < static_cast<int>(side.size()) &&
                   side[a] == side[b])
                      ? side[a]
                      : 0;
    cairo_set_line_width(cr, line + 2.0);
    cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
    cairo_move_to(cr, person(0, a), person(1, a));
    cairo_line_to(cr, person(0, b), person(1, b));
    cairo_stroke(cr);
    cairo_set_line_width(cr, line);
    SideColour(cr, s);
    cairo_move_to(cr, person(0, a), person(1, a));
    cairo_line_to(cr, person(0, b), person(1, b));
    cairo_stroke(cr);
  }
  for (int k = 0; k < person.cols(); ++k) {
    if (!ok(k)) continue;
    const double g = std::clamp(person(2, k), 0.0, 1.0);
    cairo_new_path(cr);
    cairo_arc(cr, person(0, k), person(1, k), line * 1.1, 0.0, 2.0 * M_PI);
    cairo_set_source_rgb(cr, g, g, 0.2);
    cairo_fill_preserve(cr);
    cairo_set_line_width(cr, 1.0);
    cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
    cairo_stroke(cr);
  }
  cairo_destroy(cr);
  internal::RgbFromSurface(surface, rgb);
  cairo_surface_destroy(surface);
}

void WritePoseContactSheet(capture::VideoReader& video,
                           const std::vector<int>& frame_indices,
                           const std::vector<capture::DetectedPerson>& people,
                           const std::vector<std::pair<int, int>>& edges,
                           const std::vector<int>& side,
                           const std::filesystem::path& path,
                           const ContactSheetOptions& options) {
  if (frame_indices.size() != people.size() || frame_indices.empty() || options.columns < 1 ||
      options.cell_px < 16)
    throw InputError(
        path.string(), "", "a contact sheet needs one person per frame and at least one frame");
  const int w = video.info().width, h = video.info().height;
  // The common crop: every person's box together, made square.
  Eigen::AlignedBox2d common;
  std::vector<double> sides;
  for (const auto& p : people) {
    Eigen::AlignedBox2d b;
    if (PersonBox(p, options.min_confidence, &b)) {
      common.extend(b);
      sides.push_back(b.sizes().maxCoeff());
    }
  }
  if (common.isEmpty())
    common = Eigen::AlignedBox2d(Eigen::Vector2d::Zero(), Eigen::Vector2d(w, h));
  // A path much longer than the person (a whole routine) would leave the person tiny: then each
  // frame is cropped around its own person.
  bool per_frame = !options.common_crop;
  if (!sides.empty()) {
    std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
    if (common.sizes().maxCoeff() > 2.5 * sides[sides.size() / 2]) per_frame = true;
  }

  const int n = static_cast<int>(frame_indices.size());
  const int cols = std::min(options.columns, n), rows = (n + cols - 1) / cols,
            cell = options.cell_px;
  cairo_surface_t* sheet = cairo_image_surface_create(CAIRO_FORMAT_RGB24, cols * cell, rows * cell);
  cairo_t* cr = cairo_create(sheet);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_paint(cr);
  for (int k = 0; k < n; ++k) {
    capture::VideoFrame frame = video.Frame(frame_indices[k]);
    DrawSkeleton(
        frame.width, frame.height, people[k], edges, side, options.min_confidence, &frame.pixels);
    Eigen::AlignedBox2d box = common;
    if (per_frame && !PersonBox(people[k], options.min_confidence, &box)) box = common;
    const double side_px = box.sizes().maxCoeff();
    const Eigen::Vector2d centre = box.center();
    cairo_surface_t* picture = internal::SurfaceFromRgb(frame.width, frame.height, frame.pixels);
    cairo_save(cr);
    cairo_rectangle(cr, (k % cols) * cell, (k / cols) * cell, cell, cell);
    cairo_clip(cr);
    cairo_translate(cr, (k % cols) * cell, (k / cols) * cell);
    cairo_scale(cr, cell / side_px, cell / side_px);
    cairo_translate(cr, -(centre.x() - side_px / 2), -(centre.y() - side_px / 2));
    cairo_set_source_surface(cr, picture, 0, 0);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(picture);
    // The frame number, bottom left.
    cairo_set_font_size(cr, std::max(10.0, cell / 14.0));
    cairo_move_to(cr, (k % cols) * cell + 6, (k / cols) * cell + cell - 8);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_show_text(cr, fmt::format("{}", frame_indices[k]).c_str());
  }
  cairo_destroy(cr);
  std::vector<std::uint8_t> rgb;
  internal::RgbFromSurface(sheet, &rgb);
  const int sw = cairo_image_surface_get_width(sheet), sh = cairo_image_surface_get_height(sheet);
  cairo_surface_destroy(sheet);
  WriteRgbPng(sw, sh, rgb, path);
}

int WriteDetectionOverlay(capture::VideoReader& video,
                          const std::vector<std::vector<capture::DetectedPerson>>& people,
                          const std::vector<std::pair<int, int>>& edges,
                          const std::vector<int>& side,
                          const std::filesystem::path& output,
                          const Progress& progress,
                          double min_confidence,
                          int first_frame,
                          int last_frame) {
  const capture::VideoInfo& info = video.info();
  if (info.num_frames > 0 && first_frame >= info.num_frames)
    throw InputError(
        info.path,
        "--frames",
        fmt::format("frame {} is beyond the video's {} frames", first_frame, info.num_frames));
  const int end = last_frame < 0 || (info.num_frames > 0 && last_frame >= info.num_frames)
                      ? info.num_frames - 1
                      : last_frame;
  const int total = std::max(0, end - first_frame + 1);
  capture::VideoWriterOptions options;
  options.fps = info.average_fps > 0 ? info.average_fps : 30.0;
  capture::VideoWriter writer(output, info.width, info.height, options);
  capture::VideoFrame frame;
  int written = 0;
  while (video.ReadNext(&frame)) {
    if (frame.index < first_frame) continue;
    if (last_frame >= 0 && frame.index > last_frame) break;
    progress.ReportOrThrow("overlay", written, total);
    if (frame.index < static_cast<int>(people.size()))
      for (const capture::DetectedPerson& person : people[frame.index])
        DrawSkeleton(frame.width, frame.height, person, edges, side, min_confidence, &frame.pixels);
    writer.Write(frame.pixels);
    ++written;
  }
  writer.Finish();
  progress.Report("overlay", written, total);
  return written;
}

}  // namespace acro::ui
