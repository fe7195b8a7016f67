#include "acro/vision/silhouette.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "acro/base/input_error.h"

namespace acro::vision {

namespace {

// A frame as grey values (luma for RGB, as Rec. 601 weighs it).
std::vector<std::uint8_t> GreyOf(const capture::VideoFrame& f) {
  if (f.channels == 1) return f.pixels;
  std::vector<std::uint8_t> g(static_cast<size_t>(f.width) * f.height);
  for (size_t i = 0; i < g.size(); ++i) {
    const std::uint8_t* p = &f.pixels[3 * i];
    g[i] = static_cast<std::uint8_t>((299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000);
  }
  return g;
}

}  // namespace

int Mask::CountInside() const {
  return static_cast<int>(
      std::count_if(pixels.begin(), pixels.end(), [](std::uint8_t v) { return v != 0; }));
}

Mask RenderSilhouette(const Camera& camera,
                      const Eigen::Matrix3Xd& vertices_W,
                      const Eigen::Matrix3Xi& triangles,
                      PixelRect* drawn) {
  PixelRect box{camera.width_px, camera.height_px, 0, 0};
  Mask mask;
  mask.width = camera.width_px;
  mask.height = camera.height_px;
  mask.pixels.assign(static_cast<size_t>(mask.width) * mask.height, 0);
  std::vector<Eigen::Vector2d> uv(static_cast<size_t>(vertices_W.cols()));
  std::vector<bool> visible(uv.size(), false);
  for (Eigen::Index i = 0; i < vertices_W.cols(); ++i) {
    const std::optional<Eigen::Vector2d> p = camera.Project(vertices_W.col(i));
    if (!p || !p->allFinite() || p->cwiseAbs().maxCoeff() > 1e6) continue;
    uv[size_t(i)] = *p;
    visible[size_t(i)] = true;
  }
  // Pixel (x, y) is inside when its centre — the integer point (x, y), OpenCV's convention — is
  // inside a triangle: the mask's area is the silhouette's area, with no rim. (OpenCV's
  // fillConvexPoly fills every pixel an edge touches, half a pixel all round too much.) Edges
  // shared by two triangles are owned by one (the top-left rule), so no pixel is counted twice.
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const int ia = triangles(0, t), ib = triangles(1, t), ic = triangles(2, t);
    if (!visible[size_t(ia)] || !visible[size_t(ib)] || !visible[size_t(ic)]) continue;
    Eigen::Vector2d a = uv[size_t(ia)], b = uv[size_t(ib)], c = uv[size_t(ic)];
    double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area2 == 0.0) continue;
    if (area2 < 0) {  // either winding: make it counter-clockwise in the image's (x, y)
      std::swap(b, c);
      area2 = -area2;
    }
    const int x0 = std::max(0, int(std::ceil(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(mask.width - 1, int(std::floor(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::ceil(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(mask.height - 1, int(std::floor(std::max({a.y(), b.y(), c.y()}))));
    // Edge p → q owns its points when it is a "top" or "left" edge of the triangle.
    auto owns = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
      const Eigen::Vector2d e = q - p;
      return e.y() < 0 || (e.y() == 0 && e.x() > 0);
    };
    const bool own_ab = owns(a, b), own_bc = owns(b, c), own_ca = owns(c, a);
    auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, double x, double y) {
      return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
    };
    for (int y = y0; y <= y1; ++y) {
      std::uint8_t* row = mask.pixels.data() + static_cast<size_t>(y) * mask.width;
      for (int x = x0; x <= x1; ++x) {
        const double e0 = edge(a, b, x, y), e1 = edge(b, c, x, y), e2 = edge(c, a, x, y);
        if ((e0 > 0 || (e0 == 0 && own_ab)) && (e1 > 0 || (e1 == 0 && own_bc)) &&
            (e2 > 0 || (e2 == 0 && own_ca))) {
          row[x] = 255;
          box.x0 = std::min(box.x0, x);
          box.x1 = std::max(box.x1, x + 1);
          box.y0 = std::min(box.y0, y);
          box.y1 = std::max(box.y1, y + 1);
        }
      }
    }
  }
  if (drawn != nullptr) *drawn = box.empty() ? PixelRect{} : box;
  return mask;
}

double IntersectionOverUnion(const Mask& a, const Mask& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size())
    throw std::invalid_argument("masks of different sizes");
  long both = 0, either = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const bool x = a.pixels[i] != 0, y = b.pixels[i] != 0;
    both += x && y;
    either += x || y;
  }
  return either == 0 ? 1.0 : double(both) / double(either);
}

namespace {
std::atomic<long long> built_count{0};
}  // namespace

long long BackgroundModel::BuiltCount() {
  return built_count.load();
}

BackgroundModel::BackgroundModel(capture::VideoReader& video, int num_samples) {
  ++built_count;
  const int n = video.num_frames();
  if (n < 3)
    throw InputError(
        video.info().path, "background", fmt::format("{} frames; at least 3 are needed", n));
  const int samples = std::clamp(num_samples, 3, n);
  std::vector<capture::VideoFrame> frames;
  for (int k = 0; k < samples; ++k)
    frames.push_back(video.Frame(int((long(k) * (n - 1)) / (samples - 1))));
  *this = BackgroundModel(frames);
}

BackgroundModel::BackgroundModel(const std::vector<capture::VideoFrame>& frames) {
  if (frames.empty()) throw std::invalid_argument("no frame for the background");
  width_ = frames.front().width;
  height_ = frames.front().height;
  channels_ = frames.front().channels;
  for (const capture::VideoFrame& f : frames) {
    if (f.width != width_ || f.height != height_ || f.channels != channels_)
      throw std::invalid_argument("frames of different sizes or kinds");
  }
  // The per-pixel, per-channel median.
  const size_t n = static_cast<size_t>(width_) * height_ * size_t(channels_);
  median_.resize(n);
  std::vector<std::uint8_t> values(frames.size());
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < frames.size(); ++k) values[k] = frames[k].pixels[i];
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    median_[i] = values[values.size() / 2];
  }
  capture::VideoFrame median;
  median.width = width_;
  median.height = height_;
  median.channels = channels_;
  median.pixels = median_;
  grey_ = GreyOf(median);
}

Mask BackgroundModel::Foreground(const capture::VideoFrame& frame,
                                 const BackgroundOptions& options) const {
  return Foreground(frame, options, PixelRect{0, 0, width_, height_});
}

Mask BackgroundModel::Foreground(const capture::VideoFrame& frame,
                                 const BackgroundOptions& options,
                                 const PixelRect& region) const {
  if (frame.width != width_ || frame.height != height_)
    throw std::invalid_argument("a frame of another size than the background");
  Mask mask;
  mask.width = width_;
  mask.height = height_;
  mask.pixels.assign(static_cast<size_t>(width_) * height_, 0);
  const PixelRect inside{std::max(0, region.x0),
                         std::max(0, region.y0),
                         std::min(width_, region.x1),
                         std::min(height_, region.y1)};
  if (inside.empty()) return mask;
  // The pixels the cleaning (an opening then a closing: four passes of a clean_px square) lets
  // reach the region: worked out on the region grown by that much, as the whole frame would be.
  const int reach = options.clean_px > 0 ? 2 * options.clean_px + 1 : 0;
  const cv::Rect work(std::max(0, inside.x0 - reach),
                      std::max(0, inside.y0 - reach),
                      std::min(width_, inside.x1 + reach) - std::max(0, inside.x0 - reach),
                      std::min(height_, inside.y1 + reach) - std::max(0, inside.y0 - reach));
  cv::Mat m;
  if (channels_ == 3 && frame.channels == 3) {
    // Colour: the largest difference over the three channels (skin on a grey wall can have the
    // wall's grey level). OpenCV's vectorised absdiff and max.
    const cv::Mat f(height_, width_, CV_8UC3, const_cast<std::uint8_t*>(frame.pixels.data()));
    const cv::Mat b(height_, width_, CV_8UC3, const_cast<std::uint8_t*>(median_.data()));
    cv::Mat diff;
    cv::absdiff(f(work), b(work), diff);
    cv::Mat planes[3];
    cv::split(diff, planes);
    cv::max(planes[0], planes[1], m);
    cv::max(m, planes[2], m);
  } else {
    // (a grey frame read in place; a colour one against a grey background made grey first)
    std::vector<std::uint8_t> converted;
    if (frame.channels != 1) converted = GreyOf(frame);
    const std::uint8_t* g = frame.channels == 1 ? frame.pixels.data() : converted.data();
    const cv::Mat f(height_, width_, CV_8UC1, const_cast<std::uint8_t*>(g));
    const cv::Mat b(height_, width_, CV_8UC1, const_cast<std::uint8_t*>(grey_.data()));
    cv::absdiff(f(work), b(work), m);
  }
  const int threshold =
      channels_ == 3 && frame.channels == 3 ? options.colour_threshold : options.threshold;
  cv::threshold(m, m, threshold, 255, cv::THRESH_BINARY);  // > threshold: 255
  if (options.clean_px > 0) {
    // (m is its own matrix, not a view into the frame: the cleaning sees the work rectangle's
    // edge as the frame's edge only where it is one.)
    const cv::Mat kernel =
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(options.clean_px, options.clean_px));
    cv::morphologyEx(m, m, cv::MORPH_OPEN, kernel);
    cv::morphologyEx(m, m, cv::MORPH_CLOSE, kernel);
  }
  cv::Mat out(height_, width_, CV_8UC1, mask.pixels.data());
  const cv::Rect keep(inside.x0, inside.y0, inside.x1 - inside.x0, inside.y1 - inside.y0);
  m(cv::Rect(keep.x - work.x, keep.y - work.y, keep.width, keep.height)).copyTo(out(keep));
  return mask;
}

}  // namespace acro::vision
