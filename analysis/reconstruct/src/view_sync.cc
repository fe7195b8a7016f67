#include "acro/reconstruct/view_sync.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "acro/base/input_error.h"

namespace acro::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The most confident person of each frame, as undistorted normalised coordinates (NaN where the
// keypoint is absent or below the confidence threshold).
struct Track {
  int frames = 0;
  int points = 0;
  Eigen::Matrix2Xd xy;  // column k·points + j
  const Eigen::Vector2d at(int k, int j) const {
    return xy.col(static_cast<Eigen::Index>(k) * points + j);
  }
};

Track TrackOf(const CameraView& view, double min_confidence) {
  Track t;
  t.frames = view.detections.num_frames();
  t.points = static_cast<int>(view.detections.names.size());
  t.xy.setConstant(2, static_cast<Eigen::Index>(t.frames) * t.points, kNaN);
  const vision::Camera& c = view.camera;
  for (int k = 0; k < t.frames; ++k) {
    const auto& people = view.detections.frames[k];
    if (people.empty()) continue;
    int best = 0;
    double best_sum = -1;
    for (int p = 0; p < static_cast<int>(people.size()); ++p) {
      const double sum = people[p].row(2).sum();
      if (sum > best_sum) {
        best_sum = sum;
        best = p;
      }
    }
    const auto& person = people[best];
    for (int j = 0; j < t.points && j < person.cols(); ++j) {
      if (!(person(2, j) >= min_confidence) || !person.col(j).allFinite()) continue;
      const Eigen::Vector2d u = c.Undistort(person.col(j).head<2>());
      const double y = (u.y() - c.K(1, 2)) / c.K(1, 1);
      const double x = (u.x() - c.K(0, 2) - c.K(0, 1) * y) / c.K(0, 0);
      t.xy.col(static_cast<Eigen::Index>(k) * t.points + j) = Eigen::Vector2d(x, y);
    }
  }
  return t;
}

// The keypoint j of a track at fractional frame s: linear between the frames around it.
Eigen::Vector2d Interpolated(const Track& t, double s, int j) {
  if (!(s >= 0) || s > t.frames - 1) return Eigen::Vector2d::Constant(kNaN);
  const int i = static_cast<int>(std::floor(s));
  const double w = s - i;
  if (w < 1e-9 || i + 1 >= t.frames) return t.at(i, j);
  return (1 - w) * t.at(i, j) + w * t.at(i + 1, j);
}

// Symmetric epipolar distance (px) between x0 (reference view) and x1 (other view) with the
// essential matrix E (x1ᵀ E x0 = 0), f0/f1 the views' focal lengths.
double EpipolarDistance(const Eigen::Matrix3d& E,
                        const Eigen::Vector2d& x0,
                        const Eigen::Vector2d& x1,
                        double f0,
                        double f1) {
  const Eigen::Vector3d h0(x0.x(), x0.y(), 1.0), h1(x1.x(), x1.y(), 1.0);
  const Eigen::Vector3d l1 = E * h0, l0 = E.transpose() * h1;
  const double r = h1.dot(l1);
  const double n1 = l1.head<2>().norm(), n0 = l0.head<2>().norm();
  if (!(n1 > 0) || !(n0 > 0)) return kNaN;
  return 0.5 * (f1 * std::abs(r) / n1 + f0 * std::abs(r) / n0);
}

double Cost(const Track& ref,
            const Track& other,
            const Eigen::Matrix3d& E,
            double f0,
            double f1,
            double rate_ratio,
            double offset,
            const std::vector<int>& frames,
            double cap,
            bool interpolate,
            int* pairs) {
  double sum = 0;
  int n = 0;
  for (const int k : frames) {
    const double s = (k - offset) * rate_ratio;
    if (!(s >= -0.5) || s > other.frames - 0.5) continue;
    for (int j = 0; j < ref.points; ++j) {
      const Eigen::Vector2d x0 = ref.at(k, j);
      if (!x0.allFinite()) continue;
      const Eigen::Vector2d x1 =
          interpolate
              ? Interpolated(other, std::clamp(s, 0.0, other.frames - 1.0), j)
              : other.at(std::clamp(static_cast<int>(std::lround(s)), 0, other.frames - 1), j);
      if (!x1.allFinite()) continue;
      const double d = EpipolarDistance(E, x0, x1, f0, f1);
      if (!std::isfinite(d)) continue;
      sum += std::min(d, cap);
      ++n;
    }
  }
  *pairs = n;
  return n > 0 ? sum / n : kNaN;
}

}  // namespace

