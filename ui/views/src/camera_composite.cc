#include "acro/views/camera_composite.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace acro::ui {

namespace {

constexpr int kGrid = 4;  // the undistortion is solved every kGrid pixels and interpolated

bool HasDistortion(const vision::Camera& camera) {
  return std::any_of(
      camera.distortion.begin(), camera.distortion.end(), [](double k) { return k != 0.0; });
}

// out = c + (255 − a) · out / 255 for one pixel.
inline void Over(const std::uint8_t* c, std::uint8_t* o) {
  const int keep = 255 - c[3];
  for (int ch = 0; ch < 3; ++ch)
    o[ch] = static_cast<std::uint8_t>(std::min(255, c[ch] + (o[ch] * keep + 127) / 255));
}

}  // namespace

void BlendOver(const RenderImage& image,
               int x0,
               int y0,
               int width,
               int height,
               std::vector<std::uint8_t>* rgb) {
  if (rgb->size() != size_t(width) * size_t(height) * 3)
    throw std::invalid_argument("BlendOver: the frame is not width × height × 3 bytes");
  for (int y = std::max(0, -y0); y < image.height && y + y0 < height; ++y) {
    for (int x = std::max(0, -x0); x < image.width && x + x0 < width; ++x) {
      const std::uint8_t* c = image.rgba.data() + (size_t(y) * size_t(image.width) + size_t(x)) * 4;
      if (c[3] == 0) continue;
      Over(c, rgb->data() + (size_t(y + y0) * size_t(width) + size_t(x + x0)) * 3);
    }
  }
}

CameraComposite::CameraComposite(const vision::Camera& camera, double max_canvas_scale)
    : camera_(camera), render_camera_(camera) {
  render_camera_.distortion.clear();
  warps_ = HasDistortion(camera);
  if (!warps_) return;
  const int W = camera.width_px, H = camera.height_px;
  // The undistorted position of every kGrid-th pixel, and of the last row and column.
  const int gw = (W - 1) / kGrid + 2, gh = (H - 1) / kGrid + 2;
  std::vector<Eigen::Vector2d> grid(size_t(gw) * size_t(gh));
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (int j = 0; j < gh; ++j) {
    for (int i = 0; i < gw; ++i) {
      const Eigen::Vector2d uv(std::min(i * kGrid, W - 1 + kGrid),
                               std::min(j * kGrid, H - 1 + kGrid));
      const Eigen::Vector2d u = camera.Undistort(uv);
      grid[size_t(j) * size_t(gw) + size_t(i)] = u;
      if (!std::isfinite(u.x()) || !std::isfinite(u.y())) continue;
      min_x = std::min(min_x, u.x());
      max_x = std::max(max_x, u.x());
      min_y = std::min(min_y, u.y());
      max_y = std::max(max_y, u.y());
    }
  }
  // The canvas: every undistorted position plus a pixel for the bilinear taps, within the limit.
  const double cx = camera.K(0, 2), cy = camera.K(1, 2);
  min_x = std::max(min_x, cx - max_canvas_scale * W / 2);
  max_x = std::min(max_x, cx + max_canvas_scale * W / 2);
  min_y = std::max(min_y, cy - max_canvas_scale * H / 2);
  max_y = std::min(max_y, cy + max_canvas_scale * H / 2);
  const int x0 = static_cast<int>(std::floor(min_x)) - 1;
  const int y0 = static_cast<int>(std::floor(min_y)) - 1;
  const int cw = static_cast<int>(std::ceil(max_x)) + 2 - x0;
  const int ch = static_cast<int>(std::ceil(max_y)) + 2 - y0;
  render_camera_.width_px = cw;
  render_camera_.height_px = ch;
  render_camera_.K(0, 2) = cx - x0;
  render_camera_.K(1, 2) = cy - y0;

  if (cw > 32767 || ch > 32767)
    throw std::invalid_argument("CameraComposite: camera " + camera.name + " needs a canvas of " +
                                std::to_string(cw) + " x " + std::to_string(ch) + " px");
  tap_x_.assign(size_t(W) * size_t(H), -1);
  tap_y_.assign(tap_x_.size(), 0);
  weight_x_.assign(tap_x_.size(), 0);
  weight_y_.assign(tap_x_.size(), 0);
  for (int v = 0; v < H; ++v) {
    const int j = v / kGrid;
    const double b = double(v - j * kGrid) / kGrid;
    for (int u = 0; u < W; ++u) {
      const int i = u / kGrid;
      const double a = double(u - i * kGrid) / kGrid;
      const auto g = [&](int di, int dj) {
        return grid[size_t(j + dj) * size_t(gw) + size_t(i + di)];
      };
      const Eigen::Vector2d p =
          (1 - b) * ((1 - a) * g(0, 0) + a * g(1, 0)) + b * ((1 - a) * g(0, 1) + a * g(1, 1));
      const double x = p.x() - x0, y = p.y() - y0;
      if (!(x >= 0 && y >= 0 && x < cw - 1 && y < ch - 1)) continue;
      int xi = static_cast<int>(x), yi = static_cast<int>(y);
      const size_t k = size_t(v) * size_t(W) + size_t(u);
      // Rounded to 1/256 px; a weight of 256 would not fit: the next tap takes it.
      int wx = static_cast<int>(std::lround((x - xi) * 256));
      int wy = static_cast<int>(std::lround((y - yi) * 256));
      if (wx == 256) {
        if (++xi >= cw - 1) continue;
        wx = 0;
      }
      if (wy == 256) {
        if (++yi >= ch - 1) continue;
        wy = 0;
      }
      tap_x_[k] = static_cast<std::int16_t>(xi);
      tap_y_[k] = static_cast<std::int16_t>(yi);
      weight_x_[k] = static_cast<std::uint8_t>(wx);
      weight_y_[k] = static_cast<std::uint8_t>(wy);
    }
  }
}

