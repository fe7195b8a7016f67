#include "acro/pose/pose_tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "acro/base/input_error.h"
#include "acro/pose/keypoints.h"
#include "networks.h"

namespace acro::pose {

using internal::LandmarkResult;
using internal::PersonCandidate;
using internal::Roi;
using internal::WrapAngle;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// A pose found without a track must be believed (LandmarkResult::Quality): an upside-down fit of
// an upright body scored 0.34–0.37 on the sample video, right fits 0.79–0.99.
constexpr double kMinAcquiredQuality = 0.5;

}  // namespace

bool PoseTrackerOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(min_pose_score > 0 && min_pose_score < 1)) return fail(fmt::format("min_pose_score {} not in (0, 1)", min_pose_score));
  if (!(min_detection_score > 0 && min_detection_score < 1))
    return fail(fmt::format("min_detection_score {} not in (0, 1)", min_detection_score));
  if (search_every_frames < 1) return fail(fmt::format("search_every_frames {} < 1", search_every_frames));
  if (box_px && (box_px->isEmpty() || !(box_px->sizes().array() >= 8).all() || !box_px->min().allFinite() ||
                 !box_px->max().allFinite()))
    return fail("the box is empty, smaller than 8 px or not finite");
  if (bed_corners_px)
    for (const auto& c : *bed_corners_px)
      if (!c.allFinite()) return fail("a bed corner is not finite");
  return true;
}

struct PoseTracker::Impl {
  PoseTrackerOptions options;
  internal::PersonDetectorNet detector;
  internal::LandmarkNet landmarks;
  PoseTiming timing;

  // The track.
  bool active = false;
  Roi roi;  // from the last pose: where the next frame looks (before the motion is added)
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  double omega = 0.0;
  double size_ema = 0.0;
  int poses_in_track = 0;
  int doubtful_in_a_row = 0;  // tracked poses taken on continuity with a low pose flag (FollowsClosely)
  // Where the athlete was last seen, for a lost track's search.
  std::optional<Roi> last_seen;
  int frames_since_seen = 0;
  int frame_counter = 0;
  int image_width = 0, image_height = 0;

  Impl(const PoseTrackerOptions& o, const PoseModelFiles& files)
      : options(o), detector(files.detector), landmarks(files.landmarks) {}

  LandmarkResult RunLandmarks(const cv::Mat& rgb, const Roi& r) { return landmarks.Run(rgb, r); }

  std::vector<PersonCandidate> RunDetector(const cv::Mat& rgb, const cv::Rect2d& region) {
    return detector.Detect(rgb, region, options.min_detection_score);
  }

  // The networks' stage times, summed.
  const PoseTiming& Timing() {
    const internal::StageTimes& d = detector.times();
    const internal::StageTimes& l = landmarks.times();
    timing.crop_s = d.crop_s + l.crop_s;
    timing.network_s = d.network_s + l.network_s;
    timing.post_s = d.post_s + l.post_s;
    timing.detector_runs = d.runs;
    timing.landmark_runs = l.runs;
    return timing;
  }

  // A pose is taken when the network sees a person and the region it implies follows on from the
  // one predicted: the centre within 0.6 of the region's size, the size within a factor 2.5, the
  // direction within 75° (a somersault turns 5–25° per frame at 30 fps).
  bool Consistent(const LandmarkResult& r, const std::optional<Roi>& predicted) const {
    if (!(r.pose_score > options.min_pose_score) || !r.landmarks.allFinite()) return false;
    if (!predicted) return true;
    const Roi next = r.NextRoi();
    if ((next.centre_px - predicted->centre_px).norm() > 0.6 * predicted->size_px) return false;
    if (next.size_px < predicted->size_px / 2.5 || next.size_px > predicted->size_px * 2.5) return false;
    return std::abs(WrapAngle(next.rotation - predicted->rotation)) < 75 * kDeg;
  }

