#include "acro/vision/sync.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/base/input_error.h"
#include "acro/base/progress.h"

namespace acro::vision {

int VideoSync::NearestSample(const capture::Trial& trial, double video_time_s) const {
  if (trial.num_frames == 0 || !(trial.point_rate_hz > 0)) return -1;
  const double f = std::round(TrialTime(video_time_s) * trial.point_rate_hz);
  if (!(f >= 0.0) || f > trial.num_frames - 1) return -1;
  return static_cast<int>(f);
}

VideoSync SyncFromEvent(double trial_time_s, double video_time_s, double rate) {
  return {video_time_s - rate * trial_time_s, rate};
}

void DemandTrialInsideVideo(const VideoSync& sync,
                            double trial_duration_s,
                            double video_duration_s,
                            const std::string& video) {
  const double first = sync.VideoTime(0.0), last = sync.VideoTime(trial_duration_s);
  if (std::isfinite(first) && std::isfinite(last) && last >= 0.0 && first <= video_duration_s)
    return;
  throw InputError(
      video,
      "sync",
      fmt::format("puts the trial at video time {:.6g} … {:.6g} s, outside the video's "
                  "0 … {:.3f} s (check --offset-s or --event)",
                  first,
                  last,
                  video_duration_s));
}

bool AutoSyncOptions::IsValid(std::string* why) const {
  if (!(rate > 0.0) || !std::isfinite(rate)) {
    *why = fmt::format("rate {} is not positive", rate);
    return false;
  }
  if (!(max_offset_s > min_offset_s) || !std::isfinite(min_offset_s) ||
      !std::isfinite(max_offset_s) || max_offset_s - min_offset_s > 3600.0) {
    *why = fmt::format(
        "the offsets searched (--search-s), {} to {} s, are not an interval of at most an hour",
        min_offset_s,
        max_offset_s);
    return false;
  }
  if (!(max_error_px > 0.0) || analysis_width_px < 32 || analysis_width_px > 1024 ||
      !(box_margin >= 0.0)) {
    *why = "max_error_px must be positive, analysis_width_px 32 to 1024, box_margin ≥ 0";
    return false;
  }
  return true;
}

namespace {

// Point p at trial time t (s from the first sample), linear between the samples around it; nothing
// in a gap or outside the trial.
std::optional<Eigen::Vector3d> PositionAt(const capture::Trial& trial, int p, double t) {
  const double x = t * trial.point_rate_hz;
  if (!(x >= 0.0) || x > trial.num_frames - 1) return std::nullopt;
  const int f0 = std::min(static_cast<int>(x), trial.num_frames - 1);
  const int f1 = std::min(f0 + 1, trial.num_frames - 1);
  if (!trial.valid(f0, p) || !trial.valid(f1, p)) return std::nullopt;
  const double w = x - f0;
  return ((1.0 - w) * trial.position(f0, p) + w * trial.position(f1, p)).eval();
}

double MedianInterval(const std::vector<double>& times) {
  std::vector<double> d;
  for (size_t i = 1; i < times.size(); ++i) d.push_back(times[i] - times[i - 1]);
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

// A cost at one offset and how many pairs or frames it rests on.
struct Cost {
  double value = std::numeric_limits<double>::infinity();
  int count = 0;
};

// Each offset costs a pass over the video's frames: a range of many thousands of frames would run
// for minutes. Refused with the way out, before any decoding.
void DemandSearchableRange(const AutoSyncOptions& options, double frame_s) {
  const double steps = (options.max_offset_s - options.min_offset_s) / frame_s;
  if (steps > 20000) {
    throw InputError("",
                     "--search-s",
                     fmt::format("{:.0f} to {:.0f} s is {:.0f} frames of offsets to try; narrow it "
                                 "to at most 20000 (an event or a rough offset by hand first)",
                                 options.min_offset_s,
                                 options.max_offset_s,
                                 steps));
  }
}

// The search common to both methods: every offset one frame apart, then a tenth of a frame around
// the best, then the vertex of a parabola through the best fine point and its neighbours. Offsets
// resting on less than half the largest count are not trusted (their overlap is too short).
AutoSyncResult SearchOffset(const std::function<Cost(double)>& cost,
                            double frame_s,
                            const AutoSyncOptions& options) {
  AutoSyncResult r;
  std::vector<Cost> costs;
  DemandSearchableRange(options, frame_s);
  for (int i = 0; options.min_offset_s + i * frame_s <= options.max_offset_s + 1e-12; ++i) {
    const double o = options.min_offset_s + i * frame_s;
    r.offsets_s.push_back(o);
    costs.push_back(cost(o));
  }
  int most = 0;
  for (const Cost& c : costs) most = std::max(most, c.count);
  if (most == 0)
    throw InputError(
        "", "sync", "no offset in the searched range overlaps the trial with the video");
  auto trusted = [&](const Cost& c) { return c.count * 2 >= most && std::isfinite(c.value); };
  size_t best = 0;
  for (size_t i = 0; i < costs.size(); ++i) {
    r.costs.push_back(trusted(costs[i]) ? costs[i].value
                                        : std::numeric_limits<double>::quiet_NaN());
    if (trusted(costs[i]) && (!trusted(costs[best]) || costs[i].value < costs[best].value))
      best = i;
  }
  r.runner_up_cost = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < costs.size(); ++i)
    if (trusted(costs[i]) && std::abs(r.offsets_s[i] - r.offsets_s[best]) >= 2.0 * frame_s - 1e-12)
      r.runner_up_cost = std::min(r.runner_up_cost, costs[i].value);
  // Fine grid.
  const double step = frame_s / 10.0;
  std::vector<double> fine_offsets;
  std::vector<Cost> fine;
  for (int i = -15; i <= 15; ++i) {
    fine_offsets.push_back(r.offsets_s[best] + i * step);
    fine.push_back(cost(fine_offsets.back()));
  }
  size_t fb = 15;
  for (size_t i = 0; i < fine.size(); ++i)
    if (trusted(fine[i]) && fine[i].value < fine[fb].value) fb = i;
  double offset = fine_offsets[fb];
  if (fb > 0 && fb + 1 < fine.size() && trusted(fine[fb - 1]) && trusted(fine[fb + 1])) {
    const double a = fine[fb - 1].value, b = fine[fb].value, c = fine[fb + 1].value;
    const double curvature = a - 2.0 * b + c;
    if (curvature > 0) offset += 0.5 * step * (a - c) / curvature;
  }
  const Cost at = cost(offset);
  r.sync = {offset, options.rate};
  r.cost = at.value;
  r.pairs = at.count;
  return r;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

AutoSyncResult SyncFromDetections(const capture::Trial& trial,
                                  const std::vector<CameraDetections>& cameras,
                                  const AutoSyncOptions& options) {
  DemandValidOptions(options, "sync");
  if (cameras.empty()) throw InputError("", "sync", "no camera with detections");
  // Trial point ↔ keypoint, by name, per camera (a CSV's names are its own, in its order).
  std::vector<std::vector<std::pair<int, int>>> matches(cameras.size());
  bool any = false;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const std::vector<std::string>& names = cameras[c].detections->names;
    for (int p = 0; p < trial.num_points(); ++p) {
      const std::string label = Lower(trial.points[static_cast<size_t>(p)].label);
      for (size_t j = 0; j < names.size(); ++j)
        if (Lower(names[j]) == label) matches[c].emplace_back(p, static_cast<int>(j));
    }
    any = any || !matches[c].empty();
  }
  if (!any) {
    const std::vector<std::string>& names = cameras.front().detections->names;
    throw InputError(trial.source.path,
                     "sync",
                     "no point of the trial is named like a keypoint of the detections (" +
                         (names.empty() ? std::string("none") : names.front()) + ", …)");
  }
  double frame_s = 0.0;
  for (const CameraDetections& c : cameras) {
    if (static_cast<int>(c.frame_times_s.size()) < c.detections->num_frames())
      throw InputError(c.detections->source,
                       "sync",
                       fmt::format("{} frames of detections but the video has {}",
                                   c.detections->num_frames(),
                                   c.frame_times_s.size()));
    if (frame_s == 0.0) frame_s = MedianInterval(c.frame_times_s);
  }
  if (!(frame_s > 0.0)) throw InputError("", "sync", "the video has fewer than two frames");
  DemandSearchableRange(options, frame_s);

  const double cap = options.max_error_px;
  auto cost = [&](double offset) {
    Cost out;
    double sum = 0.0;
    const VideoSync sync{offset, options.rate};
    for (size_t ci = 0; ci < cameras.size(); ++ci) {
      const CameraDetections& c = cameras[ci];
      for (int k = 0; k < c.detections->num_frames(); ++k) {
        const std::vector<capture::DetectedPerson>& people =
            c.detections->frames[static_cast<size_t>(k)];
        if (people.empty()) continue;
        const double t = sync.TrialTime(c.frame_times_s[static_cast<size_t>(k)]);
        for (const auto& [p, j] : matches[ci]) {
          const std::optional<Eigen::Vector3d> x = PositionAt(trial, p, t);
          if (!x) continue;
          const std::optional<Eigen::Vector2d> uv = c.camera->Project(options.axes.ToWorld(*x));
          if (!uv) continue;
          double best = std::numeric_limits<double>::infinity();
          for (const capture::DetectedPerson& person : people) {
            if (person(2, j) < options.min_confidence) continue;
            best = std::min(best, (person.block<2, 1>(0, j) - *uv).norm());
          }
          if (!std::isfinite(best)) continue;
          sum += std::min(best, cap);
          ++out.count;
        }
      }
    }
    if (out.count > 0) out.value = sum / out.count;
    return out;
  };
  AutoSyncResult r = SearchOffset(cost, frame_s, options);
  r.method = "detections";
  return r;
}

namespace {

// The video's motion for image-motion sync: per frame and analysed row, the running sums of what
// moved (row k holds frame k against frame k − 1), at 1/factor of the video's size.
struct VideoMotion {
  int n = 0, w = 0, h = 0, factor = 1;
  std::vector<std::uint32_t> rows;  // n × h × (w + 1)

