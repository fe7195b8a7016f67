#include "acro/report/image.h"

#include <cairo.h>

#include <string>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::ui {

void WriteRgbPng(int width,
                 int height,
                 std::span<const std::uint8_t> rgb,
                 const std::filesystem::path& path) {
  if (width <= 0 || height <= 0 || rgb.size() != 3 * static_cast<size_t>(width) * height) {
    throw InputError(
        path.string(),
        "",
        fmt::format("{} bytes are not a {} x {} RGB image", rgb.size(), width, height));
  }
  // Cairo's RGB24 pixels are 32-bit words 0x00RRGGBB.
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
  std::string png;
  const cairo_status_t status = cairo_surface_write_to_png_stream(
      surface,
      [](void* closure, const unsigned char* bytes, unsigned int length) {
        static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(bytes), length);
        return CAIRO_STATUS_SUCCESS;
      },
      &png);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw InputError(
        path.string(), "", std::string("PNG encoding failed: ") + cairo_status_to_string(status));
  WriteFileAtomically(path, png);
}

}  // namespace acro::ui
