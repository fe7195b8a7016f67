#include "acro/vision/motion_flights.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "acro/base/input_error.h"
#include "acro/fig/trampoline.h"

namespace acro::vision {

bool MotionFlightOptions::IsValid(std::string* why) const {
  const auto fail = [why](const std::string& s) {
    if (why != nullptr) *why = s;
    return false;
  };
  if (!(clearance_m > 0 && clearance_m < 1)) return fail("clearance_m must be in (0, 1) m");
  if (!(min_flight_s >= 0 && min_flight_s < 10)) return fail("min_flight_s must be in [0, 10) s");
  if (!(background_every_s > 0 && background_every_s <= 10))
    return fail("background_every_s must be in (0, 10] s");
  if (background_min_samples < 3 || background_samples < background_min_samples ||
      background_samples > 200)
    return fail("background samples: at least 3, at most 200, the minimum not above the number");
  if (!(min_region_fraction >= 0 && min_region_fraction < 1))
    return fail("min_region_fraction must be in [0, 1)");
  return true;
}

namespace {

// How much pixel i of `a` differs from the same pixel of `b` (same layout): the channel that
// differs most.
int PixelDifference(const capture::VideoFrame& a, const std::uint8_t* b, size_t i) {
  const int c = a.channels;
  int d = 0;
  for (int k = 0; k < c; ++k)
    d = std::max(d, std::abs(int(a.pixels[i * c + k]) - int(b[i * c + k])));
  return d;
}

}  // namespace

MotionFlightWatcher::MotionFlightWatcher(const BedDetection& bed,
                                         const MotionFlightOptions& options)
    : options_(options), line_(RestLineOfBed(bed)) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("MotionFlightOptions: " + why);
  if (bed.width_px <= 0 || bed.height_px <= 0)
    throw InputError(
        bed.source, "bed", fmt::format("a picture {} x {} px", bed.width_px, bed.height_px));
  full_width_px_ = bed.width_px;
  bed_x_min_px_ = bed.corners_px[0].x();
  bed_x_max_px_ = bed.corners_px[0].x();
  for (const Eigen::Vector2d& c : bed.corners_px) {
    bed_x_min_px_ = std::min(bed_x_min_px_, c.x());
    bed_x_max_px_ = std::max(bed_x_max_px_, c.x());
  }
  // The bed's length in the picture: the mean of its two long sides (the quadrilateral's top and
  // bottom, corners 0-1 and 3-2 going round from the top left).
  const double length_px = 0.5 * ((bed.corners_px[1] - bed.corners_px[0]).norm() +
                                  (bed.corners_px[2] - bed.corners_px[3]).norm());
  if (!(length_px > 10))
    throw InputError(bed.source, "bed", fmt::format("{:.0f} px long: too small", length_px));
  m_per_px_ = fig::kBedLength_m / length_px;
  // The bed's far long side (the quadrilateral's upper side for a camera above the bed): a foot
  // sunk into the bed, or behind its near pads, shows the athlete ending there.
  const Eigen::Vector2d c0 = bed.corners_px[0], c1 = bed.corners_px[1];
  far_.slope = std::abs(c1.x() - c0.x()) > 1e-9 ? (c1.y() - c0.y()) / (c1.x() - c0.x()) : 0.0;
  far_.y0_px = c0.y() - far_.slope * c0.x();
  // The athlete lands anywhere along the bed and may drift past its ends: a margin of a fifth.
  const double margin = 0.2 * (bed_x_max_px_ - bed_x_min_px_);
  bed_x_min_px_ = std::max(0.0, bed_x_min_px_ - margin);
  bed_x_max_px_ = std::min(double(bed.width_px - 1), bed_x_max_px_ + margin);
}

