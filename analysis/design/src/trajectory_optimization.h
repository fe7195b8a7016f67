#pragma once

// Model (1) in its local form (docs/skill-design.md, "Model (1): local form"): one Ceres residual
// block per quadrature sample, depending only on the gaps and on the data of the two knots around
// it, with derivatives by the chain rule through the sample's state (one ceres::Jet pass through
// the inverse dynamics per sample). Internal to acro_design:
// OptimizeSkill (skill_optimization.h) calls it; it does not know Model 2.

#include <Eigen/Core>

#include "acro/design/skill_design.h"
#include "acro/design/skill_optimization.h"

namespace acro::analysis::internal {

/// Size of Model 1's x for a design with `knots_per_interval` knots per keyframe interval.
int NumModel1Parameters(const SkillDesign& design, int knots_per_interval);

/// The trajectory that Model 1's x describes about a base with knots.
SkillTrajectory Model1TrajectoryFromParameters(const SkillDesign& design,
                                               const SkillTrajectory& base,
                                               const Eigen::VectorXd& x);

/// J(x) (Simpson's rule, `samples_per_knot_interval` even intervals per knot interval) and ∂J/∂x
/// when gradient != nullptr, from the solver's own residual blocks.
double CalcModel1Objective(const SkillDesign& design,
                           const SkillTrajectory& base,
                           const Eigen::VectorXd& x,
                           int samples_per_knot_interval,
                           Eigen::VectorXd* gradient);

/// One Ceres solve of Model 1 from `base` (which has knots); returns the optimised x.
Eigen::VectorXd SolveModel1(const SkillDesign& design,
                            const SkillTrajectory& base,
                            const SkillOptimizationOptions& options,
                            SkillOptimizationSummary* summary);

}  // namespace acro::analysis::internal
