#pragma once

// What Model 2 (timing_optimization.cc) and Model 1 (trajectory_optimization.cc) share around
// their Ceres solves: progress lines from the iterations and the summary. Internal to analysis.

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <sstream>
#include <string>
#include <thread>

#include "acro/design/skill_optimization.h"

namespace acro::analysis::internal {

/// Hands "<stage> iteration k: J = …" to the options' progress function after every iteration,
/// and stops the solve when the options' `cancelled` says so.
class SkillProgressCallback : public ceres::IterationCallback {
 public:
  SkillProgressCallback(const SkillOptimizationOptions& options, std::string stage)
      : out_(options.progress), cancelled_(options.cancelled), stage_(std::move(stage)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (out_) {
      std::ostringstream line;
      line << stage_ << " iteration " << s.iteration << ": J = " << 2.0 * s.cost
           << (s.step_is_successful ? "" : " (step rejected)");
      out_(line.str());
    }
    return cancelled_ && cancelled_() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(const std::string&)>& out_;
  const std::function<bool()>& cancelled_;
  std::string stage_;
};

/// Levenberg–Marquardt with the options' tolerances and iteration limit, silent. At the bounds the
/// plain projected step: Ceres' default follows a step that leaves the feasible box by a line
/// search along its projection, at a Jacobian evaluation per trial step; the plain step reached the
/// same optimum on Model 2's example with half the Jacobians (13 against 26) and a lower one on
/// Model 1's (J 1.75e-5 against 2.47e-5, 52 Jacobians against 125).
inline ceres::Solver::Options MakeSkillSolverOptions(const SkillOptimizationOptions& options,
                                                     ceres::LinearSolverType linear_solver,
                                                     int num_threads) {
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = linear_solver;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = options.function_tolerance;
  so.gradient_tolerance = options.gradient_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.num_threads = num_threads;
  so.max_num_line_search_step_size_iterations = 0;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

/// Threads for the residual blocks: the options' num_threads, or the hardware's concurrency.
inline int SkillSolverThreads(const SkillOptimizationOptions& options) {
  return options.num_threads > 0
             ? options.num_threads
             : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// The stage's summary from Ceres' and the wall time since `start`.
inline SkillOptimizationSummary MakeStageSummary(const ceres::Solver::Summary& s,
                                                 std::chrono::steady_clock::time_point start) {
  SkillOptimizationSummary out;
  out.success = s.IsSolutionUsable();
  out.message = s.message;
  out.iterations = static_cast<int>(s.iterations.size()) - 1;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace acro::analysis::internal
