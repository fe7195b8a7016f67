#include "acro/athlete/inertial_properties.h"

namespace acro::analysis {

Eigen::Matrix3d InertiaAboutPoint(const InertialProperties& part, const Eigen::Vector3d& p_HoP_H) {
  // Parallel-axis theorem: I_P = I_Cm + m (|d|² 1 − d dᵀ), d from P to Cm.
  const Eigen::Vector3d d = part.p_HoCm_H - p_HoP_H;
  return part.I_Cm_H +
         part.mass_kg * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

InertialProperties CombineInertia(const std::vector<InertialProperties>& parts) {
  InertialProperties total;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (const InertialProperties& p : parts) {
    total.mass_kg += p.mass_kg;
    first_moment += p.mass_kg * p.p_HoCm_H;
  }
  if (total.mass_kg <= 0.0) return total;
  total.p_HoCm_H = first_moment / total.mass_kg;
  for (const InertialProperties& p : parts) total.I_Cm_H += InertiaAboutPoint(p, total.p_HoCm_H);
  return total;
}

InertialProperties TransformInertia(const InertialProperties& part,
                                    const Eigen::Matrix3d& R_GH,
                                    const Eigen::Vector3d& p_GoHo_G) {
  InertialProperties out;
  out.mass_kg = part.mass_kg;
  out.p_HoCm_H = p_GoHo_G + R_GH * part.p_HoCm_H;
  out.I_Cm_H = R_GH * part.I_Cm_H * R_GH.transpose();
  return out;
}

}  // namespace acro::analysis