  // A fit whose region goes on exactly as the track moves — centre within a quarter of the region,
  // size within 25 %, turn within 20° of the prediction — is the athlete even when the network's
  // pose flag drops to half the threshold: a backlit body upside down mid-somersault (Sports2D's
  // flip, frame 171: flag 0.37, its region 0.3° and 12 px from the prediction). Taken for at most
  // kMaxDoubtful frames in a row: a network shown an empty region fits a body where it is told to,
  // and the track must not follow a ghost.
  static constexpr int kMaxDoubtful = 3;
  bool FollowsClosely(const LandmarkResult& r, const Roi& predicted) const {
    if (doubtful_in_a_row >= kMaxDoubtful) return false;
    if (!(r.pose_score > 0.5 * options.min_pose_score) || !r.landmarks.allFinite()) return false;
    const Roi next = r.NextRoi();
    if ((next.centre_px - predicted.centre_px).norm() > 0.25 * predicted.size_px) return false;
    if (next.size_px < predicted.size_px / 1.25 || next.size_px > predicted.size_px * 1.25) return false;
    return std::abs(WrapAngle(next.rotation - predicted.rotation)) < 20 * kDeg;
  }

  // The region around the last pose, moved on by its motion.
  Roi Predicted() const {
    Roi p = roi;
    p.centre_px += velocity;
    p.rotation = WrapAngle(p.rotation + omega);
    return p;
  }

  // Searches rotations (and a larger region) about `around`: the best pose that follows on from
  // `consistent_with`, rotations away from the prediction paying for their distance.
  std::optional<LandmarkResult> SearchRotations(const cv::Mat& rgb, const Roi& around,
                                                const std::optional<Roi>& consistent_with,
                                                const std::vector<double>& offsets_deg, double scale) {
    std::optional<LandmarkResult> best;
    double best_value = -1e9;
    for (double offset : offsets_deg) {
      Roi r = around;
      r.rotation = WrapAngle(r.rotation + offset * kDeg);
      r.size_px *= scale;
      LandmarkResult result = RunLandmarks(rgb, r);
      if (!Consistent(result, consistent_with)) continue;
      const double value = result.Quality() - 0.15 * std::abs(offset) / 180.0;
      if (value > best_value) {
        best_value = value;
        best = std::move(result);
      }
    }
    return best;
  }

  // The direction a newly found body is expected to have: the last one seen when the track was
  // lost a moment ago, else upright (a person found from nothing is far more often standing than
  // upside down: gravity's prior).
  double ExpectedRotation() const {
    return last_seen && frames_since_seen < 30 ? last_seen->rotation : 0.0;
  }

  // Where to look for the athlete when no pose is followed: the user's box, the air above the
  // bed, around the last pose seen, then the whole frame and (on search frames) its tiles.
  std::vector<cv::Rect2d> SearchRegions(int width, int height, bool search_frame) const {
    std::vector<cv::Rect2d> regions;
    if (options.box_px) {
      const auto& b = *options.box_px;
      regions.emplace_back(b.min().x(), b.min().y(), b.sizes().x(), b.sizes().y());
    }
    if (options.bed_corners_px) regions.push_back(AboveBed());
    if (last_seen && frames_since_seen < 30) {
      const double side = 2.0 * last_seen->size_px;
      regions.emplace_back(last_seen->centre_px.x() - side / 2, last_seen->centre_px.y() - side / 2, side, side);
    }
    regions.emplace_back(0, 0, width, height);
    if (search_frame) {
      // Square tiles of 0.6 of the shorter side, overlapping by half: a small athlete is twice as
      // large in the detector's input.
      const double side = 0.6 * std::min(width, height), step = side / 2;
      for (double y = 0; y < height - side / 2; y += step)
        for (double x = 0; x < width - side / 2; x += step) regions.emplace_back(x, y, side, side);
    }
    return regions;
  }

