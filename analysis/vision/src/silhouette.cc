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
                      const Eigen::Matrix3Xi& triangles) {
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
            (e2 > 0 || (e2 == 0 && own_ca)))
          row[x] = 255;
      }
    }
  }
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

long long BackgroundModel::BuiltCount() { return built_count.load(); }

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
  if (frame.width != width_ || frame.height != height_)
    throw std::invalid_argument("a frame of another size than the background");
  Mask mask;
  mask.width = width_;
  mask.height = height_;
  mask.pixels.resize(static_cast<size_t>(width_) * height_);
  if (channels_ == 3 && frame.channels == 3) {
    // Colour: the largest difference over the three channels (skin on a grey wall can have the
    // wall's grey level).
    for (size_t i = 0; i < mask.pixels.size(); ++i) {
      const std::uint8_t* p = frame.pixels.data() + 3 * i;
      const std::uint8_t* q = median_.data() + 3 * i;
      const int d = std::max({std::abs(int(p[0]) - int(q[0])),
                              std::abs(int(p[1]) - int(q[1])),
                              std::abs(int(p[2]) - int(q[2]))});
      mask.pixels[i] = d > options.colour_threshold ? 255 : 0;
    }
  } else {
    const std::vector<std::uint8_t> g = GreyOf(frame);
    for (size_t i = 0; i < g.size(); ++i)
      mask.pixels[i] = std::abs(int(g[i]) - int(grey_[i])) > options.threshold ? 255 : 0;
  }
  if (options.clean_px > 0) {
    cv::Mat m(height_, width_, CV_8UC1, mask.pixels.data());
    const cv::Mat kernel =
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(options.clean_px, options.clean_px));
    cv::morphologyEx(m, m, cv::MORPH_OPEN, kernel);
    cv::morphologyEx(m, m, cv::MORPH_CLOSE, kernel);
  }
  return mask;
}

}  // namespace acro::vision
