#include "acro/pipeline/detect.h"

#include <unistd.h>

#include <cstdlib>
#include <string>
#include <system_error>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/pose/pose_models.h"
#include "acro/vision/bed_detection.h"

namespace acro::pipeline {

void RegionFromBed(const std::filesystem::path& video, int frame, bool required, pose::PoseTrackerOptions* tracker) {
  try {
    tracker->bed_corners_px = vision::DetectBed(video, frame).corners_px;
  } catch (const InputError&) {
    if (required) throw;
  }
}

namespace {

// A folder this process can create and write in (made when it can be).
bool Writable(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  return !ec && ::access(dir.c_str(), W_OK | X_OK) == 0;
}

std::filesystem::path UserCache() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    return std::filesystem::path(cache) / "acrolab" / "detect";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "acrolab" / "detect";
  return std::filesystem::temp_directory_path() / "acrolab-detect";
}

}  // namespace

std::filesystem::path PoseCacheDirectory(const std::filesystem::path& video) {
  const std::filesystem::path absolute = std::filesystem::absolute(video).lexically_normal();
  const std::filesystem::path beside = absolute.parent_path() / "acrolab-detect";
  if (Writable(beside)) return pose::VideoOutputDirectory(beside, video);
  const std::string key = Sha256Hex(absolute.string()).substr(0, 16);
  return pose::VideoOutputDirectory(UserCache() / key, video);
}

pose::VideoPoses DetectPosesInCache(const std::filesystem::path& video, pose::LandmarkModel model,
                                    const Progress& progress) {
  pose::DetectVideoOptions options;
  options.tracker.model = model;
  pose::FindPoseModels(model);  // a missing network: its one line, before any frame is read
  RegionFromBed(video, 0, false, &options.tracker);
  return pose::DetectVideoPoses(video, PoseCacheDirectory(video), options, progress);
}

}  // namespace acro::pipeline
