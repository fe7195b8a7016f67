#pragma once

// The two forms of a designed motion (skill_design.h), as templates for double and ceres::Jet:
// the keyframe form (splines through the keyframes at times given by gaps) that Model 2
// differentiates, the local form's evaluation (quintic Hermite knots, hermite_trajectory.h) that
// Model 1 differentiates per sample, and a double-precision evaluator of either for the
// profiles, the reports and the flight simulation. Internal to acro_design.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "acro/base/cubic_spline.h"
#include "acro/base/demand.h"
#include "acro/design/quaternion_spline.h"
#include "acro/design/skill_design.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::analysis::internal {

// Simpson weights on N intervals over [0, T] divided by T, so that Σ w_k f_k ≈ T⁻¹ ∫ f dt.
inline Eigen::VectorXd SimpsonWeightsOverT(int intervals) {
  ACRO_DEMAND(intervals >= 2 && intervals % 2 == 0);
  Eigen::VectorXd w(intervals + 1);
  for (int k = 0; k <= intervals; ++k)
    w[k] = (k == 0 || k == intervals) ? 1.0 : (k % 2 ? 4.0 : 2.0);
  return w / (3.0 * intervals);
}

// Keyframe times from the gaps: t_i = T Σ_{j<i} g_j / Σ g_j, with t_0 = 0 and t_n = T exact.
template <typename T>
std::vector<T> TimesFromGaps(const T* gaps, int n, double duration) {
  T sum(0.0);
  for (int j = 0; j + 1 < n; ++j) sum += gaps[j];
  std::vector<T> t(static_cast<size_t>(n));
  T cum(0.0);
  t[0] = T(0.0);
  for (int i = 1; i + 1 < n; ++i) {
    cum += gaps[i - 1];
    t[static_cast<size_t>(i)] = T(duration) * cum / sum;
  }
  t[static_cast<size_t>(n - 1)] = T(duration);
  return t;
}

// The splines of one evaluation: joint channels and the orientation, for scalar T.
template <typename T>
struct SkillSplines {
  CubicSplineKnots<T> joint_knots;
  std::vector<T> joint_values;   // ndof × n, channel-major
  std::vector<T> joint_moments;  // ndof × n
  QuaternionSpline<T> orientation;
  int ndof = 0;
  int n = 0;
};

// Builds the keyframe splines through `base`'s keyframes at the times the gaps give.
template <typename T>
void BuildSplines(const SkillDesign& design,
                  const SkillTrajectory& base,
                  const T* gaps,
                  SkillSplines<T>& s) {
  const int n = design.num_keyframes();
  const int ndof = design.num_joint_dofs();
  s.n = n;
  s.ndof = ndof;
  const std::vector<T> t = TimesFromGaps(gaps, n, design.flight_time_s());
  s.joint_knots.Reset(t);
  s.joint_values.resize(static_cast<size_t>(ndof * n));
  s.joint_moments.resize(static_cast<size_t>(ndof * n));
  for (int j = 0; j < ndof; ++j) {
    T* y = s.joint_values.data() + j * n;
    for (int i = 0; i < n; ++i) y[i] = T(base.joint_angles_rad(j, i));
    s.joint_knots.SolveMoments(y, s.joint_moments.data() + j * n);
  }
  std::vector<Eigen::Quaternion<T>> knot_q;
  for (int i = 0; i < n; ++i)
    knot_q.push_back(base.keyframe_orientations[static_cast<size_t>(i)].template cast<T>());
  s.orientation.Reset(t, std::move(knot_q));
}

// q, v, a at time t with the root at the origin, at rest in translation (the moment residual about
// the COM does not depend on the root translation).
template <typename T>
void SampleState(const SkillSplines<T>& s,
                 double t,
                 dynamics::VectorX<T>& q,
                 dynamics::VectorX<T>& v,
                 dynamics::VectorX<T>& a) {
  const SplineWeights<T> w = s.joint_knots.Weights(s.joint_knots.FindInterval(t), t);
  for (int j = 0; j < s.ndof; ++j) {
    const SplineSample<T> y =
        s.joint_knots.Combine(w, s.joint_values.data() + j * s.n, s.joint_moments.data() + j * s.n);
    q[dynamics::kRootNq + j] = y.value;
    v[dynamics::kRootNv + j] = y.d1;
    a[dynamics::kRootNv + j] = y.d2;
  }
  const QuaternionSample<T> r = s.orientation.Eval(t);
  q.template head<3>().setZero();
  dynamics::SetRootQuaternion<T>(r.q_WB, q);
  v.template head<3>().setZero();
  a.template head<3>().setZero();
  v.template segment<3>(3) = r.w_WB_B;
  a.template segment<3>(3) = r.wdot_WB_B;
}

