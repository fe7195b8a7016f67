#pragma once

// The postures of trampoline skills as joint angles of the standard human, and prescribed joint
// angles of a flight: postures at given times joined by septic smoothsteps
// S(u) = u⁴(35 − 84u + 70u² − 20u³), whose first three derivatives vanish at both ends, so the
// joint motion is C³ and a fixed-step RK4 flight simulation keeps its full order across the
// postures. Held before the first and after the last. Used by the skill-from-code designer and
// the sample routine generator.

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

/// The postures a skill is made of (standard_human.h signs: hip, shoulder and elbow flexion
/// negative, knee flexion positive, foot positive = toes down; abduction of the right arm negative
/// about x, the left one mirrored):
///   take-off: arms overhead; straight: arms by the sides, toes pointed; tuck; pike;
///   twisting: arms wrapped in front of the chest, legs straight and together;
///   landing: arms forward, hips and knees a little flexed.
enum class Posture { kTakeoff, kStraight, kTuck, kPike, kTwist, kLanding };

/// "take-off", "straight", "tuck", "pike", "twisting", "landing".
const char* PostureName(Posture posture);

/// The posture's joint angles (StandardJointDofCount() entries, rad). `aerial_twist_action_rad`
/// adds the asymmetric arm and hip action that starts a twist in the air: one arm swings out
/// sideways by |action| (the left one for a positive action, the right one for a negative), the
/// other in across the chest by half as much, and both hips bend sideways by 0.4 of it — all three
/// turn the trunk the same way about its front–back axis.
Eigen::VectorXd PostureJoints(Posture posture, double aerial_twist_action_rad = 0.0);

/// The track's blend between two postures: S(u) = u⁴(35 − 84u + 70u² − 20u³), u clamped to [0, 1]
/// (the fraction of the way from one posture to the next).
double PostureBlend(double u);

class PostureTrack {
 public:
  /// Appends a posture (joint angles, rad) at `time_s`; times must not decrease.
  void Add(double time_s, Eigen::VectorXd joints);
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
