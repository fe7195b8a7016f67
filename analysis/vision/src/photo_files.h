#pragma once

// Which inputs are photos (read by OpenCV's imread) rather than videos (read by our decoder): the
// calibration's board pictures and the bed detector's frame.

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <string>

#include "acro/base/file_io.h"

namespace acro::vision {

inline bool IsPhotoFile(const std::filesystem::path& path) {
  static const char* const kPhotos[] = {
      "jpg", "jpeg", "png", "bmp", "tif", "tiff", "webp", "pgm", "ppm"};
  const std::string ext = LowerExtension(path);
  return std::find(std::begin(kPhotos), std::end(kPhotos), ext) != std::end(kPhotos);
}

}  // namespace acro::vision
