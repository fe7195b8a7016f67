// A skill made ready for design and the two forms of its motion (skill_design.h).

#include "acro/design/skill_design.h"

#include <algorithm>
#include <cmath>

#include "acro/athlete/standard_human.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "hermite_trajectory.h"
#include "skill_motion.h"

namespace acro::analysis {

namespace internal {

void CalcKnotMotion(const SkillTrajectory& tr,
                    double t,
                    Eigen::Ref<Eigen::VectorXd> qj,
                    Eigen::Ref<Eigen::VectorXd> vj,
                    Eigen::Ref<Eigen::VectorXd> aj,
                    Eigen::Quaterniond* q_WB,
                    Eigen::Vector3d* w_WB_B,
                    Eigen::Vector3d* wdot_WB_B) {
  ACRO_DEMAND(tr.has_knots());
  const int n = static_cast<int>(tr.times_s.size());
  const int P = tr.knots_per_interval;
  // Keyframe interval i, then the knot interval inside it.
  int i = 0;
  while (i < n - 2 && t >= tr.times_s[i + 1]) ++i;
  const double H = tr.times_s[i + 1] - tr.times_s[i];
  const double h = H / P;
  int j = static_cast<int>(std::floor((t - tr.times_s[i]) / h));
  j = std::clamp(j, 0, P - 1);
  const int k = i * P + j;
  const double u = (t - (tr.times_s[i] + j * h)) / h;
  const QuinticHermiteBasis B(u);
  for (int c = 0; c < qj.size(); ++c) {
    const double data[6] = {tr.knot_joint_angles_rad(c, k),
                            tr.knot_joint_rates(c, k),
                            tr.knot_joint_accelerations(c, k),
                            tr.knot_joint_angles_rad(c, k + 1),
                            tr.knot_joint_rates(c, k + 1),
                            tr.knot_joint_accelerations(c, k + 1)};
    qj[c] = QuinticHermite<double, double>(B, 0, h, data);
    vj[c] = QuinticHermite<double, double>(B, 1, h, data);
    aj[c] = QuinticHermite<double, double>(B, 2, h, data);
  }
  OrientationKnot<double> a, b;
  a.Q = tr.knot_orientations[static_cast<size_t>(k)];
  a.w = tr.knot_angular_velocities_B.col(k);
  a.wdot = tr.knot_angular_accelerations_B.col(k);
  b.Q = tr.knot_orientations[static_cast<size_t>(k + 1)];
  b.w = tr.knot_angular_velocities_B.col(k + 1);
  b.wdot = tr.knot_angular_accelerations_B.col(k + 1);
  const QuaternionSample<double> r = EvalOrientationHermite<double>(B, h, a, b);
  *q_WB = r.q_WB;
  *w_WB_B = r.w_WB_B;
  *wdot_WB_B = r.wdot_WB_B;
}

}  // namespace internal

SkillTrajectory MakeKnotTrajectory(const SkillTrajectory& t, int knots_per_interval) {
  ACRO_DEMAND(knots_per_interval >= 1 && !t.has_knots());
  SkillTrajectory out = t;
  const int P = knots_per_interval;
  const std::vector<double> times(t.times_s.data(), t.times_s.data() + t.times_s.size());
  const int n = static_cast<int>(times.size());
  const int K = P * (n - 1) + 1;
  const int ndof = static_cast<int>(t.joint_angles_rad.rows());
  out.knots_per_interval = P;
  out.knot_joint_angles_rad.resize(ndof, K);
  out.knot_joint_rates.resize(ndof, K);
  out.knot_joint_accelerations.resize(ndof, K);
  out.knot_orientations.clear();
  out.knot_angular_velocities_B.resize(3, K);
  out.knot_angular_accelerations_B.resize(3, K);
  // The keyframe splines, read at the knots (value, first and second derivative).
  const QuaternionSpline<double> spline(times, t.keyframe_orientations);
  const CubicSplineKnots<double> knots(times);
  // Row j: joint j's keyframe values, then its spline moments.
  const Eigen::MatrixXd Y = t.joint_angles_rad;
  Eigen::MatrixXd M(ndof, n);
  for (int j = 0; j < ndof; ++j) {
    const Eigen::VectorXd y = Y.row(j).transpose();
    Eigen::VectorXd m(n);
    knots.SolveMoments(y.data(), m.data());
    M.row(j) = m.transpose();
  }
  for (int k = 0; k < K; ++k) {
    const int i = std::min(k / P, n - 2);
    const double tk =
        k == K - 1 ? times.back() : times[i] + (k - i * P) * (times[i + 1] - times[i]) / P;
    for (int j = 0; j < ndof; ++j) {
      const Eigen::VectorXd y = Y.row(j).transpose();
      const Eigen::VectorXd m = M.row(j).transpose();
      const SplineSample<double> s = knots.Eval(i, tk, y.data(), m.data());
      // Keyframe knots carry the keyframe value itself (the spline matches it to rounding).
      out.knot_joint_angles_rad(j, k) = k % P == 0 ? t.joint_angles_rad(j, k / P) : s.value;
      out.knot_joint_rates(j, k) = s.d1;
      out.knot_joint_accelerations(j, k) = s.d2;
    }
    const QuaternionSample<double> r = spline.Eval(tk);
    // Keyframe knots carry the keyframe orientation itself (the spline matches it to rounding).
    out.knot_orientations.push_back(k % P == 0 ? t.keyframe_orientations[static_cast<size_t>(k / P)]
                                               : r.q_WB.normalized());
    out.knot_angular_velocities_B.col(k) = r.w_WB_B;
    out.knot_angular_accelerations_B.col(k) = r.wdot_WB_B;
  }
  return out;
}

SkillDesign::SkillDesign(const Skill& skill)
    : skill_(skill), model_(MakeStandardHumanModel(MakeAthleteBody(skill.athlete))) {
  ACRO_DEMAND(model_.num_joint_dofs() == StandardJointDofCount());
  const int n = num_keyframes();
  joint_angles_.resize(model_.num_joint_dofs(), n);
  for (int i = 0; i < n; ++i) {
    const SkillKeyframe& k = skill_.keyframes[static_cast<size_t>(i)];
    orientations_.push_back(KeyframeOrientation(k));
    joint_angles_.col(i) = k.joint_angles_rad;
  }
  // The flight time T = 2 v_z / g used the model's g.
  ACRO_DEMAND(std::abs(model_.gravity_W().norm() - skill.gravity_mps2) < 1e-12);
}

Eigen::VectorXd SkillDesign::EvenTimes() const {
  return Eigen::VectorXd::LinSpaced(num_keyframes(), 0.0, flight_time_s());
}

Eigen::VectorXd SkillDesign::InitialTimes() const {
  const int n = num_keyframes();
  Eigen::VectorXd t(n);
  std::vector<int> known;
  for (int i = 0; i < n; ++i) {
    const auto& g = skill_.keyframes[static_cast<size_t>(i)].time_s;
    if (i == 0) {
      t[i] = 0.0;
    } else if (i == n - 1) {
      t[i] = flight_time_s();
    } else if (g) {
      t[i] = *g;
    } else {
      continue;
    }
    known.push_back(i);
  }
  // Unknown times spread evenly between the known ones.
  for (size_t k = 0; k + 1 < known.size(); ++k) {
    const int a = known[k], b = known[k + 1];
    for (int i = a + 1; i < b; ++i) t[i] = t[a] + (t[b] - t[a]) * (i - a) / double(b - a);
  }
  return t;
}

SkillTrajectory MakeKeyframeTrajectory(const SkillDesign& design, const Eigen::VectorXd& times_s) {
  ACRO_DEMAND(times_s.size() == design.num_keyframes());
  SkillTrajectory t;
  t.times_s = times_s;
  t.joint_angles_rad = design.keyframe_joint_angles_rad();
  t.keyframe_orientations = design.keyframe_orientations();
  return t;
}

Motion SampleSkillMotion(const SkillDesign& design,
                         const SkillTrajectory& trajectory,
                         double rate_hz) {
  ACRO_DEMAND(rate_hz > 0);
  const double T = design.flight_time_s();
  const int intervals = std::max(1, static_cast<int>(std::ceil(T * rate_hz - 1e-9)));
  const internal::MotionEvaluator evaluator(design, trajectory, Eigen::Vector3d(0, 0, 1));
  Motion m;
  m.coordinate_names = MakeCoordinateNames(design.model());
  m.rate_hz = intervals / T;
  m.time_s.resize(intervals + 1);
  m.q.resize(design.model().nq(), intervals + 1);
  for (int k = 0; k <= intervals; ++k) {
    m.time_s(k) = T * k / intervals;
    m.q.col(k) = evaluator.Eval(m.time_s(k)).q;
  }
  m.fit.assign(static_cast<size_t>(intervals + 1), FrameFit{});
  return m;
}

SkillMotionState CalcSkillMotion(const SkillDesign& design,
                                 const SkillTrajectory& trajectory,
                                 double t_s,
                                 const Eigen::Vector3d& com_start_W) {
  return internal::MotionEvaluator(design, trajectory, com_start_W).Eval(t_s);
}

SkillMotionProfile CalcSkillMotionProfile(const SkillDesign& design,
                                          const SkillTrajectory& trajectory,
                                          int intervals) {
  const internal::MotionEvaluator motion(design, trajectory, Eigen::Vector3d(0, 0, 1));
  const dynamics::Model<double>& m = design.model();
  dynamics::Workspace<double> ws(m);
  SkillMotionProfile p;
  p.t_s = Eigen::VectorXd::LinSpaced(intervals + 1, 0.0, design.flight_time_s());
  p.H_Scm_W.resize(3, intervals + 1);
  p.moment_per_weight_height.resize(3, intervals + 1);
  p.force_per_weight.resize(3, intervals + 1);
  const Eigen::VectorXd w = internal::SimpsonWeightsOverT(intervals);
  Eigen::VectorXd Hnorm(intervals + 1);
  for (int k = 0; k <= intervals; ++k) {
    const SkillMotionState s = motion.Eval(p.t_s[k]);
    dynamics::CalcInverseDynamics(m, ws, s.q, s.v, s.a);
    const dynamics::RootResidual<double> r = dynamics::CalcRootResidual(m, ws, design.height_m());
    p.moment_per_weight_height.col(k) = r.moment_per_weight_height;
    p.force_per_weight.col(k) = r.force_per_weight;
    p.objective += w[k] * r.moment_per_weight_height.squaredNorm();
    dynamics::CalcForwardKinematics(m, ws, s.q, s.v);
    p.H_Scm_W.col(k) = dynamics::CalcCentroidalMomentum(m, ws).rotational();
    Hnorm[k] = p.H_Scm_W.col(k).norm();
  }
  // Relative to the mean |H|, or to 1 kg·m²/s for a flight that hardly rotates (a straight jump's
  // |H| is near zero and its ratio meaningless).
  p.angular_momentum_variation =
      (Hnorm.maxCoeff() - Hnorm.minCoeff()) / std::max(Hnorm.mean(), 1.0);
  return p;
}

}  // namespace acro::analysis
