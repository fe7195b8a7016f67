#pragma once

// RGB buffers (3 bytes per pixel, the layout of video frames) in and out of Cairo's RGB24 image
// surfaces (a 32-bit word 0x00RRGGBB per pixel).

#include <cairo.h>

#include <cstdint>
#include <span>
#include <vector>

namespace acro::ui::internal {

/// A new RGB24 surface holding the pixels; the caller destroys it.
inline cairo_surface_t* SurfaceFromRgb(int width, int height, std::span<const std::uint8_t> rgb) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  const int stride = cairo_image_surface_get_stride(surface);
  cairo_surface_flush(surface);
  std::uint8_t* data = cairo_image_surface_get_data(surface);
  for (int y = 0; y < height; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<size_t>(y) * stride);
    const std::uint8_t* src = rgb.data() + 3 * static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x)
      row[x] =
          (std::uint32_t{src[3 * x]} << 16) | (std::uint32_t{src[3 * x + 1]} << 8) | src[3 * x + 2];
  }
  cairo_surface_mark_dirty(surface);
  return surface;
}

/// The surface's pixels back into an RGB buffer of its size.
inline void RgbFromSurface(cairo_surface_t* surface, std::vector<std::uint8_t>* rgb) {
  cairo_surface_flush(surface);
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const std::uint8_t* data = cairo_image_surface_get_data(surface);
  rgb->resize(3 * static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y) {
    const auto* row =
        reinterpret_cast<const std::uint32_t*>(data + static_cast<size_t>(y) * stride);
    std::uint8_t* dst = rgb->data() + 3 * static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      dst[3 * x] = static_cast<std::uint8_t>(row[x] >> 16);
      dst[3 * x + 1] = static_cast<std::uint8_t>(row[x] >> 8);
      dst[3 * x + 2] = static_cast<std::uint8_t>(row[x]);
    }
  }
}

}  // namespace acro::ui::internal