  // The air above the bed: the bed's width on each side widened by 15 %, 1.5 bed widths high.
  cv::Rect2d AboveBed() const {
    const auto& c = *options.bed_corners_px;
    double x0 = c[0].x(), x1 = c[0].x(), y0 = c[0].y(), y1 = c[0].y();
    for (const auto& p : c) {
      x0 = std::min(x0, p.x());
      x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y());
      y1 = std::max(y1, p.y());
    }
    const double w = x1 - x0;
    return {x0 - 0.15 * w, y0 - 1.5 * w, 1.3 * w, y1 - y0 + 1.5 * w};
  }

  // How much a candidate looks like the athlete: its score, plus being where the user's box or
  // the bed says, plus being near where the athlete was last seen.
  double Preference(const PersonCandidate& c) const {
    double value = c.score;
    const Eigen::Vector2d hip = c.keypoints_px[0];
    if (options.box_px && options.box_px->contains(hip)) value += 1.0;
    if (options.bed_corners_px) {
      const cv::Rect2d air = AboveBed();
      if (air.contains(cv::Point2d(hip.x(), hip.y()))) value += 1.0;
    }
    if (last_seen && frames_since_seen < 30) {
      const double d = (hip - last_seen->centre_px).norm() / std::max(last_seen->size_px, 1.0);
      value += std::max(0.0, 1.0 - d);
    }
    return value;
  }

  std::optional<LandmarkResult> Acquire(const cv::Mat& rgb, std::string* how) {
    const bool search_frame = frame_counter % options.search_every_frames == 0;
    std::vector<PersonCandidate> candidates;
    for (const cv::Rect2d& region : SearchRegions(rgb.cols, rgb.rows, search_frame)) {
      for (PersonCandidate& c : RunDetector(rgb, region)) {
        // Several regions see the same person: keep one, the best scored.
        bool duplicate = false;
        for (PersonCandidate& k : candidates)
          if ((k.keypoints_px[0] - c.keypoints_px[0]).norm() < 0.3 * (k.keypoints_px[1] - k.keypoints_px[0]).norm()) {
            if (c.score > k.score) k = c;
            duplicate = true;
          }
        if (!duplicate) candidates.push_back(c);
      }
    }
    std::sort(candidates.begin(), candidates.end(),
              [&](const auto& a, const auto& b) { return Preference(a) > Preference(b); });
    // Each candidate's region as the detector turned it and half a turn from there: the detector
    // sometimes takes a body for one upside down (a faceless figure, a crop that cuts the feet),
    // and the landmark network then fits it upside down with its pose flag at 1; the quality tells.
    for (const PersonCandidate& c : candidates) {
      std::optional<LandmarkResult> best;
      double best_value = -1e9;
      for (double turn : {0.0, kPi}) {
        Roi region = c.roi();
        region.rotation = WrapAngle(region.rotation + turn);
        LandmarkResult r = RunLandmarks(rgb, region);
        const double value = r.Quality() - 0.3 * std::abs(WrapAngle(r.NextRoi().rotation - ExpectedRotation())) / kPi;
        if (Consistent(r, std::nullopt) && r.Quality() >= kMinAcquiredQuality && value > best_value) {
          best_value = value;
          best = std::move(r);
        }
      }
      if (best) {
        *how = "detector";
        return best;
      }
    }
    // The detector found nobody it could confirm: search the user's box, the bed's air or the last
    // place seen over rotations (an inverted or tucked athlete the detector does not know).
    if (!search_frame) return std::nullopt;
    std::vector<Roi> regions;
    if (options.box_px) {
      Roi r;
      r.centre_px = options.box_px->center();
      r.size_px = 1.25 * options.box_px->sizes().maxCoeff();
      regions.push_back(r);
    }
    if (last_seen && frames_since_seen < 30) regions.push_back(*last_seen);
    for (const Roi& region : regions) {
      auto found = SearchRotations(rgb, region, std::nullopt, {0, 90, -90, 180, 45, -45, 135, -135}, 1.0);
      if (found && found->Quality() >= kMinAcquiredQuality) {
        *how = "region";
        return found;
      }
    }
    return std::nullopt;
  }

  FramePose Take(const LandmarkResult& r, const std::string& how, bool continuing) {
    FramePose pose;
    pose.found = true;
    pose.how = how;
    pose.pose_score = r.pose_score;
    pose.quality = r.Quality();
    // Confidence: the landmark's visibility and presence, the pose flag, and the heatmap's
    // agreement with the regression (its window's peak); a pose found by a search is trusted less.
    for (int i = 0; i < 33; ++i) {
      pose.keypoints(0, i) = r.landmarks(0, i);
      pose.keypoints(1, i) = r.landmarks(1, i);
      double c = r.landmarks(3, i) * r.landmarks(4, i) * std::min(1.0, r.pose_score) * (0.5 + 0.5 * r.landmarks(5, i));
      if (how == "rotation search" || how == "region") c *= 0.8;
      pose.keypoints(2, i) = std::clamp(c, 0.0, 1.0);
    }

    // The next region: from the auxiliary landmarks, its size kept near its recent value (a tuck
    // shrinks the network's estimate of the body's extent faster than the body shrinks).
    // The region grows at once but shrinks slowly: a body's size in the image changes little from
    // frame to frame, and a region cut too small makes the network fit a small body inside the
    // torso (seen on the sample's standing athlete), while one too large only costs resolution.
    Roi next = r.NextRoi();
    if (poses_in_track > 0 && size_ema > 0) next.size_px = std::clamp(next.size_px, 0.9 * size_ema, 1.3 * size_ema);
    next.size_px = std::min(next.size_px, 1.2 * std::max(image_width, image_height));
    size_ema = poses_in_track > 0 && size_ema > 0 ? std::max(next.size_px, 0.95 * size_ema + 0.05 * next.size_px)
                                                  : next.size_px;
    if (continuing) {
      velocity = 0.5 * velocity + 0.5 * (next.centre_px - roi.centre_px);
      omega = std::clamp(0.5 * omega + 0.5 * WrapAngle(next.rotation - roi.rotation), -60 * kDeg, 60 * kDeg);
    } else {
      velocity.setZero();
      omega = 0.0;
    }
    roi = next;
    active = true;
    ++poses_in_track;
    last_seen = roi;
    frames_since_seen = 0;
    return pose;
  }

  void Lose() {
    active = false;
    poses_in_track = 0;
    doubtful_in_a_row = 0;
    velocity.setZero();
    omega = 0.0;
  }

  FramePose Track(const cv::Mat& rgb) {
    image_width = rgb.cols;
    image_height = rgb.rows;
    FramePose pose;
    std::string how;
    if (active) {
      const Roi predicted = Predicted();
      LandmarkResult r = RunLandmarks(rgb, predicted);
      if (Consistent(r, predicted)) {
        pose = Take(r, "tracked", true);
        doubtful_in_a_row = 0;
      } else if (FollowsClosely(r, predicted)) {
        pose = Take(r, "tracked", true);
        ++doubtful_in_a_row;
      } else {
        doubtful_in_a_row = 0;
        // Lost: the same place turned by up to half a turn either way, or taken larger.
        auto found = SearchRotations(rgb, predicted, predicted, {0, 45, -45, 90, -90, 135, -135, 180}, 1.4);
        if (!found) found = SearchRotations(rgb, predicted, predicted, {45, -45, 90, -90, 135, -135, 180}, 1.0);
        if (found) pose = Take(*found, "rotation search", true);
        else Lose();
      }
    }
    if (!pose.found) {
      if (auto r = Acquire(rgb, &how)) pose = Take(*r, how, false);
    }
    if (!pose.found) ++frames_since_seen;
    ++frame_counter;
    pose.roi_centre_px = roi.centre_px;
    pose.roi_size_px = roi.size_px;
    pose.roi_rotation_rad = roi.rotation;
    pose.velocity_px = velocity;
    pose.angular_velocity_rad = omega;
    return pose;
  }
};