bool ViewSyncOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(max_offset_s >= 0 && max_offset_s <= 3600))
    return fail(fmt::format("maximum offset {:g} s is outside 0 … 3600 s", max_offset_s));
  if (!(min_confidence >= 0 && min_confidence <= 1))
    return fail(fmt::format("minimum confidence {:g} is outside 0 … 1", min_confidence));
  if (!(min_distinctness >= 1 && min_distinctness <= 100))
    return fail(fmt::format("distinctness {:g} is outside 1 … 100", min_distinctness));
  if (!(max_distance_px > 0 && max_distance_px <= 1000))
    return fail(fmt::format("distance cap {:g} px is outside (0, 1000]", max_distance_px));
  return true;
}

std::vector<ViewOffset> SyncViews(const std::vector<CameraView>& views,
                                  const std::vector<double>& rates_hz,
                                  const ViewSyncOptions& options,
                                  const Progress& progress) {
  DemandValidOptions(options, "sync");
  if (views.size() < 2) throw InputError("", "sync", "syncing cameras needs at least 2");
  if (rates_hz.size() != views.size())
    throw InputError(
        "", "sync", fmt::format("{} rates for {} cameras", rates_hz.size(), views.size()));
  for (size_t v = 0; v < views.size(); ++v)
    if (!(rates_hz[v] > 0 && rates_hz[v] <= 10000))
      throw InputError("",
                       "camera " + views[v].camera.name,
                       fmt::format("frame rate {:g} Hz is outside (0, 10000]", rates_hz[v]));
  const Track ref = TrackOf(views[0], options.min_confidence);
  const double f0 = 0.5 * (views[0].camera.K(0, 0) + views[0].camera.K(1, 1));
  // The reference's frames compared: at most 600, spread over the take.
  std::vector<int> frames;
  const int step = std::max(1, ref.frames / 600);
  for (int k = 0; k < ref.frames; k += step) frames.push_back(k);

  std::vector<ViewOffset> result(views.size());
  result[0].camera = views[0].camera.name;
  for (size_t v = 1; v < views.size(); ++v) {
    progress.ReportOrThrow("sync", static_cast<int>(v) - 1, static_cast<int>(views.size()) - 1);
    const Track other = TrackOf(views[v], options.min_confidence);
    if (other.points != ref.points)
      throw InputError(views[v].detections.source,
                       "sync",
                       fmt::format("camera {} has {} keypoints, camera {} {}",
                                   views[v].camera.name,
                                   other.points,
                                   views[0].camera.name,
                                   ref.points));
    const vision::Camera& c0 = views[0].camera;
    const vision::Camera& c1 = views[v].camera;
    const Eigen::Matrix3d R = c1.R_KW * c0.R_KW.transpose();
    const Eigen::Vector3d t = c1.t_KW - R * c0.t_KW;
    Eigen::Matrix3d tx;
    tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
    const Eigen::Matrix3d E = tx * R;
    const double f1 = 0.5 * (c1.K(0, 0) + c1.K(1, 1));
    const double ratio = rates_hz[v] / rates_hz[0];  // the other's frames per reference frame
    const int max_lag = static_cast<int>(std::ceil(options.max_offset_s * rates_hz[0]));
    // Enough pairs to decide: a tenth of what the whole overlap could give, at least 20.
    const int min_pairs = 20;

    std::vector<double> costs(2 * max_lag + 1, kNaN);
    std::vector<int> counts(2 * max_lag + 1, 0);
    int most_pairs = 0;
    for (int lag = -max_lag; lag <= max_lag; ++lag) {
      int pairs = 0;
      const double c =
          Cost(ref, other, E, f0, f1, ratio, lag, frames, options.max_distance_px, false, &pairs);
      costs[lag + max_lag] = c;
      counts[lag + max_lag] = pairs;
      most_pairs = std::max(most_pairs, pairs);
    }
    const int needed = std::max(min_pairs, most_pairs / 4);
    int best = -1;
    for (int i = 0; i < static_cast<int>(costs.size()); ++i)
      if (counts[i] >= needed && std::isfinite(costs[i]) && (best < 0 || costs[i] < costs[best]))
        best = i;
    if (best < 0)
      throw InputError(
          views[v].detections.source,
          "sync",
          fmt::format("camera {} shares fewer than {} confident keypoints with camera {} "
                      "at every offset within ±{:g} s",
                      c1.name,
                      min_pairs,
                      c0.name,
                      options.max_offset_s));
    double runner_up = kNaN;
    for (int i = 0; i < static_cast<int>(costs.size()); ++i)
      if (std::abs(i - best) >= 2 && counts[i] >= needed && std::isfinite(costs[i]) &&
          !(costs[i] >= runner_up))
        runner_up = costs[i];
    // A tenth of a frame around the best, on interpolated detections, then a parabola.
    const double centre = best - max_lag;
    double fine_best = centre, fine_cost = std::numeric_limits<double>::infinity();
    std::vector<std::pair<double, double>> fine;
    for (int i = -12; i <= 12; ++i) {
      const double offset = centre + 0.1 * i;
      int pairs = 0;
      const double c =
          Cost(ref, other, E, f0, f1, ratio, offset, frames, options.max_distance_px, true, &pairs);
      fine.emplace_back(offset, c);
      if (pairs >= needed && c < fine_cost) {
        fine_cost = c;
        fine_best = offset;
      }
    }
    double offset = fine_best;
    const int at = static_cast<int>(std::lround((fine_best - centre) / 0.1)) + 12;
    if (at > 0 && at < static_cast<int>(fine.size()) - 1) {
      const double a = fine[at - 1].second, b = fine[at].second, c = fine[at + 1].second;
      const double denominator = a - 2 * b + c;
      if (std::isfinite(denominator) && denominator > 0)
        offset += std::clamp(0.5 * (a - c) / denominator, -0.5, 0.5) * 0.1;
    }
    int pairs = 0;
    const double cost =
        Cost(ref, other, E, f0, f1, ratio, offset, frames, options.max_distance_px, true, &pairs);
    result[v] = {c1.name,
                 offset,
                 cost,
                 runner_up,
                 pairs,
                 !std::isfinite(runner_up) || runner_up >= options.min_distinctness * cost};
  }
  progress.ReportOrThrow(
      "sync", static_cast<int>(views.size()) - 1, static_cast<int>(views.size()) - 1);
  return result;
}

