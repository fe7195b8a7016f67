#include "acro/vision/camera_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "acro/base/input_error.h"
#include "acro/capture/video.h"

namespace acro::vision {

bool CameraMotionOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (analysis_width_px < 32 || analysis_width_px > 4096)
    return fail("analysis_width_px must be 32–4096");
  if (every_frames < 1) return fail("every_frames must be >= 1");
  if (!(moved_px > 0 && std::isfinite(moved_px))) return fail("moved_px must be finite and > 0");
  return true;
}

double CameraMotion::LargestShiftPx(int first, int last) const {
  for (const int k : lost_frames)
    if (k <= last) return std::numeric_limits<double>::infinity();
  double largest = 0;
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i] >= first && frames[i] <= last) largest = std::max(largest, shift[i].norm());
  return largest;
}

int CameraMotion::FirstMovedFrame() const {
  for (size_t i = 0; i < frames.size(); ++i)
    if (shift[i].norm() > moved_px) return frames[i];
  return lost_frames.empty() ? -1 : lost_frames.front();
}

namespace {

// The frame as grey bytes at 1/factor of its size (block means).
cv::Mat Reduce(const capture::VideoFrame& frame, int factor) {
  const int w = frame.width / factor, h = frame.height / factor, c = frame.channels;
  cv::Mat out(h, w, CV_8U);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int dy = 0; dy < factor; ++dy) {
        const std::uint8_t* px =
            frame.pixels.data() +
            (static_cast<size_t>(y * factor + dy) * frame.width + size_t(x) * factor) * c;
        for (int dx = 0; dx < factor; ++dx, px += c)
          s += c == 1 ? float(px[0]) : 0.299f * px[0] + 0.587f * px[1] + 0.114f * px[2];
      }
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(s / float(factor * factor));
    }
  return out;
}

double Median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The picture's shift against a key frame from patches around the key frame's corners: each
// patch found again near where the shift so far puts it (normalised cross-correlation, the peak
// refined by a parabola), the median of the patches' displacements — the corners on the athlete,
// who moves, are a minority of a picture's; the background's say where the camera points.
class Follower {
 public:
  static constexpr int kHalfPatch = 7;
  static constexpr int kSearch = 10;

  explicit Follower(const cv::Mat& key) : key_(key) {
    const int margin = kHalfPatch + kSearch + 1;
    cv::Mat mask = cv::Mat::zeros(key.size(), CV_8U);
    if (key.cols > 2 * margin && key.rows > 2 * margin)
      mask(cv::Rect(margin, margin, key.cols - 2 * margin, key.rows - 2 * margin)) = 255;
    cv::goodFeaturesToTrack(key, corners_, 60, 0.01, 2.0 * kHalfPatch, mask);
  }

  size_t num_corners() const { return corners_.size(); }

  // The shift of `frame` against the first frame (px of the reduced picture), from `guess`; false
  // when too few of the key frame's patches are found again.
  bool Follow(const cv::Mat& frame, const Eigen::Vector2d& guess, Eigen::Vector2d* shift) const {
    std::vector<double> dx, dy;
    for (const cv::Point2f& c : corners_) {
      const int x = int(std::lround(c.x + guess.x())), y = int(std::lround(c.y + guess.y()));
      const cv::Rect search(x - kHalfPatch - kSearch,
                            y - kHalfPatch - kSearch,
                            2 * (kHalfPatch + kSearch) + 1,
                            2 * (kHalfPatch + kSearch) + 1);
      if ((search & cv::Rect(0, 0, frame.cols, frame.rows)) != search) continue;
      const cv::Rect patch(int(std::lround(c.x)) - kHalfPatch,
                           int(std::lround(c.y)) - kHalfPatch,
                           2 * kHalfPatch + 1,
                           2 * kHalfPatch + 1);
      cv::Mat score;
      cv::matchTemplate(frame(search), key_(patch), score, cv::TM_CCOEFF_NORMED);
      double best = 0;
      cv::Point at;
      cv::minMaxLoc(score, nullptr, &best, nullptr, &at);
      // A peak on the window's edge may be a slope towards a match outside it: not found.
      if (best < 0.8 || at.x == 0 || at.y == 0 || at.x == score.cols - 1 || at.y == score.rows - 1)
        continue;
      // Sub-pixel: the parabola through the peak and its neighbours, per axis.
      auto refine = [&](int i, int n, auto value) {
        if (i <= 0 || i >= n - 1) return 0.0;
        const double a = value(i - 1), b = value(i), c2 = value(i + 1);
        const double d = a - 2 * b + c2;
        return d < 0 ? 0.5 * (a - c2) / d : 0.0;
      };
      const double sx =
          refine(at.x, score.cols, [&](int i) { return double(score.at<float>(at.y, i)); });
      const double sy =
          refine(at.y, score.rows, [&](int i) { return double(score.at<float>(i, at.x)); });
      dx.push_back(search.x + at.x + sx + kHalfPatch - patch.x - kHalfPatch);
      dy.push_back(search.y + at.y + sy + kHalfPatch - patch.y - kHalfPatch);
    }
    const size_t needed = std::max<size_t>(5, corners_.size() / 3);
    if (dx.size() < needed) return false;
    *shift = Eigen::Vector2d(Median(dx), Median(dy));
    // Found again means agreeing: a patch matched on a flat wall or along an edge lands anywhere,
    // the background's land together.
    size_t agree = 0;
    for (size_t i = 0; i < dx.size(); ++i)
      agree += (Eigen::Vector2d(dx[i], dy[i]) - *shift).norm() < 1.5 ? 1 : 0;
    return agree >= needed;
  }