PixelBox CameraComposite::RenderRegion(const PixelBox& frame_box) const {
  const int W = camera_.width_px, H = camera_.height_px;
  const PixelBox f{std::clamp(frame_box.x0, 0, W),
                   std::clamp(frame_box.y0, 0, H),
                   std::clamp(frame_box.x1, 0, W),
                   std::clamp(frame_box.y1, 0, H)};
  if (f.empty()) return {};
  if (!warps_) return f;
  // The taps of the box's border (a sane distortion maps the inside inside), and one more pixel
  // for the bilinear neighbours.
  PixelBox r{render_camera_.width_px, render_camera_.height_px, 0, 0};
  const auto add = [&](int u, int v) {
    const size_t k = size_t(v) * size_t(W) + size_t(u);
    if (tap_x_[k] < 0) return;
    r.x0 = std::min<int>(r.x0, tap_x_[k]);
    r.y0 = std::min<int>(r.y0, tap_y_[k]);
    r.x1 = std::max<int>(r.x1, tap_x_[k] + 2);
    r.y1 = std::max<int>(r.y1, tap_y_[k] + 2);
  };
  for (int u = f.x0; u < f.x1; ++u) {
    add(u, f.y0);
    add(u, f.y1 - 1);
  }
  for (int v = f.y0; v < f.y1; ++v) {
    add(f.x0, v);
    add(f.x1 - 1, v);
  }
  return r;
}

void CameraComposite::Composite(const RenderImage& render, std::vector<std::uint8_t>* rgb) const {
  Composite(render, PixelBox{0, 0, camera_.width_px, camera_.height_px}, rgb);
}

void CameraComposite::Composite(const RenderImage& render,
                                const PixelBox& frame_box,
                                std::vector<std::uint8_t>* rgb) const {
  const int W = camera_.width_px, H = camera_.height_px;
  if (rgb->size() != size_t(W) * size_t(H) * 3)
    throw std::invalid_argument("CameraComposite: the frame is not the camera's size");
  if (render.x0 < 0 || render.y0 < 0 || render.x0 + render.width > render_camera_.width_px ||
      render.y0 + render.height > render_camera_.height_px)
    throw std::invalid_argument("CameraComposite: the render is not a part of the canvas");
  const PixelBox f{std::clamp(frame_box.x0, 0, W),
                   std::clamp(frame_box.y0, 0, H),
                   std::clamp(frame_box.x1, 0, W),
                   std::clamp(frame_box.y1, 0, H)};
  std::uint8_t* out = rgb->data();
  const std::uint8_t* in = render.rgba.data();
  const int row = render.width * 4;
  for (int v = f.y0; v < f.y1; ++v) {
    for (int u = f.x0; u < f.x1; ++u) {
      const size_t k = size_t(v) * size_t(W) + size_t(u);
      if (!warps_) {
        // The render is the frame's own geometry.
        const int x = u - render.x0, y = v - render.y0;
        if (x < 0 || y < 0 || x >= render.width || y >= render.height) continue;
        const std::uint8_t* c = in + (size_t(y) * size_t(render.width) + size_t(x)) * 4;
        if (c[3] != 0) Over(c, out + 3 * k);
        continue;
      }
      if (tap_x_[k] < 0) continue;
      const int x = tap_x_[k] - render.x0, y = tap_y_[k] - render.y0;
      if (x < 0 || y < 0 || x + 1 >= render.width || y + 1 >= render.height) continue;
      const std::uint8_t* p00 = in + y * row + x * 4;
      const std::uint8_t* p10 = p00 + 4;
      const std::uint8_t* p01 = p00 + row;
      const std::uint8_t* p11 = p01 + 4;
      if ((p00[3] | p10[3] | p01[3] | p11[3]) == 0) continue;
      const int wx = weight_x_[k], wy = weight_y_[k];
      const int w00 = (256 - wx) * (256 - wy), w10 = wx * (256 - wy), w01 = (256 - wx) * wy,
                w11 = wx * wy;  // sum 65536
      std::uint8_t c[4];
      for (int ch = 0; ch < 4; ++ch)
        c[ch] = static_cast<std::uint8_t>(
            (p00[ch] * w00 + p10[ch] * w10 + p01[ch] * w01 + p11[ch] * w11 + 32768) >> 16);
      Over(c, out + 3 * k);
    }
  }
}

}  // namespace acro::ui
