// Keyframe timing (Model 2) and trajectory (Model 1) optimisation with Ceres. This is the one
// translation unit that instantiates the splines and the inverse dynamics for ceres::Jet.

#include "acro/design/timing_optimization.h"

#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "acro/design/keyframe_spline.h"
#include "acro/design/quaternion_spline.h"
#include "acro/athlete/standard_human.h"
#include "acro/base/text_format.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/kinematics.h"
#include "skill_solver.h"
#include "trajectory_optimization.h"

namespace acro::analysis {
namespace {

// Derivative chunk of the dynamic automatic differentiation: Model 2's 11 gaps in one pass.
constexpr int kStride = 12;
using Jet = ceres::Jet<double, kStride>;

// Simpson weights on N intervals over [0, T] divided by T, so that Σ w_k f_k ≈ T⁻¹ ∫ f dt.
Eigen::VectorXd SimpsonWeightsOverT(int intervals) {
  ACRO_DEMAND(intervals >= 2 && intervals % 2 == 0);
  Eigen::VectorXd w(intervals + 1);
  for (int k = 0; k <= intervals; ++k)
    w[k] = (k == 0 || k == intervals) ? 1.0 : (k % 2 ? 4.0 : 2.0);
  return w / (3.0 * intervals);
}

// Model 2's one parameter block: the gaps (Model 1 lives in trajectory_optimization.cc).
int NumGaps(const SkillDesign& d) {
  return d.num_keyframes() - 1;
}

// Everything the residual evaluation needs besides the variables.
struct ResidualData {
  const SkillDesign* design = nullptr;
  SkillTrajectory base;
  int intervals = 80;
  Eigen::VectorXd sample_t;     // fixed quadrature grid
  Eigen::VectorXd sqrt_weight;  // sqrt of the Simpson weights over T
  double scale_weight = 0.0;    // weight of the gap-scale residual (0: none)
  // The grid samples this residual block evaluates: first_sample … last_sample (all by default;
  // Model 2's solve splits them between blocks so that Ceres evaluates them on several threads).
  int first_sample = 0;
  int last_sample = -1;  // −1: intervals
  int end_sample() const { return (last_sample < 0 ? intervals : last_sample) + 1; }
};

int NumResiduals(const ResidualData& d) {
  return 3 * (d.end_sample() - d.first_sample) + (d.scale_weight > 0.0 ? 1 : 0);
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

// Builds the keyframe splines from the gaps.
template <typename T>
void BuildSplines(const ResidualData& d, const T* const* params, SkillSplines<T>& s) {
  const SkillDesign& design = *d.design;
  const int n = design.num_keyframes();
  const int ndof = design.num_joint_dofs();
  s.n = n;
  s.ndof = ndof;
  const std::vector<T> t = TimesFromGaps(params[0], n, design.flight_time_s());
  s.joint_knots.Reset(t);
  s.joint_values.resize(static_cast<size_t>(ndof * n));
  s.joint_moments.resize(static_cast<size_t>(ndof * n));
  for (int j = 0; j < ndof; ++j) {
    T* y = s.joint_values.data() + j * n;
    for (int i = 0; i < n; ++i) y[i] = T(d.base.joint_angles_rad(j, i));
    s.joint_knots.SolveMoments(y, s.joint_moments.data() + j * n);
  }
  std::vector<Eigen::Quaternion<T>> knot_q;
  for (int i = 0; i < n; ++i)
    knot_q.push_back(d.base.keyframe_orientations[static_cast<size_t>(i)].template cast<T>());
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
    q[7 + j] = y.value;
    v[6 + j] = y.d1;
    a[6 + j] = y.d2;
  }
  const QuaternionSample<T> r = s.orientation.Eval(t);
  q.template head<3>().setZero();
  q[3] = r.q_WB.w();
  q[4] = r.q_WB.x();
  q[5] = r.q_WB.y();
  q[6] = r.q_WB.z();
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

// r_k = sqrt(w_k/T) · n_Scm(t_k)/(m g h) for the block's grid samples, then the gap-scale
// residual when the block carries it.
template <typename T>
void EvalResiduals(const ResidualData& d, ScalarKit<T>& kit, const T* const* params, T* residuals) {
  BuildSplines(d, params, kit.splines);
  const T height(d.design->height_m());
  const int end = d.end_sample();
  for (int k = d.first_sample; k < end; ++k) {
    SampleState(kit.splines, d.sample_t[k], kit.q, kit.v, kit.a);
    dynamics::CalcInverseDynamics(kit.model, kit.ws, kit.q, kit.v, kit.a);
    const dynamics::RootResidual<T> r = dynamics::CalcRootResidual(kit.model, kit.ws, height);
    T* rk = residuals + 3 * (k - d.first_sample);
    for (int c = 0; c < 3; ++c) rk[c] = T(d.sqrt_weight[k]) * r.moment_per_weight_height[c];
  }
  if (d.scale_weight > 0.0) {
    T sum(0.0);
    for (int j = 0; j + 1 < d.design->num_keyframes(); ++j) sum += params[0][j];
    residuals[3 * (end - d.first_sample)] =
        T(d.scale_weight) * (sum / T(d.design->flight_time_s()) - T(1.0));
  }
}

// The functor of ceres::DynamicAutoDiffCostFunction (double without Jacobians, Jet with).
class SkillCostFunctor {
 public:
  explicit SkillCostFunctor(ResidualData data)
      : data_(std::move(data)), kit_d_(data_.design->model()), kit_j_(data_.design->model()) {}

  template <typename T>
  bool operator()(T const* const* params, T* residuals) const {
    if constexpr (std::is_same_v<T, double>)
      EvalResiduals(data_, kit_d_, params, residuals);
    else
      EvalResiduals(data_, kit_j_, params, residuals);
    return true;
  }
  const ResidualData& data() const { return data_; }

 private:
  ResidualData data_;
  mutable ScalarKit<double> kit_d_;
  mutable ScalarKit<Jet> kit_j_;
};

using SkillCostFunction = ceres::DynamicAutoDiffCostFunction<SkillCostFunctor, kStride>;

ResidualData MakeResidualData(const SkillDesign& design,
                              const SkillTrajectory& base,
                              int intervals,
                              double scale_weight) {
  ResidualData d;
  d.design = &design;
  d.base = base;
  d.intervals = intervals;
  d.sample_t = Eigen::VectorXd::LinSpaced(intervals + 1, 0.0, design.flight_time_s());
  d.sqrt_weight = SimpsonWeightsOverT(intervals).cwiseSqrt();
  d.scale_weight = scale_weight;
  return d;
}

std::unique_ptr<SkillCostFunction> MakeCostFunction(const ResidualData& d) {
  auto cost = std::make_unique<SkillCostFunction>(new SkillCostFunctor(d));
  cost->AddParameterBlock(NumGaps(*d.design));
  cost->SetNumResiduals(NumResiduals(d));
  return cost;
}

// A double-precision evaluator of the designed motion: Model 2's keyframe splines (built once) or
// Model 1's local form.
class MotionEvaluator {
 public:
  MotionEvaluator(const SkillDesign& design,
                  const SkillTrajectory& trajectory,
                  const Eigen::Vector3d& com_start_W)
      : design_(design), trajectory_(trajectory), kit_(design.model()), com_start_W_(com_start_W) {
    if (trajectory.has_knots()) return;
    ResidualData d = MakeResidualData(design, trajectory, 2, 0.0);
    Eigen::VectorXd gaps(design.num_keyframes() - 1);
    for (int i = 0; i + 1 < design.num_keyframes(); ++i)
      gaps[i] = trajectory.times_s[i + 1] - trajectory.times_s[i];
    const double* p = gaps.data();
    BuildSplines(d, &p, kit_.splines);
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
    internal::EvalKnotTrajectory(
        trajectory_, t, q.tail(ndof), v.tail(ndof), a.tail(ndof), &q_WB, &w, &wdot);
    q.head<3>().setZero();
    q[3] = q_WB.w();
    q[4] = q_WB.x();
    q[5] = q_WB.y();
    q[6] = q_WB.z();
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

}  // namespace

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

namespace {

// One Ceres solve of Model 2 from `base`; returns the optimised gaps.
Eigen::VectorXd Solve(const SkillDesign& design,
                      const SkillTrajectory& base,
                      int intervals,
                      const TimingOptimizationOptions& options,
                      TimingOptimizationSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  // The gap-scale residual pins Σ g = T, a direction J does not see (J depends on the ratios).
  ResidualData data = MakeResidualData(design, base, intervals, 1e-2);
  Eigen::VectorXd x = InitialSkillParameters(design, base, 2);
  double* gaps = x.data();

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  // The grid in one block per thread (each block builds the splines once and owns its workspaces),
  // the gap-scale residual in the last; Ceres evaluates the blocks concurrently.
  const int blocks = std::clamp(internal::SkillSolverThreads(options), 1, intervals + 1);
  for (int b = 0; b < blocks; ++b) {
    ResidualData part = data;
    part.first_sample = (intervals + 1) * b / blocks;
    part.last_sample = (intervals + 1) * (b + 1) / blocks - 1;
    if (b + 1 < blocks) part.scale_weight = 0.0;
    problem.AddResidualBlock(MakeCostFunction(part).release(), nullptr, gaps);
  }
  // Ordering kept by positive gaps: g_j ≥ min_gap_fraction · T/(n − 1).
  const int n = design.num_keyframes();
  const double min_gap = options.min_gap_fraction * design.flight_time_s() / (n - 1);
  for (int j = 0; j + 1 < n; ++j) problem.SetParameterLowerBound(gaps, j, min_gap);

  ceres::Solver::Options so = internal::MakeSkillSolverOptions(options, ceres::DENSE_QR, blocks);
  internal::SkillProgressCallback callback(options.progress, "model 2");
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);

  *summary = internal::MakeStageSummary(s, start);
  return x;
}

double MaxJointDeviation(const SkillDesign& design, const SkillTrajectory& t) {
  return (t.joint_angles_rad - design.keyframe_joint_angles_rad()).cwiseAbs().maxCoeff();
}

double MaxOrientationDeviation(const SkillDesign& design, const SkillTrajectory& t) {
  double worst = 0.0;
  for (size_t i = 0; i < t.keyframe_orientations.size(); ++i)
    worst = std::max(worst,
                     t.keyframe_orientations[i].angularDistance(design.keyframe_orientations()[i]));
  return worst;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

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

SkillMotionState EvalSkillMotion(const SkillDesign& design,
                                 const SkillTrajectory& trajectory,
                                 double t_s,
                                 const Eigen::Vector3d& com_start_W) {
  return MotionEvaluator(design, trajectory, com_start_W).Eval(t_s);
}

SkillMotionProfile CalcSkillMotionProfile(const SkillDesign& design,
                                          const SkillTrajectory& trajectory,
                                          int intervals) {
  const MotionEvaluator motion(design, trajectory, Eigen::Vector3d(0, 0, 1));
  const dynamics::Model<double>& m = design.model();
  dynamics::Workspace<double> ws(m);
  SkillMotionProfile p;
  p.t_s = Eigen::VectorXd::LinSpaced(intervals + 1, 0.0, design.flight_time_s());
  p.H_Scm_W.resize(3, intervals + 1);
  p.moment_per_weight_height.resize(3, intervals + 1);
  p.force_per_weight.resize(3, intervals + 1);
  const Eigen::VectorXd w = SimpsonWeightsOverT(intervals);
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
  p.angular_momentum_variation = (Hnorm.maxCoeff() - Hnorm.minCoeff()) / Hnorm.mean();
  return p;
}

int NumSkillParameters(const SkillDesign& design, int model, int knots_per_interval) {
  if (model == 1) return internal::NumModel1Parameters(design, knots_per_interval);
  return NumGaps(design);
}

Eigen::VectorXd InitialSkillParameters(const SkillDesign& design,
                                       const SkillTrajectory& base,
                                       int model) {
  ACRO_DEMAND(model == 2 || base.has_knots());
  Eigen::VectorXd x =
      Eigen::VectorXd::Zero(NumSkillParameters(design, model, base.knots_per_interval));
  for (int j = 0; j + 1 < design.num_keyframes(); ++j) x[j] = base.times_s[j + 1] - base.times_s[j];
  return x;
}

SkillTrajectory SkillTrajectoryFromParameters(const SkillDesign& design,
                                              const SkillTrajectory& base,
                                              int model,
                                              const Eigen::VectorXd& x) {
  if (model == 1) return internal::Model1TrajectoryFromParameters(design, base, x);
  ACRO_DEMAND(x.size() == NumSkillParameters(design, model));
  const int n = design.num_keyframes();
  SkillTrajectory t = base;
  const std::vector<double> times = TimesFromGaps(x.data(), n, design.flight_time_s());
  t.times_s = Eigen::Map<const Eigen::VectorXd>(times.data(), n);
  return t;
}

double CalcSkillObjective(const SkillDesign& design,
                          const SkillTrajectory& base,
                          int model,
                          const Eigen::VectorXd& x,
                          int intervals,
                          Eigen::VectorXd* gradient) {
  if (model == 1) return internal::CalcModel1Objective(design, base, x, intervals, gradient);
  ACRO_DEMAND(x.size() == NumSkillParameters(design, model));
  const ResidualData data = MakeResidualData(design, base, intervals, 0.0);
  const std::unique_ptr<SkillCostFunction> cost = MakeCostFunction(data);
  const double* gaps = x.data();
  const int nr = NumResiduals(data);
  Eigen::VectorXd r(nr);
  if (gradient == nullptr) {
    cost->Evaluate(&gaps, r.data(), nullptr);
    return r.squaredNorm();
  }
  // Row-major Jacobian; ∇J = 2 Jᵀ r.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jac(nr, x.size());
  double* jac_ptr = jac.data();
  cost->Evaluate(&gaps, r.data(), &jac_ptr);
  *gradient = 2.0 * jac.transpose() * r;
  return r.squaredNorm();
}

bool TimingOptimizationOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why != nullptr) *why = m;
    return false;
  };
  if (model != 1 && model != 2) return fail("model must be 1 or 2");
  if (quadrature_intervals < 2 || quadrature_intervals % 2 != 0)
    return fail("quadrature_intervals must be even and at least 2");
  if (!(min_gap_fraction > 0.0 && min_gap_fraction < 1.0))
    return fail("min_gap_fraction must lie in (0, 1)");
  if (max_iterations < 0) return fail("max_iterations must be non-negative");
  if (!(model1_function_tolerance > 0.0 && model1_function_tolerance < 1.0))
    return fail("model1_function_tolerance must lie in (0, 1)");
  if (model1_samples_per_knot_interval < 2 || model1_samples_per_knot_interval % 2 != 0)
    return fail("model1_samples_per_knot_interval must be even and at least 2");
  if (model1_knots_per_interval < 1) return fail("model1_knots_per_interval must be positive");
  if (num_threads < 0) return fail("num_threads must be non-negative");
  return true;
}

std::string TimingOptimizationSummary::BriefReport() const {
  std::ostringstream s;
  s << (success ? "converged" : "not converged") << " after " << iterations << " iterations, cost "
    << initial_cost << " -> " << final_cost << ", " << time_s << " s: " << message;
  return s.str();
}

TimingOptimizationResult OptimizeSkillTiming(const SkillDesign& design,
                                             const TimingOptimizationOptions& options) {
  std::string why;
  ACRO_DEMAND(options.IsValid(&why));
  TimingOptimizationResult result;
  result.model = options.model;
  result.times_initial_s = design.InitialTimes();
  result.initial = MakeKeyframeTrajectory(design, result.times_initial_s);
  const int N = options.quadrature_intervals;
  // Model 1's grid: model1_samples_per_knot_interval intervals in each of its knot intervals.
  const int n = design.num_keyframes();
  const int N1 =
      options.model1_samples_per_knot_interval * options.model1_knots_per_interval * (n - 1);
  // J and the momentum variation are reported on a check grid 8 times finer than the
  // optimisation's (Simpson's rule as well).
  const int check = 8 * std::max(N, options.model == 1 ? N1 : N);
  const SkillMotionProfile p0 = CalcSkillMotionProfile(design, result.initial, check);
  result.objective_initial = p0.objective;
  result.angular_momentum_variation_initial = p0.angular_momentum_variation;

  // Model 2: times only.
  TimingOptimizationSummary s2;
  const Eigen::VectorXd x2 = Solve(design, result.initial, N, options, &s2);
  result.stages.push_back(s2);
  result.optimized = SkillTrajectoryFromParameters(design, result.initial, 2, x2);

  // Model 1: times and trajectory coefficients, from the Model 2 optimum (or the initial times).
  if (options.model == 1) {
    const SkillTrajectory base1 =
        MakeKnotTrajectory(options.model1_from_model2 ? result.optimized : result.initial,
                           options.model1_knots_per_interval);
    TimingOptimizationSummary s1;
    const Eigen::VectorXd x1 = internal::SolveModel1(design, base1, options, &s1);
    result.stages.push_back(s1);
    result.optimized = SkillTrajectoryFromParameters(design, base1, 1, x1);
  }
  result.summary = result.stages.back();
  const SkillMotionProfile p = CalcSkillMotionProfile(design, result.optimized, check);
  result.objective = p.objective;
  result.angular_momentum_variation = p.angular_momentum_variation;
  result.max_joint_deviation_rad = MaxJointDeviation(design, result.optimized);
  result.max_orientation_deviation_rad = MaxOrientationDeviation(design, result.optimized);
  return result;
}

SkillSimulationResult SimulateSkill(const SkillDesign& design,
                                    const SkillTrajectory& trajectory,
                                    double step_s,
                                    bool fit_momentum) {
  const dynamics::Model<double>& m = design.model();
  const MotionEvaluator motion(design, trajectory, Eigen::Vector3d(0, 0, 1));
  SkillSimulationResult out;
  // The designed motion's angular momentum about the COM; its mean over the flight is the
  // take-off momentum to start from.
  const SkillMotionProfile profile = CalcSkillMotionProfile(design, trajectory, 200);
  out.H_mean_W = profile.H_Scm_W.rowwise().mean();
  const SkillMotionState s0 = motion.Eval(0.0);
  dynamics::Workspace<double> ws(m);
  dynamics::FlightSimulationOptions fo;
  fo.duration_s = design.flight_time_s();
  fo.step_s = step_s;
  fo.output_interval_s = 0.01;
  const dynamics::JointTrajectory<double> joints = [&](const double& t,
                                                       dynamics::VectorXRef<double> qj,
                                                       dynamics::VectorXRef<double> vj,
                                                       dynamics::VectorXRef<double> aj) {
    motion.Joints(t, qj, vj, aj);
  };
  auto simulate = [&](const Eigen::Vector3d& H) {
    const dynamics::Vector6<double> v_root0 = dynamics::CalcRootVelocityFromMomentum(
        m, ws, s0.q, s0.v, Eigen::Vector3d(design.skill().takeoff_com_velocity_mps), H);
    return dynamics::SimulateFlight(
        m, fo, Eigen::Matrix<double, 7, 1>(s0.q.head<7>()), v_root0, joints);
  };
  out.H_Scm_W = out.H_mean_W;
  out.flight = simulate(out.H_Scm_W);
  // The designed orientation at the simulation's output times.
  std::vector<Eigen::Quaterniond> designed;
  for (double t : out.flight.t) {
    const SkillMotionState s = motion.Eval(t);
    designed.emplace_back(s.q[3], s.q[4], s.q[5], s.q[6]);
  }
  auto misfit = [&](const dynamics::FlightSimulationResult<double>& f, double* r) {
    for (size_t k = 0; k < designed.size(); ++k) {
      const Eigen::VectorXd& q = f.q[std::min(k, f.q.size() - 1)];
      const Eigen::Quaterniond sim(q[3], q[4], q[5], q[6]);
      const Eigen::AngleAxisd e(designed[k].conjugate() * sim.normalized());
      const Eigen::Vector3d v = e.axis() * e.angle();
      for (int c = 0; c < 3; ++c) r[3 * k + c] = v[c];
    }
  };
  // The take-off momentum that the design needs: the H that makes the simulated orientation follow
  // the designed one best over the whole flight (least squares over the 10 ms samples; Ceres with
  // central differences, each evaluation one flight simulation), from the mean.
  if (fit_momentum) {
    struct Misfit {
      std::function<void(const double*, double*)> eval;
      bool operator()(const double* H, double* r) const {
        eval(H, r);
        return true;
      }
    };
    const int residuals = 3 * static_cast<int>(designed.size());
    auto* cost = new ceres::NumericDiffCostFunction<Misfit, ceres::CENTRAL, ceres::DYNAMIC, 3>(
        new Misfit{[&](const double* H, double* r) {
          misfit(simulate(Eigen::Vector3d(H[0], H[1], H[2])), r);
        }},
        ceres::TAKE_OWNERSHIP,
        residuals);
    double H[3] = {out.H_mean_W[0], out.H_mean_W[1], out.H_mean_W[2]};
    ceres::Problem problem;
    problem.AddResidualBlock(cost, nullptr, H);
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 20;
    so.function_tolerance = 1e-8;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    out.H_Scm_W = Eigen::Vector3d(H[0], H[1], H[2]);
    out.flight = simulate(out.H_Scm_W);
  }
  std::vector<double> r(3 * designed.size());
  misfit(out.flight, r.data());
  double sum = 0;
  for (size_t k = 0; k < designed.size(); ++k)
    sum += r[3 * k] * r[3 * k] + r[3 * k + 1] * r[3 * k + 1] + r[3 * k + 2] * r[3 * k + 2];
  out.rms_orientation_error_rad = std::sqrt(sum / static_cast<double>(designed.size()));
  const Eigen::VectorXd& qf = out.flight.q.back();
  out.final_orientation = Eigen::Quaterniond(qf[3], qf[4], qf[5], qf[6]).normalized();
  out.intended_final_orientation = design.keyframe_orientations().back();
  out.final_orientation_error_rad =
      out.final_orientation.angularDistance(out.intended_final_orientation);
  // Somersault angle of the root's long axis z_B in W's x–z plane, unwrapped.
  auto turns = [](const std::vector<Eigen::Quaterniond>& qs) {
    double total = 0.0, prev = 0.0;
    for (size_t i = 0; i < qs.size(); ++i) {
      const Eigen::Vector3d z = qs[i] * Eigen::Vector3d::UnitZ();
      const double a = std::atan2(z.x(), z.z());
      if (i > 0) total += std::remainder(a - prev, 2.0 * std::numbers::pi);
      prev = a;
    }
    return total / (2.0 * std::numbers::pi);
  };
  // Twist: the angle about the pelvis' long axis in R_y(somersault) R_x(tilt) R_z(twist), from row
  // y of R = (cos t sin w, cos t cos w, −sin t), unwrapped.
  auto twist_turns = [](const std::vector<Eigen::Quaterniond>& qs) {
    double total = 0.0, prev = 0.0;
    for (size_t i = 0; i < qs.size(); ++i) {
      const Eigen::Matrix3d R = qs[i].normalized().toRotationMatrix();
      const double w = std::atan2(R(1, 0), R(1, 1));
      if (i > 0) total += std::remainder(w - prev, 2.0 * std::numbers::pi);
      prev = w;
    }
    return total / (2.0 * std::numbers::pi);
  };
  std::vector<Eigen::Quaterniond> sim;
  for (const Eigen::VectorXd& q : out.flight.q) sim.emplace_back(q[3], q[4], q[5], q[6]);
  out.somersault_turns = turns(sim);
  out.intended_somersault_turns = turns(designed);
  out.twist_turns = twist_turns(sim);
  out.intended_twist_turns = twist_turns(designed);
  out.warnings = SkillSimulationWarnings(out);
  return out;
}

std::vector<std::string> SkillSimulationWarnings(const SkillSimulationResult& sim) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  constexpr double kLimit = 15.0 * kDeg;
  std::vector<std::string> w;
  auto deg = [](double rad) { return FormatFixed(rad / kDeg, 1) + "°"; };
  auto turns = [](double t) { return FormatFixed(t, 2); };
  if (sim.flight.summary.status != dynamics::FlightSimulationStatus::kSuccess)
    w.push_back("the flight simulation did not finish: " + sim.flight.summary.BriefReport());
  if (sim.final_orientation_error_rad > kLimit || sim.rms_orientation_error_rad > kLimit)
    w.push_back("the simulated flight lands " + deg(sim.final_orientation_error_rad) +
                " from the last keyframe and follows the design within " +
                deg(sim.rms_orientation_error_rad) +
                " RMS: the keyframes ask for a rotation this body does not make in the air");
  const double somersault_error = sim.somersault_turns - sim.intended_somersault_turns;
  if (std::abs(somersault_error) * 2.0 * std::numbers::pi > kLimit)
    w.push_back("the simulation somersaults " + turns(sim.somersault_turns) +
                " turns, the design " + turns(sim.intended_somersault_turns) +
                ": more or less time in a compact shape (tuck, pike) changes the somersault rate");
  const double designed = sim.intended_twist_turns, simulated = sim.twist_turns;
  if (std::abs(designed) >= 0.25 && simulated * designed < 0.0)
    w.push_back("the design twists " + turns(designed) + " turns but the simulation " +
                turns(simulated) +
                ": in the air the twist's direction follows the tilt and the arm action; if "
                "Model 1 cannot reconcile them, reverse the twist or the tilt");
  else if (std::abs(simulated - designed) > 0.25)
    w.push_back("the simulation twists " + turns(simulated) + " turns, the design " +
                turns(designed) +
                ": the tilt during the twist (or how tightly the arms wrap) is too small or too "
                "large for this twist in this time");
  return w;
}

}  // namespace acro::analysis
