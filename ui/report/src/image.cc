#include "acro/report/image.h"

#include <cairo.h>

#include <string>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "rgb_surface.h"

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
  cairo_surface_t* surface = internal::SurfaceFromRgb(width, height, rgb);
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