MotionFlightWatcher::Sole MotionFlightWatcher::FindSole(const capture::VideoFrame& grey,
                                                        const capture::VideoFrame* before) const {
  Sole sole;
  const Mask mask = Foreground(grey);
  const double s = grey.width / full_width_px_;  // analysis px per full px
  const int x0 = std::clamp(int(std::floor(bed_x_min_px_ * s)), 0, grey.width - 1);
  const int x1 = std::clamp(int(std::ceil(bed_x_max_px_ * s)), x0, grey.width - 1);
  // Down to the bed's line plus the depth a bed sinks under a landing (about 1 m at most).
  const double below_px = 1.2 / m_per_px_;
  const double y_line = std::max(line_.At(bed_x_min_px_), line_.At(bed_x_max_px_));
  const int y1 = std::clamp(int(std::ceil((y_line + below_px) * s)), 0, grey.height - 1);
  cv::Mat m(mask.height, mask.width, CV_8UC1, const_cast<std::uint8_t*>(mask.pixels.data()));
  cv::Mat roi = m(cv::Range(0, y1 + 1), cv::Range(x0, x1 + 1));
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(roi, labels, stats, centroids, 8, CV_32S);
  // The athlete: the region that moves most since `before` (what the background still holds of
  // an athlete who stood or bounced in one place is a region too, a still one); the largest when
  // none moves.
  std::vector<int> moving(static_cast<size_t>(n), 0);
  if (before != nullptr && before->pixels.size() == grey.pixels.size()) {
    const int threshold = Threshold(grey);
    for (int y = 0; y < labels.rows; ++y) {
      const int* row = labels.ptr<int>(y);
      const size_t base = static_cast<size_t>(y) * grey.width + x0;
      for (int x = 0; x < labels.cols; ++x)
        if (row[x] > 0 && PixelDifference(grey, before->pixels.data(), base + x) > threshold)
          ++moving[static_cast<size_t>(row[x])];
    }
  }
  const double bed_length_px = fig::kBedLength_m / m_per_px_ * s;
  const double min_area = options_.min_region_fraction * bed_length_px * bed_length_px;
  int best = -1, best_area = 0, best_moving = 0;
  for (int k = 1; k < n; ++k) {
    const int area = stats.at<int>(k, cv::CC_STAT_AREA);
    if (area < min_area) continue;  // specks never outweigh a large, slow athlete
    const int moved = moving[static_cast<size_t>(k)];
    if (moved > best_moving || (moved == best_moving && area > best_area)) {
      best_area = area;
      best_moving = moved;
      best = k;
    }
  }
  if (best < 0) return sole;
  const int bottom =
      stats.at<int>(best, cv::CC_STAT_TOP) + stats.at<int>(best, cv::CC_STAT_HEIGHT) - 1;
  // The soles: the region's lowest rows (two, against a single pixel's noise), their mean column.
  double sum_x = 0;
  int count = 0;
  for (int y = std::max(0, bottom - 1); y <= bottom; ++y) {
    const int* row = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (row[x] == best) {
        sum_x += x;
        ++count;
      }
  }
  if (count == 0) return sole;
  sole.found = true;
  sole.box = {x0 + stats.at<int>(best, cv::CC_STAT_LEFT),
              stats.at<int>(best, cv::CC_STAT_TOP),
              x0 + stats.at<int>(best, cv::CC_STAT_LEFT) + stats.at<int>(best, cv::CC_STAT_WIDTH),
              bottom + 1};
  sole.x_px = (x0 + sum_x / count + 0.5) / s - 0.5;
  sole.y_px = (bottom + 1.0) / s - 0.5;  // the lowest row's lower edge
  sole.height_m = (line_.At(sole.x_px) - sole.y_px) * m_per_px_;
  return sole;
}

Mask MotionFlightWatcher::Foreground(const capture::VideoFrame& grey) const {
  Mask mask;
  mask.width = grey.width;
  mask.height = grey.height;
  const size_t n = static_cast<size_t>(grey.width) * grey.height;
  mask.pixels.resize(n);
  const int threshold = Threshold(grey);
  for (size_t i = 0; i < n; ++i)
    mask.pixels[i] = PixelDifference(grey, background_.data(), i) > threshold ? 255 : 0;
  if (options_.foreground.clean_px > 0) {
    cv::Mat m(mask.height, mask.width, CV_8UC1, mask.pixels.data());
    const cv::Mat kernel = cv::getStructuringElement(
        cv::MORPH_RECT, cv::Size(options_.foreground.clean_px, options_.foreground.clean_px));
    cv::morphologyEx(m, m, cv::MORPH_OPEN, kernel);
    cv::morphologyEx(m, m, cv::MORPH_CLOSE, kernel);
  }
  return mask;
}

