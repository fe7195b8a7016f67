#pragma once

// What Model 2 (timing_optimization.cc) and Model 1 (trajectory_optimization.cc) share around
// their Ceres solves: progress lines from the iterations and the summary. Internal to analysis.

#include <ceres/ceres.h>

#include <chrono>
#include <functional>
#include <sstream>
#include <string>

#include "acro/analysis/timing_optimization.h"

namespace acro::analysis::internal {

/// Hands "<stage> iteration k: J = …" to the options' progress function after every iteration.
class SkillProgressCallback : public ceres::IterationCallback {
 public:
  SkillProgressCallback(const std::function<void(const std::string&)>& out, std::string stage)
      : out_(out), stage_(std::move(stage)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (out_) {
      std::ostringstream line;
      line << stage_ << " iteration " << s.iteration << ": J = " << 2.0 * s.cost
           << (s.step_is_successful ? "" : " (step rejected)");
      out_(line.str());
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(const std::string&)>& out_;
  std::string stage_;
};

/// The stage's summary from Ceres' and the wall time since `start`.
inline TimingOptimizationSummary MakeStageSummary(const ceres::Solver::Summary& s,
                                                  std::chrono::steady_clock::time_point start) {
  TimingOptimizationSummary out;
  out.success = s.IsSolutionUsable();
  out.message = s.message;
  out.iterations = static_cast<int>(s.iterations.size()) - 1;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace acro::analysis::internal
