#include "acro/design/posture_track.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "acro/base/demand.h"
#include "acro/design/skill_file.h"

namespace acro::analysis {
namespace {

// S(u) = u⁴(35 − 84u + 70u² − 20u³) and its first two derivatives, u clamped to [0, 1].
void SmoothStep(double u, double* s, double* ds, double* dds) {
  u = std::clamp(u, 0.0, 1.0);
  const double u2 = u * u, v = 1 - u;
  *s = u2 * u2 * (35 - 84 * u + 70 * u2 - 20 * u2 * u);
  *ds = 140 * u2 * u * v * v * v;
  *dds = 420 * u2 * v * v * (1 - 2 * u);
}

void Set(Eigen::VectorXd& q, std::string_view segment, int axis, double value) {
  const int i = StandardJointDofIndex(segment, axis);
  ACRO_DEMAND(i >= 0);
  q[i] = value;
}

void Add(Eigen::VectorXd& q, std::string_view segment, int axis, double value) {
  const int i = StandardJointDofIndex(segment, axis);
  ACRO_DEMAND(i >= 0);
  q[i] += value;
}

// Both sides; `mirror` multiplies the left side's value (−1 for angles about x).
void Both(
    Eigen::VectorXd& q, const std::string& segment, int axis, double right, double mirror = 1) {
  Set(q, "r_" + segment, axis, right);
  Set(q, "l_" + segment, axis, mirror * right);
}

}  // namespace

double PostureBlend(double u) {
  double s = 0, ds = 0, dds = 0;
  SmoothStep(u, &s, &ds, &dds);
  return s;
}

const char* PostureName(Posture posture) {
  switch (posture) {
    case Posture::kTakeoff:
      return "take-off";
    case Posture::kStraight:
      return "straight";
    case Posture::kTuck:
      return "tuck";
    case Posture::kPike:
      return "pike";
    case Posture::kTwist:
      return "twisting";
    case Posture::kLanding:
      return "landing";
  }
  return "";
}

Eigen::VectorXd PostureJoints(Posture posture, double action) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(StandardJointDofCount());
  switch (posture) {
    case Posture::kTakeoff:
      Both(q, "upper_arm", 0, -2.8);
      break;
    case Posture::kStraight:
      Both(q, "upper_arm", 2, -0.12, -1);
      Both(q, "foot", 0, 0.4);
      break;
    case Posture::kTuck:
      Set(q, "thorax", 0, 0.25);
      Set(q, "head", 0, 0.2);
      Both(q, "thigh", 0, -2.3);
      Both(q, "shank", 0, 2.25);
      Both(q, "foot", 0, 0.5);
      Both(q, "upper_arm", 0, -0.45);
      Both(q, "forearm", 0, -1.6);
      break;
    case Posture::kPike:
      Set(q, "thorax", 0, 0.3);
      Set(q, "head", 0, 0.2);
      Both(q, "thigh", 0, -2.2);
      Both(q, "foot", 0, 0.5);
      Both(q, "upper_arm", 0, -1.3);
      break;
    case Posture::kTwist:
      Both(q, "upper_arm", 0, -0.35);
      Both(q, "upper_arm", 2, -0.1, -1);
      Both(q, "forearm", 0, -2.0);
      Both(q, "foot", 0, 0.4);
      break;
    case Posture::kLanding:
      Both(q, "upper_arm", 0, -1.0);
      Both(q, "thigh", 0, -0.5);
      Both(q, "shank", 0, 0.35);
      break;
  }
  if (action != 0.0) {
    const double out = std::abs(action), in = 0.5 * std::abs(action);
    Add(q, "l_upper_arm", 2, action > 0 ? out : -in);
    Add(q, "r_upper_arm", 2, action > 0 ? in : -out);
    Add(q, "r_thigh", 2, 0.4 * action);
    Add(q, "l_thigh", 2, 0.4 * action);
  }
  return q;
}

void PostureTrack::Add(double time_s, Eigen::VectorXd joints) {
  ACRO_DEMAND(keys_.empty() ||
              (time_s >= keys_.back().first && joints.size() == keys_.back().second.size()));
  keys_.emplace_back(time_s, std::move(joints));
}

void PostureTrack::Eval(double t,
                        Eigen::Ref<Eigen::VectorXd> q,
                        Eigen::Ref<Eigen::VectorXd> qd,
                        Eigen::Ref<Eigen::VectorXd> qdd) const {
  ACRO_DEMAND(!keys_.empty());
  qd.setZero();
  qdd.setZero();
  if (t <= keys_.front().first) {
    q = keys_.front().second;
    return;
  }
  for (size_t k = 0; k + 1 < keys_.size(); ++k) {
    const double t0 = keys_[k].first, t1 = keys_[k + 1].first;
    if (t < t1) {
      double s, ds, dds;
      SmoothStep((t - t0) / (t1 - t0), &s, &ds, &dds);
      const Eigen::VectorXd dq = keys_[k + 1].second - keys_[k].second;
      q = keys_[k].second + s * dq;
      qd = ds / (t1 - t0) * dq;
      qdd = dds / ((t1 - t0) * (t1 - t0)) * dq;
      return;
    }
  }
  q = keys_.back().second;
}

Eigen::VectorXd PostureTrack::At(double t) const {
  ACRO_DEMAND(!keys_.empty());
  const Eigen::Index n = keys_.front().second.size();
  Eigen::VectorXd q(n), qd(n), qdd(n);
  Eval(t, q, qd, qdd);
  return q;
}

}  // namespace acro::analysis