 private:
  cv::Mat key_;
  std::vector<cv::Point2f> corners_;
};

}  // namespace

CameraMotion MeasureCameraMotion(const std::filesystem::path& video,
                                 const CameraMotionOptions& options,
                                 const Progress& progress) {
  DemandValidOptions(options, "camera motion");
  capture::VideoReaderOptions reader_options;
  reader_options.pixels = capture::VideoPixels::kGrey;
  capture::VideoReader reader(video, reader_options);
  const capture::VideoInfo& info = reader.info();
  CameraMotion out;
  out.path = video.string();
  out.width_px = info.width;
  out.moved_px = options.moved_px;
  const int factor = std::max(1, info.width / options.analysis_width_px);
  if (info.width / factor < 64 || info.height / factor < 64) {
    out.unmeasured =
        fmt::format("its picture, {}×{} px, is too small to follow", info.width, info.height);
    return out;
  }
  std::optional<Follower> follower;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // reduced px, against the first frame
  capture::VideoFrame frame;
  const int n = info.num_frames;
  for (int k = 0; k < n; ++k) {
    if (!reader.ReadNext(&frame)) break;
    if (k % options.every_frames == 0) {
      const cv::Mat grey = Reduce(frame, factor);
      if (!follower) {
        follower.emplace(grey);
        if (follower->num_corners() < 5) {
          out.unmeasured = "its first frame has too little texture to follow";
          return out;
        }
      } else {
        Eigen::Vector2d next;
        if (!follower->Follow(grey, shift, &next)) {
          // The first frame's patches are lost (the camera turned far or fast, or the picture
          // changed): from here on where the camera points is not known.
          out.lost_frames.push_back(k);
          break;
        }
        shift = next;
      }
      out.frames.push_back(k);
      out.shift.push_back(shift * factor);
    }
    progress.ReportOrThrow("camera motion", k + 1, n);
  }
  if (out.frames.empty() && out.unmeasured.empty()) out.unmeasured = "no frame could be read";
  return out;
}

std::vector<std::string> CameraMotionWarnings(
    const CameraMotion& motion,
    const std::vector<std::pair<std::pair<int, int>, std::string>>& spans) {
  std::vector<std::string> out;
  if (!motion.unmeasured.empty()) {
    out.push_back(motion.path + ": whether the camera held still is not known (" +
                  motion.unmeasured + "): one camera's numbers need a camera that holds still");
    return out;
  }
  const int moved = motion.FirstMovedFrame();
  if (moved < 0) return out;
  const double largest = motion.LargestShiftPx(0, std::numeric_limits<int>::max());
  const auto amount = [](double px) {
    return std::isfinite(px) ? fmt::format("shifted by {:.0f} px", px)
                             : std::string("turned too far to follow");
  };
  out.push_back(fmt::format(
      "{}: the camera moves — the picture is {} from the first frame's (from frame {}), where the "
      "bed's line and the camera's pose were taken: one camera's numbers need a camera that holds "
      "still",
      motion.path,
      std::isfinite(largest) ? "shifted by up to " + fmt::format("{:.0f} px", largest)
                             : std::string("turned too far to follow"),
      moved));
  for (const auto& [span, label] : spans) {
    const double s = motion.LargestShiftPx(span.first, span.second);
    if (s > motion.moved_px)
      out.push_back(
          fmt::format("{}: the picture is {} from the first frame's during it: its "
                      "times, heights and depth are not to be trusted",
                      label,
                      amount(s)));
  }
  return out;
}

std::vector<std::string> CameraMotionWarnings(const CameraMotion& motion,
                                              const ImageFlights& flights) {
  std::vector<std::pair<std::pair<int, int>, std::string>> spans;
  for (size_t i = 0; i < flights.flights.size(); ++i) {
    const ImageFlight& f = flights.flights[i];
    const int a = f.last_contact_frame >= 0 ? f.last_contact_frame : 0;
    // In the air at the video's end: up to its end (past the last frame compared, a loss
    // included).
    const int b =
        f.first_contact_frame >= 0 ? f.first_contact_frame : std::numeric_limits<int>::max();
    // Named by its frames in the air, as the flights' own warnings name it.
    const double from = f.last_contact_frame >= 0 ? (a + 1) / flights.rate_hz : 0.0;
    spans.push_back(
        {{a, b},
         f.first_contact_frame >= 0
             ? fmt::format("flight {} ({:.2f}–{:.2f} s)", i + 1, from, (b - 1) / flights.rate_hz)
             : fmt::format("flight {} (from {:.2f} s)", i + 1, from)});
  }
  return CameraMotionWarnings(motion, spans);
}

}  // namespace acro::vision