void MotionFlightWatcher::BuildBackground() {
  // Per pixel the median of the samples in which the athlete's region (grown by a sixth and 4 px)
  // did not cover it: an athlete who bounces on one spot covers the air just above the bed in
  // more than half of any set of frames, and a plain median keeps him there as a ghost.
  const int w = samples_.front().grey.width, h = samples_.front().grey.height;
  const int c = samples_.front().grey.channels;
  background_.assign(static_cast<size_t>(w) * h * c, 0);
  std::vector<std::array<int, 4>> boxes;
  for (const BackgroundSample& b : samples_) {
    const int gx = (b.box[2] - b.box[0]) / 6 + 4, gy = (b.box[3] - b.box[1]) / 6 + 4;
    boxes.push_back(
        b.has_box ? std::array<int, 4>{b.box[0] - gx, b.box[1] - gy, b.box[2] + gx, b.box[3] + gy}
                  : std::array<int, 4>{0, 0, -1, -1});
  }
  std::vector<std::uint8_t> clear, all;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) {
        clear.clear();
        all.clear();
        const size_t i = (static_cast<size_t>(y) * w + x) * c + ch;
        for (size_t k = 0; k < samples_.size(); ++k) {
          const std::uint8_t v = samples_[k].grey.pixels[i];
          all.push_back(v);
          const auto& r = boxes[k];
          if (!(x >= r[0] && x < r[2] && y >= r[1] && y < r[3])) clear.push_back(v);
        }
        // The regions are grown: one sample clear of the athlete is the background itself.
        std::vector<std::uint8_t>& use = !clear.empty() ? clear : all;
        std::nth_element(use.begin(), use.begin() + use.size() / 2, use.end());
        background_[i] = use[use.size() / 2];
      }
}

int MotionFlightWatcher::Threshold(const capture::VideoFrame& frame) const {
  return frame.channels == 3 ? options_.foreground.colour_threshold : options_.foreground.threshold;
}

void MotionFlightWatcher::Sample(const capture::VideoFrame& grey, const Sole* sole) {
  if (grey.time_s < next_sample_s_) return;
  // The next one 0.6–1.4 intervals later (a fixed step falls in step with a regular bounce and
  // samples the athlete at the same height every time).
  sample_seed_ = sample_seed_ * 6364136223846793005ULL + 1442695040888963407ULL;
  const double u = static_cast<double>(sample_seed_ >> 11) / 9007199254740992.0;
  next_sample_s_ = grey.time_s + options_.background_every_s * (0.6 + 0.8 * u);
  BackgroundSample b;
  b.grey = grey;
  if (sole != nullptr && sole->found) {
    b.has_box = true;
    b.box = sole->box;
  }
  samples_.push_back(std::move(b));
  while (static_cast<int>(samples_.size()) > options_.background_samples) samples_.pop_front();
  if (static_cast<int>(samples_.size()) < options_.background_min_samples) return;
  const bool first = background_.empty();
  BuildBackground();
  // The first samples had no athlete to leave out: found in each (the region that moved since
  // the sample beside it), and the background made again, twice (the second finds the athlete
  // against a background without the first one's ghosts).
  for (int round = 0; first && round < 2; ++round) {
    for (size_t k = 0; k < samples_.size(); ++k) {
      const Sole found = FindSole(samples_[k].grey, &samples_[k == 0 ? 1 : k - 1].grey);
      samples_[k].has_box = found.found;
      samples_[k].box = found.box;
    }
    BuildBackground();
  }
}

