// Model (2): keyframe timing optimisation with Ceres. This translation unit instantiates the
// keyframe splines and the inverse dynamics for ceres::Jet.

#include "timing_optimization.h"

#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <sstream>

#include "acro/athlete/standard_human.h"
#include "acro/base/cubic_spline.h"
#include "acro/base/text_format.h"
#include "acro/design/quaternion_spline.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/kinematics.h"
#include "skill_motion.h"
#include "skill_solver.h"

namespace acro::analysis::internal {
namespace {

// Derivative chunk of the dynamic automatic differentiation: Model 2's 11 gaps in one pass.
constexpr int kStride = 12;
using Jet = ceres::Jet<double, kStride>;

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

// r_k = sqrt(w_k/T) · n_Scm(t_k)/(m g h) for the block's grid samples, then the gap-scale
// residual when the block carries it.
template <typename T>
void EvalResiduals(const ResidualData& d, ScalarKit<T>& kit, const T* const* params, T* residuals) {
  BuildSplines(*d.design, d.base, params[0], kit.splines);
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

}  // namespace

int NumModel2Parameters(const SkillDesign& design) {
  return NumGaps(design);
}

SkillTrajectory Model2TrajectoryFromParameters(const SkillDesign& design,
                                               const SkillTrajectory& base,
                                               const Eigen::VectorXd& x) {
  ACRO_DEMAND(x.size() == NumModel2Parameters(design));
  const int n = design.num_keyframes();
  SkillTrajectory t = base;
  const std::vector<double> times = TimesFromGaps(x.data(), n, design.flight_time_s());
  t.times_s = Eigen::Map<const Eigen::VectorXd>(times.data(), n);
  return t;
}

double CalcModel2Objective(const SkillDesign& design,
                           const SkillTrajectory& base,
                           const Eigen::VectorXd& x,
                           int intervals,
                           Eigen::VectorXd* gradient) {
  ACRO_DEMAND(x.size() == NumModel2Parameters(design));
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

Eigen::VectorXd SolveModel2(const SkillDesign& design,
                            const SkillTrajectory& base,
                            int intervals,
                            const SkillOptimizationOptions& options,
                            SkillOptimizationSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  // The gap-scale residual pins Σ g = T, a direction J does not see (J depends on the ratios).
  ResidualData data = MakeResidualData(design, base, intervals, 1e-2);
  Eigen::VectorXd x(NumModel2Parameters(design));
  for (int j = 0; j + 1 < design.num_keyframes(); ++j) x[j] = base.times_s[j + 1] - base.times_s[j];
  double* gaps = x.data();

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  // The grid in one block per thread (each block builds the splines once and owns its workspaces),
  // the gap-scale residual in the last; Ceres evaluates the blocks concurrently.
  const int blocks = std::clamp(SkillSolverThreads(options), 1, intervals + 1);
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

  ceres::Solver::Options so = MakeSkillSolverOptions(options, ceres::DENSE_QR, blocks);
  SkillProgressCallback callback(options, "model 2");
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);

  *summary = MakeStageSummary(s, start);
  return x;
}

}  // namespace acro::analysis::internal
