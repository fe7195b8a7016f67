#include "acro/pose/video_poses.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/trc.h"
#include "acro/pose/keypoints.h"
#include "acro/pose/left_right.h"

namespace acro::pose {
namespace {

using nlohmann::ordered_json;

// Frames decoded ahead on their own thread (a few, so memory stays bounded: 1080p RGB is 6 MB).
class FrameQueue {
 public:
  explicit FrameQueue(const std::filesystem::path& video) {
    capture::VideoReaderOptions options;
    options.num_threads = 1;
    reader_ = std::make_unique<capture::VideoReader>(video, options);
  }
  ~FrameQueue() { Stop(); }

  const capture::VideoInfo& info() const { return reader_->info(); }

  void Start(int first, int end) {
    first_ = first;
    end_ = end;
    thread_ = std::thread([this] { Produce(); });
  }

  // The next frame; false at the end. Rethrows the decoder's error.
  bool Next(capture::VideoFrame* frame) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return !frames_.empty() || done_; });
    if (!frames_.empty()) {
      *frame = std::move(frames_.front());
      frames_.pop_front();
      room_.notify_one();
      return true;
    }
    if (error_) std::rethrow_exception(error_);
    return false;
  }

  void Stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    room_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  double decode_s() const { return decode_s_; }

 private:
  void Produce() {
    try {
      for (int k = first_; k < end_; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        capture::VideoFrame frame;
        if (k == first_ && first_ > 0) {
          frame = reader_->Frame(k);  // the pass continues from here
        } else if (!reader_->ReadNext(&frame)) {
          throw InputError(info().path, fmt::format("frame {}", k), "the video ends before it");
        }
        decode_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::unique_lock<std::mutex> lock(mutex_);
        room_.wait(lock, [&] { return frames_.size() < 3 || stop_; });
        if (stop_) break;
        frames_.push_back(std::move(frame));
        ready_.notify_one();
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    done_ = true;
    ready_.notify_all();
  }

  std::unique_ptr<capture::VideoReader> reader_;
  int first_ = 0, end_ = 0;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable ready_, room_;
  std::deque<capture::VideoFrame> frames_;
  bool done_ = false, stop_ = false;
  std::exception_ptr error_;
  double decode_s_ = 0.0;
};

std::vector<double> Flatten(const capture::DetectedPerson& k) {
  std::vector<double> out;
  out.reserve(k.size());
  for (int c = 0; c < k.cols(); ++c)
    for (int r = 0; r < 3; ++r) out.push_back(k(r, c));
  return out;
}

std::string FrameFileName(const std::filesystem::path& video, int frame) {
  return fmt::format("{}_{:012d}_keypoints.json", video.stem().string(), frame);
}

// One frame as OpenPose writes it, with BlazePose's 33 and the tracker's state beside.
std::string FrameJson(const FramePose& pose) {
  ordered_json j;
  j["version"] = 1.3;
  j["people"] = ordered_json::array();
  if (pose.found) {
    ordered_json person;
    person["person_id"] = {-1};
    person["pose_keypoints_2d"] = Flatten(Body25bFromBlazePose(pose.keypoints));
    for (const char* empty : {"face_keypoints_2d", "hand_left_keypoints_2d", "hand_right_keypoints_2d",
                              "pose_keypoints_3d", "face_keypoints_3d", "hand_left_keypoints_3d",
                              "hand_right_keypoints_3d"})
      person[empty] = ordered_json::array();
    person["blazepose_keypoints_2d"] = Flatten(pose.keypoints);
    j["people"].push_back(person);
  }
  ordered_json a;
  a["frame"] = pose.frame;
  a["time_s"] = pose.time_s;
  a["found"] = pose.found;
  a["how"] = pose.how;
  a["pose_score"] = pose.pose_score;
  a["quality"] = pose.quality;
  a["swapped_groups"] = pose.swapped_groups;
  a["roi"] = {pose.roi_centre_px.x(), pose.roi_centre_px.y(), pose.roi_size_px, pose.roi_rotation_rad};
  a["velocity_px"] = {pose.velocity_px.x(), pose.velocity_px.y()};
  a["angular_velocity_rad"] = pose.angular_velocity_rad;
  j["acrolab"] = a;
  return j.dump() + "\n";
}

// A frame file of an earlier run back into a FramePose; nullopt when it is not one of ours.
std::optional<FramePose> ReadFrameJson(const std::filesystem::path& path) {
  try {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in);
    const auto& a = j.at("acrolab");
    FramePose pose;
    pose.frame = a.at("frame").get<int>();
    pose.time_s = a.at("time_s").get<double>();
    pose.found = a.at("found").get<bool>();
    pose.how = a.at("how").get<std::string>();
    pose.pose_score = a.at("pose_score").get<double>();
    pose.quality = a.value("quality", 0.0);
    pose.swapped_groups = a.at("swapped_groups").get<int>();
    const auto roi = a.at("roi").get<std::vector<double>>();
    const auto v = a.at("velocity_px").get<std::vector<double>>();
    if (roi.size() != 4 || v.size() != 2) return std::nullopt;
    pose.roi_centre_px = {roi[0], roi[1]};
    pose.roi_size_px = roi[2];
    pose.roi_rotation_rad = roi[3];
    pose.velocity_px = {v[0], v[1]};
    pose.angular_velocity_rad = a.at("angular_velocity_rad").get<double>();
    if (pose.found) {
      const auto k = j.at("people").at(0).at("blazepose_keypoints_2d").get<std::vector<double>>();
      if (k.size() != 99) return std::nullopt;
      for (int c = 0; c < 33; ++c)
        for (int r = 0; r < 3; ++r) pose.keypoints(r, c) = k[3 * c + r];
    }
    return pose;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// What must match for an earlier run's frames to be reused.
std::string RunSignature(const capture::VideoInfo& info, const DetectVideoOptions& options) {
  ordered_json j;
  j["video"] = std::filesystem::path(info.path).filename().string();
  j["frames"] = info.num_frames;
  j["width"] = info.width;
  j["height"] = info.height;
  j["first_frame"] = options.first_frame;
  j["model"] = LandmarkModelName(options.tracker.model);
  if (options.tracker.box_px) {
    const auto& b = *options.tracker.box_px;
    j["box_px"] = {b.min().x(), b.min().y(), b.max().x(), b.max().y()};
  }
  if (options.tracker.bed_corners_px)
    for (const auto& c : *options.tracker.bed_corners_px) j["bed_px"].push_back({c.x(), c.y()});
  return j.dump() + "\n";
}

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The whole video's BODY_25B keypoints as a 2D TRC (pixels, y down, Z 0; absent = gap).
void WriteKeypointsTrc(const VideoPoses& poses, const std::filesystem::path& path) {
  capture::Trial trial;
  trial.source.path = poses.video.string();
  trial.point_rate_hz = poses.info.average_fps > 0 ? poses.info.average_fps : 30.0;
  trial.first_frame = poses.first_frame + 1;
  trial.num_frames = static_cast<int>(poses.frames.size());
  const auto& names = capture::KeypointSetNames("body25b");
  for (const std::string& name : names) {
    capture::PointInfo info;
    info.label = name;
    info.unit = "m";
    trial.points.push_back(info);
  }
  trial.positions.setConstant(3, static_cast<Eigen::Index>(trial.num_frames) * names.size(), std::nan(""));
  for (int f = 0; f < trial.num_frames; ++f) {
    if (!poses.frames[f].found) continue;
    const capture::DetectedPerson k = Body25bFromBlazePose(poses.frames[f].keypoints);
    for (int p = 0; p < static_cast<int>(names.size()); ++p)
      if (k(2, p) > 0) trial.position(f, p) = Eigen::Vector3d(k(0, p), k(1, p), 0.0);
  }
  capture::TrcWriteOptions options;
  options.units = "m";
  options.decimals = 3;
  capture::WriteTrc(trial, path, options);
}

std::string KeypointsCsv(const VideoPoses& poses) {
  std::string out = "frame,time_s,keypoint,u_px,v_px,confidence\n";
  const auto& names = BlazePoseNames();
  for (const FramePose& f : poses.frames) {
    if (!f.found) continue;
    for (int k = 0; k < 33; ++k)
      out += fmt::format("{},{:.6f},{},{:.3f},{:.3f},{:.4f}\n", f.frame, f.time_s, names[k], f.keypoints(0, k),
                         f.keypoints(1, k), f.keypoints(2, k));
  }
  return out;
}

// Runs of frames with a pose shorter than kMinTrackFrames, marked as without one; how many frames.
constexpr int kMinTrackFrames = 3;
int DropShortTracks(std::vector<FramePose>* frames) {
  int dropped = 0;
  for (std::size_t begin = 0; begin < frames->size();) {
    std::size_t end = begin;
    while (end < frames->size() && (*frames)[end].found) ++end;
    if (end > begin && end - begin < kMinTrackFrames)
      for (std::size_t k = begin; k < end; ++k) {
        FramePose& f = (*frames)[k];
        f.found = false;
        f.keypoints.row(2).setZero();
        ++dropped;
      }
    begin = end == begin ? begin + 1 : end;
  }
  return dropped;
}

}  // namespace

bool DetectVideoOptions::IsValid(std::string* why) const {
  if (first_frame < 0 || (end_frame >= 0 && end_frame <= first_frame)) {
    if (why) *why = fmt::format("frames {}:{} is not a range A:B with 0 ≤ A < B", first_frame, end_frame);
    return false;
  }
  return tracker.IsValid(why);
}

int VideoPoses::frames_with_pose() const {
  return static_cast<int>(std::count_if(frames.begin(), frames.end(), [](const FramePose& f) { return f.found; }));
}

double VideoPoses::median_confidence() const {
  std::vector<double> c;
  for (const FramePose& f : frames)
    if (f.found)
      for (int k = 0; k < 33; ++k) c.push_back(f.keypoints(2, k));
  if (c.empty()) return 0.0;
  std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
  return c[c.size() / 2];
}

void SetNetworkThreads(int threads) { cv::setNumThreads(std::max(1, threads)); }

std::filesystem::path VideoOutputDirectory(const std::filesystem::path& output_dir,
                                           const std::filesystem::path& video) {
  return output_dir / video.stem();
}

VideoPoses DetectVideoPoses(const std::filesystem::path& video, const std::filesystem::path& directory,
                            const DetectVideoOptions& options, const Progress& progress) {
  DemandValidOptions(options, "detect");
  const auto start = std::chrono::steady_clock::now();
  VideoPoses result;
  result.video = video;
  // The networks first: a missing model is said before any work.
  PoseTracker tracker(options.tracker);

  FrameQueue frames(video);
  result.info = frames.info();
  const int n = result.info.num_frames;
  result.first_frame = options.first_frame;
  result.end_frame = options.end_frame < 0 ? n : options.end_frame;
  if (result.first_frame >= n || result.end_frame > n)
    throw InputError(video.string(), "--frames",
                     fmt::format("{}:{} outside the video's {} frames (0:{})", result.first_frame,
                                 options.end_frame < 0 ? std::string("") : std::to_string(options.end_frame), n, n));

  // An earlier run's frames: kept when it detected the same video with the same settings.
  const std::filesystem::path json_dir = directory / "json";
  CreateOutputDirectory(json_dir);
  const std::string signature = RunSignature(result.info, options);
  const bool same_run = options.resume && IsRegularFile(directory / "detect_run.json") && ReadText(directory / "detect_run.json") == signature;
  if (!same_run) {
    for (const auto& entry : std::filesystem::directory_iterator(json_dir))
      if (entry.path().extension() == ".json") std::filesystem::remove(entry.path());
    WriteFileAtomically(directory / "detect_run.json", signature);
  }
  int next = result.first_frame;
  if (same_run) {
    while (next < result.end_frame) {
      auto pose = ReadFrameJson(json_dir / FrameFileName(video, next));
      if (!pose || pose->frame != next) break;
      result.frames.push_back(*pose);
      ++next;
    }
    result.frames_resumed = static_cast<int>(result.frames.size());
    if (!result.frames.empty()) tracker.Resume(result.frames.back());
  }

  // The remaining frames, decoded ahead on their own thread.
  const int total = result.end_frame - result.first_frame;
  if (next < result.end_frame) {
    frames.Start(next, result.end_frame);
    capture::VideoFrame frame;
    while (frames.Next(&frame)) {
      if (!progress.Report("detect", static_cast<int>(result.frames.size()), total)) {
        frames.Stop();
        throw Cancelled(fmt::format("cancelled after {} of {} frames (a second run resumes)", result.frames.size(), total));
      }
      FramePose pose = tracker.Track(frame);
      WriteFileAtomically(json_dir / FrameFileName(video, pose.frame), FrameJson(pose));
      result.frames.push_back(std::move(pose));
    }
    result.decode_s = frames.decode_s();
  }
  progress.Report("detect", total, total);
  // A pose seen in fewer than kMinTrackFrames frames in a row is not a person (a pattern that
  // looked like one for a moment: a person stays); then left and right made continuous over the
  // whole video. The frames changed are written again.
  const std::vector<FramePose> before = result.frames;
  result.frames_dropped = DropShortTracks(&result.frames);
  result.frames_repaired = RepairLeftRight(&result.frames);
  for (std::size_t k = 0; k < result.frames.size(); ++k)
    if (result.frames[k].swapped_groups != before[k].swapped_groups || result.frames[k].found != before[k].found)
      WriteFileAtomically(json_dir / FrameFileName(video, result.frames[k].frame), FrameJson(result.frames[k]));
  result.timing = tracker.timing();
  if (result.frames_with_pose() == 0)
    result.warnings.push_back(fmt::format("{}: nobody found in frames {}–{}", video.string(), result.first_frame,
                                          result.end_frame - 1));
  result.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  WriteKeypointsTrc(result, directory / "keypoints_2d.trc");
  WriteFileAtomically(directory / "blazepose_2d.csv", KeypointsCsv(result));
  WriteFileAtomically(directory / "detect.json", FormatVideoPosesJson(result, options));
  return result;
}

std::string FormatVideoPosesJson(const VideoPoses& poses, const DetectVideoOptions& options) {
  ordered_json j;
  j["video"] = poses.video.string();
  j["model"] = LandmarkModelName(options.tracker.model);
  j["first_frame"] = poses.first_frame;
  j["end_frame"] = poses.end_frame;
  j["frames"] = poses.frames.size();
  j["frames_with_pose"] = poses.frames_with_pose();
  j["frames_resumed"] = poses.frames_resumed;
  j["median_confidence"] = poses.median_confidence();
  const int run = static_cast<int>(poses.frames.size()) - poses.frames_resumed;
  const double per = run > 0 ? 1000.0 / run : 0.0;
  j["ms_per_frame"] = poses.elapsed_s * per;
  j["decode_ms_per_frame"] = poses.decode_s * per;
  j["crop_ms_per_frame"] = poses.timing.crop_s * per;
  j["network_ms_per_frame"] = poses.timing.network_s * per;
  j["post_ms_per_frame"] = poses.timing.post_s * per;
  j["detector_runs"] = poses.timing.detector_runs;
  j["landmark_runs"] = poses.timing.landmark_runs;
  j["frames_left_right_repaired"] = poses.frames_repaired;
  j["frames_dropped_short_tracks"] = poses.frames_dropped;
  j["warnings"] = poses.warnings;
  return j.dump(2) + "\n";
}

}  // namespace acro::pose
