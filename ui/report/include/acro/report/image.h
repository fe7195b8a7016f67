#pragma once

// Raster images out of the report layer: an RGB picture (a video frame, a rendered view) as PNG,
// through Cairo's encoder, written atomically.

#include <cstdint>
#include <filesystem>
#include <span>

namespace acro::ui {

/// Writes `rgb` (3 bytes per pixel, rows top to bottom, width × height) as a PNG file, atomically.
/// Throws acro::InputError for a size that does not match the pixels or a file that cannot be
/// written.
void WriteRgbPng(int width,
                 int height,
                 std::span<const std::uint8_t> rgb,
                 const std::filesystem::path& path);

}  // namespace acro::ui