capture::KeypointDetections ResampleDetections(const capture::KeypointDetections& source,
                                               double source_rate_hz,
                                               double target_rate_hz,
                                               double offset_frames,
                                               int num_frames) {
  capture::KeypointDetections out;
  out.source = source.source;
  out.names = source.names;
  out.warnings = source.warnings;
  out.frames.resize(std::max(0, num_frames));
  const int n = static_cast<int>(source.names.size());
  const double ratio = source_rate_hz / target_rate_hz;
  auto person_at = [&](int i) -> const capture::DetectedPerson* {
    if (i < 0 || i >= source.num_frames() || source.frames[i].empty()) return nullptr;
    return &source.frames[i][0];
  };
  for (int k = 0; k < num_frames; ++k) {
    const double s = (k - offset_frames) * ratio;
    if (!(s > -0.01) || s > source.num_frames() - 1 + 0.01) continue;
    const int i = static_cast<int>(std::floor(s));
    const double w = s - i;
    const capture::DetectedPerson* a = person_at(i);
    const capture::DetectedPerson* b = person_at(i + 1);
    capture::DetectedPerson p = capture::DetectedPerson::Zero(3, n);
    bool any = false;
    for (int j = 0; j < n; ++j) {
      const bool in_a = a && j < a->cols() && (*a)(2, j) > 0;
      const bool in_b = b && j < b->cols() && (*b)(2, j) > 0;
      if (w < 0.01 && in_a) {
        p.col(j) = a->col(j);
      } else if (w > 0.99 && in_b) {
        p.col(j) = b->col(j);
      } else if (in_a && in_b) {
        p.col(j).head<2>() = (1 - w) * a->col(j).head<2>() + w * b->col(j).head<2>();
        p(2, j) = std::min((*a)(2, j), (*b)(2, j));
      } else {
        continue;
      }
      any = true;
    }
    if (any) out.frames[k].push_back(p);
  }
  return out;
}

}  // namespace acro::analysis