std::vector<MotionJump> MotionFlightWatcher::Add(const capture::VideoFrame& grey,
                                                 double arrival_s) {
  if ((grey.channels != 1 && grey.channels != 3) || grey.width <= 0 || grey.height <= 0 ||
      grey.pixels.size() != static_cast<size_t>(grey.width) * grey.height * grey.channels)
    throw std::invalid_argument("MotionFlightWatcher: a grey or RGB frame expected");
  if (!samples_.empty() &&
      (grey.width != samples_.front().grey.width || grey.height != samples_.front().grey.height ||
       grey.channels != samples_.front().grey.channels))
    throw InputError(line_.source,
                     "frame",
                     fmt::format("{} x {} px after {} x {} px: the picture changed size",
                                 grey.width,
                                 grey.height,
                                 samples_.front().grey.width,
                                 samples_.front().grey.height));
  sightings_.clear();
  if (background_.empty()) {
    Sample(grey, nullptr);
    waiting_.emplace_back(grey, arrival_s);
    // A background that does not form (time that does not advance): the oldest frames go.
    if (waiting_.size() > 900) waiting_.pop_front();
    if (background_.empty()) return {};
  }
  std::vector<MotionJump> out;
  while (!waiting_.empty()) {
    for (MotionJump& j : Step(waiting_.front().first, waiting_.front().second, nullptr))
      out.push_back(j);
    waiting_.pop_front();
    if (waiting_.empty()) return out;  // this frame was the last of them
  }
  Sole sole;
  for (MotionJump& j : Step(grey, arrival_s, &sole)) out.push_back(j);
  Sample(grey, &sole);
  return out;
}

namespace {

// Where the soles' ballistic path y(t) = a + b (t − t0) + g/2 (t − t0)² (image y down, g in px/s²
// known from the bed's scale) fitted to `frames` (t, y, the line's y there) meets the line: going
// up (a take-off) or down (a landing), within [lo_s, hi_s]. NaN without two frames or such a
// root. One frame more than 4 px off the others' path (an arm taken for a foot) is left out.
double BallisticCrossing(std::vector<Eigen::Vector3d> frames,  // t, y, line y
                         double g_px,
                         bool going_up,
                         double lo_s,
                         double hi_s) {
  const auto fit = [&](const std::vector<Eigen::Vector3d>& f, double* a, double* b) {
    // Least squares for a, b with g fixed, about the first frame's time.
    const double t0 = f.front().x();
    double s1 = 0, st = 0, stt = 0, sy = 0, sty = 0;
    for (const Eigen::Vector3d& p : f) {
      const double t = p.x() - t0, y = p.y() - 0.5 * g_px * t * t;
      s1 += 1;
      st += t;
      stt += t * t;
      sy += y;
      sty += t * y;
    }
    const double det = s1 * stt - st * st;
    if (std::abs(det) < 1e-12) return false;
    *a = (stt * sy - st * sty) / det;
    *b = (s1 * sty - st * sy) / det;
    return true;
  };
  if (frames.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  double a = 0, b = 0;
  if (!fit(frames, &a, &b)) return std::numeric_limits<double>::quiet_NaN();
  if (frames.size() >= 3) {
    size_t worst = 0;
    double worst_r = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
      const double t = frames[i].x() - frames.front().x();
      const double r = std::abs(frames[i].y() - (a + b * t + 0.5 * g_px * t * t));
      if (r > worst_r) {
        worst_r = r;
        worst = i;
      }
    }
    if (worst_r > 4.0) {
      frames.erase(frames.begin() + static_cast<std::ptrdiff_t>(worst));
      if (!fit(frames, &a, &b)) return std::numeric_limits<double>::quiet_NaN();
    }
  }
  // a + b τ + g/2 τ² = line (the line's height taken at the frames' mean; it is nearly flat).
  double line = 0;
  for (const Eigen::Vector3d& p : frames) line += p.z() / frames.size();
  const double qa = 0.5 * g_px, qb = b, qc = a - line;
  const double disc = qb * qb - 4 * qa * qc;
  if (disc < 0) return std::numeric_limits<double>::quiet_NaN();
  const double t0 = frames.front().x();
  double best = std::numeric_limits<double>::quiet_NaN();
  for (double sign : {-1.0, 1.0}) {
    const double tau = (-qb + sign * std::sqrt(disc)) / (2 * qa);
    const double rising = qb + 2 * qa * tau < 0;  // dy/dt < 0: going up the picture
    if (rising == going_up && t0 + tau >= lo_s && t0 + tau <= hi_s) best = t0 + tau;
  }
  return best;
}

}  // namespace

