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
template Vector3<double> CalcPointPosition<double>(const Model<double>&,
                                                   const Workspace<double>&,
                                                   int);
template Vector3<double> CalcPointVelocity<double>(const Model<double>&,
                                                   const Workspace<double>&,
                                                   int);
template SpatialMotion<double> CalcSegmentSpatialVelocity<double>(const Workspace<double>&, int);
template void CalcPointJacobian<double>(const Model<double>&,
                                        const Workspace<double>&,
                                        int,
                                        const Vector3<double>&,
                                        Matrix3XRef<double>);
template void CalcPointJacobian<double>(const Model<double>&,
                                        const Workspace<double>&,
                                        int,
                                        Matrix3XRef<double>);
template void CalcSegmentJacobian<double>(const Model<double>&,
                                          const Workspace<double>&,
                                          int,
                                          Matrix6XRef<double>);
template void CalcCenterOfMassJacobian<double>(const Model<double>&,
                                               const Workspace<double>&,
                                               Matrix3XRef<double>);
template Vector3<double> CalcCenterOfMassPosition<double>(const Model<double>&,
                                                          const Workspace<double>&);
template Vector3<double> CalcCenterOfMassVelocity<double>(const Model<double>&,
                                                          const Workspace<double>&);
template Vector3<double> CalcCenterOfMassAcceleration<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
template SpatialMomentum<double> CalcCentroidalMomentum<double>(const Model<double>&,
                                                                const Workspace<double>&);

}  // namespace acro::dynamics