  double BoxMotion(int k, int x0, int y0, int x1, int y1) const {
    double m = 0;
    for (int y = y0; y < y1; ++y) {
      const std::uint32_t* row = &rows[(static_cast<size_t>(k) * h + y) * (w + 1)];
      m += double(row[x1]) - double(row[x0]);
    }
    return m;
  }
};

VideoMotion MeasureVideoMotion(capture::VideoReader& video, const AutoSyncOptions& options) {
  const capture::VideoInfo& info = video.info();
  // The video's motion: grey frames averaged over factor × factor blocks, the difference of each
  // frame from the one before less twice its mean (the sensor noise and flicker everywhere), and
  // per row the running sums of what is left, so that any box's motion is a sum over its rows.
  const int n = info.num_frames;
  int factor =
      std::max(1, (info.width + options.analysis_width_px - 1) / options.analysis_width_px);
  // At most 512 MiB of row sums: a long video is analysed at a coarser scale.
  auto bytes = [&](int f) {
    return std::int64_t(n) * (info.height / f) * (info.width / f + 1) * std::int64_t(4);
  };
  while (bytes(factor) > (std::int64_t(512) << 20) && info.width / factor > 16) ++factor;
  if (bytes(factor) > (std::int64_t(512) << 20)) {
    throw InputError(info.path,
                     "sync",
                     fmt::format("{} frames are too many for image-motion sync: cut the video "
                                 "around the trial, or sync from detections",
                                 n));
  }
  const int w = info.width / factor, h = info.height / factor;
  // Row sums: uint16 holds 255 × w for w ≤ 257; the options cap w at 1024 so use 32 bits there.
  std::vector<std::uint32_t> rows(static_cast<size_t>(n) * h * (w + 1), 0);
  std::vector<float> grey(static_cast<size_t>(w) * h), previous;
  std::vector<float> diff(grey.size());
  capture::VideoFrame frame;
  for (int k = 0; k < n; ++k) {
    // Frame 0 by index: the pass starts there whatever the reader read before (a background
    // model built on the same reader, say); then sequentially.
    if (k == 0) {
      frame = video.Frame(0);
    } else if (!video.ReadNext(&frame)) {
      throw InputError(info.path, fmt::format("frame {}", k), "the video ends early");
    }
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        // Grey readers hand out luma; RGB frames are weighted as Rec. 601 luma.
        float s = 0;
        const int c = frame.channels;
        for (int dy = 0; dy < factor; ++dy) {
          const std::uint8_t* px =
              frame.pixels.data() +
              (static_cast<size_t>(y * factor + dy) * frame.width + x * factor) * c;
          for (int dx = 0; dx < factor; ++dx, px += c)
            s += c == 1 ? float(px[0]) : 0.299f * px[0] + 0.587f * px[1] + 0.114f * px[2];
        }
        grey[static_cast<size_t>(y) * w + x] = s / float(factor * factor);
      }
    }
    if (!previous.empty()) {
      double mean = 0.0;
      for (size_t i = 0; i < grey.size(); ++i) {
        diff[i] = std::abs(grey[i] - previous[i]);
        mean += diff[i];
      }
      const float floor = static_cast<float>(2.0 * mean / double(grey.size()));
      for (int y = 0; y < h; ++y) {
        std::uint32_t* row = &rows[(static_cast<size_t>(k) * h + y) * (w + 1)];
        for (int x = 0; x < w; ++x) {
          const float v = std::max(0.0f, diff[static_cast<size_t>(y) * w + x] - floor);
          row[x + 1] = row[x] + static_cast<std::uint32_t>(std::lround(v));
        }
      }
    }
    previous.swap(grey);
    grey.resize(previous.size());
    if (options.progress && !options.progress(k + 1, n)) throw Cancelled();
  }
  VideoMotion out;
  out.n = n;
  out.w = w;
  out.h = h;
  out.factor = factor;
  out.rows = std::move(rows);
  return out;
}

// The trial's side: per sample, the athlete's box in the analysed image and the mean speed of
// the projected points (px per sample) to the next sample.
struct TrialSample {
  bool valid = false;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double speed = 0.0;
};

std::vector<TrialSample> ProjectTrialMotion(const capture::Trial& trial,
                                            const Camera& camera,
                                            const AutoSyncOptions& options,
                                            const VideoMotion& motion) {
  const int factor = motion.factor, w = motion.w, h = motion.h;
  std::vector<TrialSample> samples(static_cast<size_t>(trial.num_frames));
  std::vector<std::optional<Eigen::Vector2d>> uv(static_cast<size_t>(trial.num_points())), next;
  auto project = [&](int f, std::vector<std::optional<Eigen::Vector2d>>* out) {
    out->assign(static_cast<size_t>(trial.num_points()), std::nullopt);
    for (int p = 0; p < trial.num_points(); ++p)
      if (trial.valid(f, p))
        (*out)[static_cast<size_t>(p)] = camera.Project(options.axes.ToWorld(trial.position(f, p)));
  };
  project(0, &uv);
  for (int f = 0; f + 1 < trial.num_frames; ++f) {
    project(f + 1, &next);
    TrialSample& s = samples[static_cast<size_t>(f)];
    Eigen::AlignedBox2d box;
    double speed = 0.0;
    int moving = 0;
    for (size_t p = 0; p < uv.size(); ++p) {
      if (!uv[p]) continue;
      box.extend(*uv[p]);
      if (next[p]) {
        speed += (*next[p] - *uv[p]).norm();
        ++moving;
      }
    }
    uv.swap(next);
    if (moving < 3 || box.isEmpty()) continue;
    const Eigen::Vector2d grow = options.box_margin * box.sizes() + Eigen::Vector2d::Constant(8.0);
    const Eigen::Vector2d lo = (box.min() - grow) / factor, hi = (box.max() + grow) / factor;
    s.x0 = std::clamp(static_cast<int>(std::floor(lo.x())), 0, w);
    s.y0 = std::clamp(static_cast<int>(std::floor(lo.y())), 0, h);
    s.x1 = std::clamp(static_cast<int>(std::ceil(hi.x())), 0, w);
    s.y1 = std::clamp(static_cast<int>(std::ceil(hi.y())), 0, h);
    s.valid = s.x1 > s.x0 && s.y1 > s.y0;
    s.speed = speed / moving;
  }
  return samples;
}

}  // namespace