std::vector<MotionJump> MotionFlightWatcher::Step(const capture::VideoFrame& grey,
                                                  double arrival_s,
                                                  Sole* found) {
  ++frames_seen_;
  last_time_s_ = grey.time_s;
  const Sole sole = FindSole(grey, previous_.pixels.empty() ? nullptr : &previous_);
  previous_ = grey;
  if (found != nullptr) *found = sole;
  MotionSighting& seen = sightings_.emplace_back();
  seen.time_s = grey.time_s;
  seen.found = sole.found;
  seen.sole_px = {sole.x_px, sole.y_px};
  seen.height_m = sole.height_m;
  const double full = full_width_px_ / grey.width;  // full px per analysis px
  for (size_t k = 0; k < 4; ++k) seen.box_px[k] = sole.box[k] * full;
  if (!sole.found) return {};
  ++frames_with_athlete_;
  const double t = grey.time_s, h = sole.height_m;
  // On the bed while the lowest point seen is at or below the bed's far side (a foot in the bed
  // is hidden by it); in the air once clearly above it.
  const double on_bed_m =
      std::max(0.0, (line_.At(sole.x_px) - far_.At(sole.x_px)) * m_per_px_) + 0.02;
  std::vector<MotionJump> out;
  if (!in_air_) {
    if (h <= on_bed_m) {
      last_contact_s_ = t;
      have_contact_ = true;
      flight_.clear();
    } else {
      flight_.push_back({t, sole.y_px, line_.At(sole.x_px), h});
      if (flight_.size() > 2000) flight_.erase(flight_.begin());  // hovering above the bed
      if (h > on_bed_m + options_.clearance_m && have_contact_) {
        in_air_ = true;
        apex_m_ = h;
      }
    }
  } else {
    if (h > on_bed_m) {
      flight_.push_back({t, sole.y_px, line_.At(sole.x_px), h});
      apex_m_ = std::max(apex_m_, h);
      // No jump lasts 8 s: someone standing on a pad or the frame, not a flight.
      if (t - flight_.front().t > 8.0) {
        in_air_ = false;
        have_contact_ = false;
        flight_.clear();
      }
    } else {
      in_air_ = false;
      const double frame_s = flight_.size() >= 2
                                 ? (flight_.back().t - flight_.front().t) / (flight_.size() - 1)
                                 : t - last_contact_s_;
      const double takeoff = Crossing(true, last_contact_s_, frame_s);
      const double landing = Crossing(false, t, frame_s);
      if (landing - takeoff >= options_.min_flight_s) {
        MotionJump j;
        j.number = ++jumps_;
        j.takeoff_s = takeoff;
        j.landing_s = landing;
        j.landing_frame = grey.index;
        j.landing_arrival_s = arrival_s;
        j.landing_px = {sole.x_px, sole.y_px};
        j.apex_above_bed_m = apex_m_;
        out.push_back(j);
      }
      last_contact_s_ = t;
      flight_.clear();
    }
  }
  return out;
}

double MotionFlightWatcher::Crossing(bool takeoff, double contact_s, double frame_s) const {
  // The soles seen clearly in the air, within 0.2 s of the flight's end concerned.
  const double g_px = 9.81 / m_per_px_;
  std::vector<Eigen::Vector3d> frames;
  if (takeoff) {
    for (const FlightFrame& f : flight_)
      if (f.t <= flight_.front().t + 0.2) frames.emplace_back(f.t, f.y_px, f.line_px);
  } else {
    for (const FlightFrame& f : flight_)
      if (f.t >= flight_.back().t - 0.2) frames.emplace_back(f.t, f.y_px, f.line_px);
  }
  // The crossing lies before the first frame clearly in the air (after the last one), by at most
  // the time the soles take through the band where the bed hides them, and a frame.
  const double edge = takeoff ? flight_.front().t : flight_.back().t;
  const double reach = std::abs(edge - contact_s) + frame_s + 0.15;
  const double t = takeoff ? BallisticCrossing(frames, g_px, true, edge - reach, edge)
                           : BallisticCrossing(frames, g_px, false, edge, edge + reach);
  if (std::isfinite(t)) return t;
  // Too few frames for a path: halfway between the frames around the crossing (the foot's height
  // on the bed is not seen to interpolate with).
  return 0.5 * (contact_s + edge);
}

}  // namespace acro::vision
