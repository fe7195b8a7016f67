// Explicit instantiation of the kinematics templates for double (kinematics.h declares them
// extern); other scalar types (ceres::Jet) are instantiated where they are used.
#include "acro/dynamics/kinematics.h"

namespace acro::dynamics {

template void CalcForwardKinematics<double>(const Model<double>&,
                                            Workspace<double>&,
                                            const Eigen::Ref<const VectorX<double>>&);
template void CalcForwardKinematics<double>(const Model<double>&,
                                            Workspace<double>&,
                                            const Eigen::Ref<const VectorX<double>>&,
                                            const Eigen::Ref<const VectorX<double>>&);
template Vector3<double> CalcCenterOfMassAcceleration<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
template SpatialMomentum<double> CalcCentroidalMomentum<double>(const Model<double>&,
                                                                const Workspace<double>&);

}  // namespace acro::dynamics
