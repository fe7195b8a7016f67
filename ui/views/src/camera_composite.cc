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

void BlendOver(const RenderImage& image, int x0, int y0, int width, int height,
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
      const Eigen::Vector2d uv(std::min(i * kGrid, W - 1 + kGrid), std::min(j * kGrid, H - 1 + kGrid));
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

  tap_.assign(size_t(W) * size_t(H), -1);
  weight_x_.assign(tap_.size(), 0);
  weight_y_.assign(tap_.size(), 0);
  for (int v = 0; v < H; ++v) {
    const int j = v / kGrid;
    const double b = double(v - j * kGrid) / kGrid;
    for (int u = 0; u < W; ++u) {
      const int i = u / kGrid;
      const double a = double(u - i * kGrid) / kGrid;
      const auto g = [&](int di, int dj) { return grid[size_t(j + dj) * size_t(gw) + size_t(i + di)]; };
      const Eigen::Vector2d p = (1 - b) * ((1 - a) * g(0, 0) + a * g(1, 0)) +
                                b * ((1 - a) * g(0, 1) + a * g(1, 1));
      const double x = p.x() - x0, y = p.y() - y0;
      if (!(x >= 0 && y >= 0 && x < cw - 1 && y < ch - 1)) continue;
      const int xi = static_cast<int>(x), yi = static_cast<int>(y);
      const size_t k = size_t(v) * size_t(W) + size_t(u);
      tap_[k] = (yi * cw + xi) * 4;
      // Rounded to 1/256 px; a weight of 256 would not fit: the next tap takes it.
      int wx = static_cast<int>(std::lround((x - xi) * 256)), wy = static_cast<int>(std::lround((y - yi) * 256));
      if (wx == 256 || wy == 256) {
        const int xs = wx == 256 ? 1 : 0, ys = wy == 256 ? 1 : 0;
        if (xi + xs >= cw - 1 || yi + ys >= ch - 1) continue;
        tap_[k] += (ys * cw + xs) * 4;
        if (wx == 256) wx = 0;
        if (wy == 256) wy = 0;
      }
      weight_x_[k] = static_cast<std::uint8_t>(wx);
      weight_y_[k] = static_cast<std::uint8_t>(wy);
    }
  }
}

void CameraComposite::Composite(const RenderImage& render, std::vector<std::uint8_t>* rgb) const {
  const int W = camera_.width_px, H = camera_.height_px;
  if (render.width != render_camera_.width_px || render.height != render_camera_.height_px)
    throw std::invalid_argument("CameraComposite: the render is " + std::to_string(render.width) +
                                " x " + std::to_string(render.height) + " px, not the canvas' " +
                                std::to_string(render_camera_.width_px) + " x " +
                                std::to_string(render_camera_.height_px));
  if (rgb->size() != size_t(W) * size_t(H) * 3)
    throw std::invalid_argument("CameraComposite: the frame is not the camera's size");
  std::uint8_t* out = rgb->data();
  const std::uint8_t* in = render.rgba.data();
  if (!warps_) {
    const size_t n = size_t(W) * size_t(H);
    for (size_t k = 0; k < n; ++k) {
      const std::uint8_t* c = in + 4 * k;
      if (c[3] == 0) continue;
      Over(c, out + 3 * k);
    }
    return;
  }
  const int row = render.width * 4;
  const size_t n = size_t(W) * size_t(H);
  for (size_t k = 0; k < n; ++k) {
    const std::int32_t t = tap_[k];
    if (t < 0) continue;
    const std::uint8_t* p00 = in + t;
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

}  // namespace acro::ui