PoseTracker::PoseTracker(const PoseTrackerOptions& options) {
  DemandValidOptions(options, "pose tracker");
  const PoseModelFiles files =
      FindPoseModels(options.model, options.model_directory.empty() ? DefaultModelDirectory() : options.model_directory);
  impl_ = std::make_unique<Impl>(options, files);
}

PoseTracker::~PoseTracker() = default;

FramePose PoseTracker::Track(const capture::VideoFrame& frame) {
  if (frame.channels != 3 || frame.width <= 0 || frame.height <= 0 ||
      frame.pixels.size() != static_cast<std::size_t>(frame.width) * frame.height * 3)
    throw InputError("", fmt::format("frame {}", frame.index), "not an RGB picture");
  const cv::Mat rgb(frame.height, frame.width, CV_8UC3, const_cast<std::uint8_t*>(frame.pixels.data()));
  FramePose pose = impl_->Track(rgb);
  pose.frame = frame.index;
  pose.time_s = frame.time_s;
  return pose;
}

void PoseTracker::Resume(const FramePose& last) {
  Impl& s = *impl_;
  s.Lose();
  s.roi.centre_px = last.roi_centre_px;
  s.roi.size_px = last.roi_size_px;
  s.roi.rotation = last.roi_rotation_rad;
  if (last.roi_size_px > 0) s.last_seen = s.roi;
  if (!last.found || last.roi_size_px <= 0) return;
  s.active = true;
  s.velocity = last.velocity_px;
  s.omega = last.angular_velocity_rad;
  s.size_ema = last.roi_size_px;
  s.poses_in_track = 1;
}

const PoseTiming& PoseTracker::timing() const { return impl_->Timing(); }

}  // namespace acro::pose
