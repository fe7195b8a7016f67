#include "acro/pipeline/detect.h"

#include <algorithm>
#include <mutex>

#include "acro/base/parallel.h"
#include "acro/pose/keypoints.h"

#include <unistd.h>

#include <cstdlib>
#include <string>
#include <system_error>

#include "acro/base/content_hash.h"
#include "acro/base/input_error.h"
#include "acro/pose/pose_models.h"
#include "acro/vision/bed_detection.h"

namespace acro::pipeline {

void RegionFromBed(const std::filesystem::path& video,
                   int frame,
                   bool required,
                   pose::PoseTrackerOptions* tracker) {
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

pose::VideoPoses DetectPosesInCache(const std::filesystem::path& video,
                                    pose::LandmarkModel model,
                                    const Progress& progress) {
  pose::DetectVideoOptions options;
  options.tracker.model = model;
  pose::FindPoseModels(model);  // a missing network: its one line, before any frame is read
  RegionFromBed(video, 0, false, &options.tracker);
  return pose::DetectVideoPoses(video, PoseCacheDirectory(video), options, progress);
}

std::vector<pose::VideoPoses> DetectPosesInCache(const std::vector<std::filesystem::path>& videos,
                                                 pose::LandmarkModel model,
                                                 const Progress& progress) {
  pose::FindPoseModels(model);
  const int at_once = std::max(1, std::min<int>(WorkerThreads(0), static_cast<int>(videos.size())));
  pose::SetNetworkThreads(std::max(1, WorkerThreads(0) / at_once));
  std::mutex mutex;
  std::vector<int> done(videos.size(), 0), total(videos.size(), 0);
  bool cancelled = false;
  std::vector<pose::VideoPoses> results(videos.size());
  ParallelFor(
      static_cast<int>(videos.size()),
      at_once,
      [&](int v) {
        Progress mine;
        mine.report = [&, v](const std::string&, int d, int t) {
          std::lock_guard<std::mutex> lock(mutex);
          done[v] = d;
          total[v] = t;
          int sum_done = 0, sum_total = 0;
          for (size_t k = 0; k < done.size(); ++k) {
            sum_done += done[k];
            sum_total += total[k];
          }
          if (!cancelled && !progress.Report("detect", sum_done, sum_total)) cancelled = true;
          return !cancelled;
        };
        results[v] = DetectPosesInCache(videos[v], model, mine);
      },
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return !cancelled;
      });
  if (cancelled) throw Cancelled();
  return results;
}

capture::KeypointDetections Body25bDetections(const pose::VideoPoses& poses) {
  capture::KeypointDetections d;
  d.source = poses.video.string();
  d.names = capture::KeypointSetNames("body25b");
  d.frames.resize(static_cast<size_t>(std::max(0, poses.end_frame)));
  for (const pose::FramePose& f : poses.frames)
    if (f.found && f.frame >= 0 && f.frame < static_cast<int>(d.frames.size()))
      d.frames[f.frame].push_back(pose::Body25bFromBlazePose(f.keypoints));
  d.warnings = poses.warnings;
  return d;
}

}  // namespace acro::pipeline
