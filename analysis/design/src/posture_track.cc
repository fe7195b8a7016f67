#include "acro/design/posture_track.h"

#include <algorithm>

#include "acro/base/demand.h"

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

}  // namespace

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
