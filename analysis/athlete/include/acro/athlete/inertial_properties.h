#pragma once

// Mass, centre of mass and rotational inertia of a rigid part, and their combination.

#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

/// Mass properties of one rigid part expressed in a frame H (for the athlete model: the body frame,
/// x anterior, y to the athlete's left, z up; see docs/athlete-model.md).
struct InertialProperties {
  double mass_kg = 0.0;
  /// Centre of mass Cm, from H's origin, in H.
  Eigen::Vector3d p_HoCm_H = Eigen::Vector3d::Zero();
  /// Rotational inertia about the part's own centre of mass, H axes, kg·m².
  Eigen::Matrix3d I_Cm_H = Eigen::Matrix3d::Zero();
};

/// The parts as one rigid body: masses added, centre of mass averaged, inertias moved to the common
/// centre of mass by the parallel-axis theorem (I_C = I_Cm + m (|d|² 1 − d dᵀ), d = p_CCm).
InertialProperties CombineInertia(const std::vector<InertialProperties>& parts);

/// The rotational inertia of `part` about the point p_HoP_H (parallel-axis theorem).
Eigen::Matrix3d InertiaAboutPoint(const InertialProperties& part, const Eigen::Vector3d& p_HoP_H);

/// The same part seen from another frame G: p_GoCm_G = p_GoHo_G + R_GH p_HoCm_H,
/// I_Cm_G = R_GH I_Cm_H R_GHᵀ.
InertialProperties TransformInertia(const InertialProperties& part,
                                    const Eigen::Matrix3d& R_GH,
                                    const Eigen::Vector3d& p_GoHo_G);

}  // namespace acro::analysis