// The model and workspace for one scalar type.
template <typename T>
struct ScalarKit {
  explicit ScalarKit(const dynamics::Model<double>& m)
      : model(m.Cast<T>()), ws(model), q(model.nq()), v(model.nv()), a(model.nv()) {}
  dynamics::Model<T> model;
  dynamics::Workspace<T> ws;
  dynamics::VectorX<T> q, v, a;
  SkillSplines<T> splines;
};

/// Joint angles, rates, accelerations and the root orientation, body angular velocity and
/// acceleration of a trajectory with knots at time t (double).
void CalcKnotMotion(const SkillTrajectory& trajectory,
                    double t,
                    Eigen::Ref<Eigen::VectorXd> qj,
                    Eigen::Ref<Eigen::VectorXd> vj,
                    Eigen::Ref<Eigen::VectorXd> aj,
                    Eigen::Quaterniond* q_WB,
                    Eigen::Vector3d* w_WB_B,
                    Eigen::Vector3d* wdot_WB_B);

// A double-precision evaluator of the designed motion: Model 2's keyframe splines (built once) or
// Model 1's local form.
class MotionEvaluator {
 public:
  MotionEvaluator(const SkillDesign& design,
                  const SkillTrajectory& trajectory,
                  const Eigen::Vector3d& com_start_W)
      : design_(design), trajectory_(trajectory), kit_(design.model()), com_start_W_(com_start_W) {
    if (trajectory.has_knots()) return;
    Eigen::VectorXd gaps(design.num_keyframes() - 1);
    for (int i = 0; i + 1 < design.num_keyframes(); ++i)
      gaps[i] = trajectory.times_s[i + 1] - trajectory.times_s[i];
    BuildSplines(design, trajectory, gaps.data(), kit_.splines);
  }

  // q, v, a with the root at the origin, at rest in translation.
  void State(double t,
             Eigen::Ref<Eigen::VectorXd> q,
             Eigen::Ref<Eigen::VectorXd> v,
             Eigen::Ref<Eigen::VectorXd> a) const {
    if (!trajectory_.has_knots()) {
      dynamics::VectorX<double>& kq = kit_.q;
      SampleState(kit_.splines, t, kq, kit_.v, kit_.a);
      q = kit_.q;
      v = kit_.v;
      a = kit_.a;
      return;
    }
    const int ndof = design_.num_joint_dofs();
    Eigen::Quaterniond q_WB;
    Eigen::Vector3d w, wdot;
    CalcKnotMotion(trajectory_, t, q.tail(ndof), v.tail(ndof), a.tail(ndof), &q_WB, &w, &wdot);
    q.head<3>().setZero();
    dynamics::SetRootQuaternion<double>(q_WB, q);
    v.head<3>().setZero();
    a.head<3>().setZero();
    v.segment<3>(3) = w;
    a.segment<3>(3) = wdot;
  }

  // Joint angles, rates and accelerations only.
  void Joints(double t,
              Eigen::Ref<Eigen::VectorXd> qj,
              Eigen::Ref<Eigen::VectorXd> vj,
              Eigen::Ref<Eigen::VectorXd> aj) const {
    State(t, kit_.q, kit_.v, kit_.a);
    qj = kit_.q.tail(qj.size());
    vj = kit_.v.tail(vj.size());
    aj = kit_.a.tail(aj.size());
  }

  // The full state with the root translation that keeps the COM on the take-off parabola.
  SkillMotionState Eval(double t) const {
    SkillMotionState s;
    s.q = Eigen::VectorXd(kit_.model.nq());
    s.v = Eigen::VectorXd(kit_.model.nv());
    s.a = Eigen::VectorXd(kit_.model.nv());
    State(t, s.q, s.v, s.a);
    const dynamics::Model<double>& m = kit_.model;
    dynamics::Workspace<double>& ws = kit_.ws;
    // COM position, velocity and acceleration relative to a root fixed at the origin.
    dynamics::CalcForwardKinematics(m, ws, s.q, s.v);
    const Eigen::Vector3d p0 = dynamics::CalcCenterOfMassPosition(m, ws);
    const Eigen::Vector3d v0 = dynamics::CalcCenterOfMassVelocity(m, ws);
    const Eigen::Vector3d a0 = dynamics::CalcCenterOfMassAcceleration(m, ws, s.q, s.v, s.a);
    // The parabola: p_G = p_start + v_takeoff t + ½ g t².
    const Eigen::Vector3d g = m.gravity_W();
    const Eigen::Vector3d& vt = design_.skill().takeoff_com_velocity_mps;
    s.q.head<3>() = com_start_W_ + vt * t + 0.5 * g * t * t - p0;
    s.v.head<3>() = vt + g * t - v0;
    s.a.head<3>() = g - a0;
    return s;
  }

 private:
  const SkillDesign& design_;
  const SkillTrajectory& trajectory_;
  mutable ScalarKit<double> kit_;
  Eigen::Vector3d com_start_W_;
};

}  // namespace acro::analysis::internal
