// Explicit instantiation of the configuration templates for double (configuration.h declares
// them extern).
#include "acro/dynamics/configuration.h"

namespace acro::dynamics {

template VectorX<double> MakeNeutralConfiguration<double>(const Model<double>&);
template void CalcConfigurationDerivative<double>(const Model<double>&,
                                                  const VectorXcRef<double>&,
                                                  const VectorXcRef<double>&,
                                                  VectorXRef<double>);
template void CalcConfigurationDerivativeMatrix<double>(const Model<double>&,
                                                        const VectorXcRef<double>&,
                                                        MatrixXRef<double>);
template void CalcVelocityFromConfigurationDerivative<double>(const Model<double>&,
                                                              const VectorXcRef<double>&,
                                                              const VectorXcRef<double>&,
                                                              VectorXRef<double>);
template void IntegrateConfiguration<double>(const Model<double>&,
                                             const VectorXcRef<double>&,
                                             const VectorXcRef<double>&,
                                             const double&,
                                             VectorXRef<double>);

}  // namespace acro::dynamics
