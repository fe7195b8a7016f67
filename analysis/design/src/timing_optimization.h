#pragma once

// Model (2): the keyframe times that minimise J, the motion between keyframes being the keyframe
// form (skill_design.h). One Ceres parameter block, the n − 1 gaps (ordering kept by positive
// gaps); the quadrature grid split into one residual block per thread. Internal to acro_design:
// OptimizeSkill (skill_optimization.h) calls it.

#include <Eigen/Core>

#include "acro/design/skill_design.h"
#include "acro/design/skill_optimization.h"

namespace acro::analysis::internal {

/// Model 2's x: the n − 1 gaps.
int NumModel2Parameters(const SkillDesign& design);

/// `base` with the keyframe times that the gaps x give.
SkillTrajectory Model2TrajectoryFromParameters(const SkillDesign& design,
                                               const SkillTrajectory& base,
                                               const Eigen::VectorXd& x);

/// J(x) on `intervals` (even) uniform intervals over [0, T], and ∂J/∂x when gradient != nullptr,
/// from the solver's own residuals.
double CalcModel2Objective(const SkillDesign& design,
                           const SkillTrajectory& base,
                           const Eigen::VectorXd& x,
                           int intervals,
                           Eigen::VectorXd* gradient);

/// One Ceres solve of Model 2 from `base` on `intervals` quadrature intervals; returns the
/// optimised gaps.
Eigen::VectorXd SolveModel2(const SkillDesign& design,
                            const SkillTrajectory& base,
                            int intervals,
                            const SkillOptimizationOptions& options,
                            SkillOptimizationSummary* summary);

}  // namespace acro::analysis::internal