AutoSyncResult SyncFromImageMotion(const capture::Trial& trial,
                                   const Camera& camera,
                                   capture::VideoReader& video,
                                   const AutoSyncOptions& options) {
  DemandValidOptions(options, "sync");
  const capture::VideoInfo& info = video.info();
  const std::vector<double>& times = video.frame_times_s();
  const double frame_s = MedianInterval(times);
  if (!(frame_s > 0.0)) throw InputError(info.path, "sync", "the video has fewer than two frames");
  DemandSearchableRange(options, frame_s);
  if (trial.num_frames < 2 || !(trial.point_rate_hz > 0))
    throw InputError(trial.source.path, "sync", "the trial has fewer than two samples");

  const VideoMotion motion = MeasureVideoMotion(video, options);
  const int n = motion.n;
  const std::vector<TrialSample> samples = ProjectTrialMotion(trial, camera, options, motion);

  auto cost = [&](double offset) {
    const VideoSync sync{offset, options.rate};
    // Pearson correlation of the box motion with the speed over the overlapping frames.
    double sm = 0, ss = 0, smm = 0, sss = 0, sms = 0;
    int count = 0;
    for (int k = 1; k < n; ++k) {
      const double t =
          sync.TrialTime(0.5 * (times[static_cast<size_t>(k - 1)] + times[static_cast<size_t>(k)]));
      const double x = t * trial.point_rate_hz;
      if (!(x >= 0.0) || x >= trial.num_frames - 1) continue;
      const TrialSample& s = samples[static_cast<size_t>(x)];
      if (!s.valid) continue;
      const double m = motion.BoxMotion(k, s.x0, s.y0, s.x1, s.y1);
      // The trial's speed over one video frame, not one sample.
      const double v = s.speed * trial.point_rate_hz *
                       (times[static_cast<size_t>(k)] - times[static_cast<size_t>(k - 1)]) /
                       options.rate;
      sm += m;
      ss += v;
      smm += m * m;
      sss += v * v;
      sms += m * v;
      ++count;
    }
    Cost out;
    out.count = count;
    if (count < 10) return out;
    const double cov = sms - sm * ss / count;
    const double vm = smm - sm * sm / count, vs = sss - ss * ss / count;
    if (vm > 0 && vs > 0) out.value = 1.0 - cov / std::sqrt(vm * vs);
    return out;
  };
  AutoSyncResult r = SearchOffset(cost, frame_s, options);
  r.method = "image motion";
  return r;
}

}  // namespace acro::vision
