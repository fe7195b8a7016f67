#include "acro/reconstruct/up_axis.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "acro/base/input_error.h"
#include "acro/reconstruct/markerset.h"

namespace acro::analysis {

std::string UpAxis::Name() const {
  return std::string(sign > 0 ? "+" : "-") + char('X' + axis);
}

UpAxis DetectUpAxis(const capture::Trial& trial) {
  UpAxis up;
  MarkerSetMatch match;
  MarkerSet set;
  try {
    set = DetectMarkerSet(trial, &match);
  } catch (const InputError&) {
    return up;  // no known marker set: nothing to tell up by
  }
  std::vector<int> head, feet;
  for (size_t k = 0; k < set.markers.size(); ++k) {
    const int point = match.trial_point[k];
    if (point < 0) continue;
    const std::string& segment = set.markers[k].segment;
    if (segment == "head") head.push_back(point);
    if (segment == "r_foot" || segment == "l_foot") feet.push_back(point);
  }
  if (head.empty() || feet.empty()) return up;
  const auto mean_of = [&](const std::vector<int>& points, int frame, Eigen::Vector3d* mean) {
    int n = 0;
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (const int p : points)
      if (trial.valid(frame, p)) {
        s += trial.position(frame, p);
        ++n;
      }
    if (n > 0) *mean = s / n;
    return n > 0;
  };
  // Per frame, the axis (±x, ±y, ±z) the feet→head direction lies within 45° of, if any: the body
  // upright along it. The axis with the most such frames is up — a routine is upright in every
  // contact and around every take-off and landing, upside down only for moments.
  int upright[6] = {0, 0, 0, 0, 0, 0};  // +x −x +y −y +z −z
  int used = 0;
  for (int f = 0; f < trial.num_frames; ++f) {
    Eigen::Vector3d h, o;
    if (!mean_of(head, f, &h) || !mean_of(feet, f, &o)) continue;
    const Eigen::Vector3d d = h - o;
    if (!(d.norm() > 0.3)) continue;  // a crouch seen end-on, or a bad frame
    ++used;
    const Eigen::Vector3d u = d.normalized();
    int k = 0;
    const double largest = u.cwiseAbs().maxCoeff(&k);
    if (largest >= std::cos(std::numbers::pi / 4)) ++upright[2 * k + (u[k] < 0 ? 1 : 0)];
  }
  up.frames = used;
  if (used < 10) return up;
  const int* best = std::max_element(std::begin(upright), std::end(upright));
  int runner_up = 0;
  for (const int* c = std::begin(upright); c != std::end(upright); ++c)
    if (c != best) runner_up = std::max(runner_up, *c);
  const int index = static_cast<int>(best - std::begin(upright));
  up.axis = index / 2;
  up.sign = index % 2 == 0 ? 1 : -1;
  up.agreement = double(*best) / used;
  // Clearly: upright along it in a quarter of the frames at least, twice as often as along any
  // other.
  up.found = up.agreement >= 0.25 && *best >= 2 * runner_up;
  if (!up.found) {
    const int frames = up.frames;
    up = UpAxis{};
    up.frames = frames;
  }
  return up;
}

Eigen::Matrix3d RotationToZUp(const UpAxis& up) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  u[up.axis] = up.sign;
  if (u.z() > 0.5) return Eigen::Matrix3d::Identity();
  if (u.z() < -0.5)
    return Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // A quarter turn about the horizontal axis perpendicular to both.
  return Eigen::Quaterniond::FromTwoVectors(u, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

std::string OrientTrialUp(capture::Trial* trial, const std::string& up, UpAxis* found) {
  UpAxis axis;
  std::string how;
  if (up == "auto") {
    axis = DetectUpAxis(*trial);
    if (found) *found = axis;
    if (!axis.found || (axis.axis == 2 && axis.sign > 0)) return "";
    how = fmt::format(
        "detected: the body upright along {} in {:.0f} % of {} frames; --up z keeps "
        "the file as it is",
        axis.Name(),
        100 * axis.agreement,
        axis.frames);
  } else {
    std::string a = up;
    int sign = 1;
    if (!a.empty() && (a[0] == '-' || a[0] == '+')) {
      sign = a[0] == '-' ? -1 : 1;
      a = a.substr(1);
    }
    if (a != "x" && a != "y" && a != "z")
      throw InputError("", "--up", "'" + up + "' is not auto, x, y, z, -x, -y or -z");
    axis.axis = a[0] - 'x';
    axis.sign = sign;
    axis.found = true;
    if (found) *found = axis;
    if (axis.axis == 2 && axis.sign > 0) return "";
    how = "as --up says";
  }
  capture::RotateTrial(RotationToZUp(axis), trial);
  return trial->source.path + ": " + axis.Name() + " up (" + how + "), turned to Z up";
}

}  // namespace acro::analysis
