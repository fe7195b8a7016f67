#pragma once

// Prescribed joint angles of a flight: postures at given times joined by septic smoothsteps
// S(u) = u⁴(35 − 84u + 70u² − 20u³), whose first three derivatives vanish at both ends, so the
// joint motion is C³ and a fixed-step RK4 flight simulation keeps its full order across the
// postures. Held before the first and after the last. Used by the skill-from-code designer and
// the sample routine generator.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

class PostureTrack {
 public:
  /// Appends a posture (joint angles, rad) at `time_s`; times must not decrease.
  void Add(double time_s, Eigen::VectorXd joints);
  bool empty() const { return keys_.empty(); }
  const std::vector<std::pair<double, Eigen::VectorXd>>& keys() const { return keys_; }
  /// Angles, rates and accelerations at t.
  void Eval(double t,
            Eigen::Ref<Eigen::VectorXd> q,
            Eigen::Ref<Eigen::VectorXd> qd,
            Eigen::Ref<Eigen::VectorXd> qdd) const;
  Eigen::VectorXd At(double t) const;

 private:
  std::vector<std::pair<double, Eigen::VectorXd>> keys_;
};

}  // namespace acro::analysis
