#include "acro/vision/projection.h"

#include <fmt/format.h>

#include "acro/base/input_error.h"

namespace acro::vision {

AxisMapping ParseAxisMapping(const std::string& text) {
  AxisMapping m;
  int k = 0;
  bool used[3] = {false, false, false};
  double sign = 1.0;
  for (char c : text) {
    if (c == '-' && sign > 0) {
      sign = -1.0;
      continue;
    }
    const int axis = c == 'x' ? 0 : c == 'y' ? 1 : c == 'z' ? 2 : -1;
    if (axis < 0 || k >= 3 || used[axis])
      throw InputError(
          "", "--axes", "'" + text + "' is not three of x, y, z, each once, a minus flipping one");
    used[axis] = true;
    m.index[k] = axis;
    m.sign[k] = sign;
    sign = 1.0;
    ++k;
  }
  if (k != 3) throw InputError("", "--axes", "'" + text + "' does not name three axes");
  return m;
}

std::vector<ProjectedPoint> ProjectTrial(const capture::Trial& trial,
                                         const Camera& camera,
                                         const AxisMapping& axes,
                                         double offset_s) {
  std::vector<ProjectedPoint> out;
  const double dt = trial.point_rate_hz > 0 ? 1.0 / trial.point_rate_hz : 0.0;
  for (int f = 0; f < trial.num_frames; ++f) {
    for (int p = 0; p < trial.num_points(); ++p) {
      if (!trial.valid(f, p)) continue;
      const auto uv = camera.Project(axes.ToWorld(trial.position(f, p)));
      if (!uv) continue;
      out.push_back({f, offset_s + f * dt, p, *uv, f});
    }
  }
  return out;
}

std::vector<ProjectedPoint> ProjectTrialOnFrames(const capture::Trial& trial,
                                                 const Camera& camera,
                                                 const std::vector<double>& frame_times_s,
                                                 const VideoSync& sync,
                                                 const AxisMapping& axes) {
  std::vector<ProjectedPoint> out;
  for (size_t k = 0; k < frame_times_s.size(); ++k) {
    const int f = sync.NearestSample(trial, frame_times_s[k]);
    if (f < 0) continue;
    for (int p = 0; p < trial.num_points(); ++p) {
      if (!trial.valid(f, p)) continue;
      const auto uv = camera.Project(axes.ToWorld(trial.position(f, p)));
      if (!uv) continue;
      out.push_back({static_cast<int>(k), frame_times_s[k], p, *uv, f});
    }
  }
  return out;
}

std::string FormatProjectionCsv(const capture::Trial& trial,
                                const Camera& camera,
                                const std::vector<ProjectedPoint>& points) {
  std::string csv = "camera,frame,time_s,marker,u_px,v_px\n";
  for (const ProjectedPoint& p : points) {
    csv += fmt::format("{},{},{:.6f},{},{:.3f},{:.3f}\n",
                       camera.name,
                       p.frame,
                       p.time_s,
                       trial.points[static_cast<size_t>(p.marker)].label,
                       p.uv_px.x(),
                       p.uv_px.y());
  }
  return csv;
}

}  // namespace acro::vision
