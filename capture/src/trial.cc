#include "acro/capture/trial.h"

#include <cmath>

#include <fmt/format.h>

#include "acro/base/input_error.h"

namespace acro::capture {
namespace {

// The label without a "Subject:" prefix (Vicon Nexus writes "Subject:Marker").
std::string_view WithoutSubject(std::string_view label) {
  const std::size_t colon = label.rfind(':');
  return colon == std::string_view::npos ? label : label.substr(colon + 1);
}

}  // namespace

int Trial::analog_samples_per_frame() const {
  if (analog.cols() == 0 || analog.rows() == 0) return 0;
  if (num_frames > 0) return static_cast<int>(analog.cols() / num_frames);
  if (point_rate_hz > 0) return static_cast<int>(std::lround(analog_rate_hz / point_rate_hz));
  return 0;
}

int Trial::FindPoint(const std::string& label) const {
  for (int i = 0; i < num_points(); ++i) {
    if (points[i].label == label) return i;
  }
  const std::string_view wanted = WithoutSubject(label);
  for (int i = 0; i < num_points(); ++i) {
    if (WithoutSubject(points[i].label) == wanted) return i;
  }
  return -1;
}

int Trial::FindAnalog(const std::string& label) const {
  for (int i = 0; i < num_analog_channels(); ++i) {
    if (analog_channels[i].label == label) return i;
  }
  return -1;
}

void RotateTrial(const Eigen::Matrix3d& R_new_old, Trial* trial) {
  trial->positions = R_new_old * trial->positions;  // NaN gaps stay NaN
  for (ForcePlate& plate : trial->force_plates) {
    plate.corners_W_m = R_new_old * plate.corners_W_m;
    for (Eigen::Matrix3Xd* m :
         {&plate.force_W_N, &plate.cop_W_m, &plate.free_moment_W_Nm, &plate.moment_at_origin_W_Nm})
      if (m->cols() > 0) *m = R_new_old * *m;
  }
}

void GapImpossiblePositions(Trial* trial, const std::string& file) {
  constexpr double kFarthest_m = 1e4;
  const int points = trial->num_points();
  std::int64_t count = 0;
  std::string first;
  for (int f = 0; f < trial->num_frames; ++f) {
    for (int p = 0; p < points; ++p) {
      auto x = trial->position(f, p);
      if (std::isnan(x(0)) && std::isnan(x(1)) && std::isnan(x(2))) continue;
      const bool finite = x.allFinite();
      // Positions are metres only for markers; other point types (angles, forces) are only
      // held to finiteness.
      const bool far = finite && trial->points[p].type == PointType::kMarker &&
                       x.cwiseAbs().maxCoeff() > kFarthest_m;
      if (finite && !far) continue;
      if (count++ == 0) {
        first = fmt::format("{} at frame {}: ({:g}, {:g}, {:g})", trial->points[p].label,
                            trial->first_frame + f, x(0), x(1), x(2));
      }
      x.setConstant(std::numeric_limits<double>::quiet_NaN());
      if (p < trial->residuals.rows() && f < trial->residuals.cols()) trial->residuals(p, f) = -1.0f;
    }
  }
  if (count == 0) return;
  trial->warnings.push_back(fmt::format(
      "{}: {} position{} not finite or farther than 10 km from the origin, read as gaps (the first: "
      "{})",
      file, count, count == 1 ? " is" : "s are", first));
}

TrialContent CountContent(const Trial& trial) {
  TrialContent c;
  c.frames = trial.num_frames;
  std::vector<char> marker_seen(trial.points.size(), 0);
  for (int p = 0; p < trial.num_points(); ++p) c.markers += trial.points[p].type == PointType::kMarker;
  for (int f = 0; f < trial.num_frames; ++f) {
    bool any = false;
    for (int p = 0; p < trial.num_points(); ++p) {
      if (trial.points[p].type != PointType::kMarker || !trial.valid(f, p)) continue;
      any = true;
      marker_seen[p] = 1;
    }
    c.frames_with_data += any;
  }
  for (char seen : marker_seen) c.markers_with_data += seen;
  return c;
}

void DemandUsableContent(const Trial& trial, const std::string& file, int min_frames,
                         const std::string& use) {
  const TrialContent c = CountContent(trial);
  const auto plural = [](int n, const char* one) {
    return fmt::format("{} {}{}", n, one, n == 1 ? "" : "s");
  };
  if (c.markers == 0)
    throw InputError(file, "", fmt::format("holds no marker: nothing for {}", use));
  if (c.markers_with_data == 0) {
    throw InputError(file, "", fmt::format("none of its {} has a position in any of its {} (all "
                                           "gaps, NaN or impossible): nothing for {}",
                                           plural(c.markers, "marker"), plural(c.frames, "frame"),
                                           use));
  }
  if (c.frames_with_data < min_frames) {
    const std::string held = c.frames_with_data == c.frames
                                 ? "holds " + plural(c.frames, "frame")
                                 : fmt::format("holds {} with a marker position (of {})",
                                               plural(c.frames_with_data, "frame"), c.frames);
    throw InputError(file, "", fmt::format("{}; {} needs at least {}", held, use, min_frames));
  }
}

}  // namespace acro::capture
