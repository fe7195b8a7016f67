// Explicit instantiation of the inverse-dynamics templates for double (inverse_dynamics.h
// declares them extern); other scalar types (ceres::Jet) are instantiated where they are used.
#include "acro/dynamics/inverse_dynamics.h"

namespace acro::dynamics {

template const VectorX<double>& CalcInverseDynamics<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const std::vector<SpatialForce<double>>*);
template const VectorX<double>& CalcInverseDynamicsAtSameConfiguration<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
template SpatialForce<double> CalcRootWrenchWithJointChanged<double>(
    const Model<double>&,
    Workspace<double>&,
    int,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
template const VectorX<double>& CalcBiasForces<double>(const Model<double>&,
                                                       Workspace<double>&,
                                                       const Eigen::Ref<const VectorX<double>>&,
                                                       const Eigen::Ref<const VectorX<double>>&);
template const MatrixX<double>& CalcMassMatrix<double>(const Model<double>&,
                                                       Workspace<double>&,
                                                       const Eigen::Ref<const VectorX<double>>&);
template RootResidual<double> CalcRootResidual<double>(const Model<double>&,
                                                       Workspace<double>&,
                                                       const double&);
template void CalcFlightRootAcceleration<double>(const Model<double>&,
                                                 Workspace<double>&,
                                                 const Eigen::Ref<const VectorX<double>>&,
                                                 const Eigen::Ref<const VectorX<double>>&,
                                                 Eigen::Ref<VectorX<double>>,
                                                 const std::vector<SpatialForce<double>>*);

}  // namespace acro::dynamics
