#pragma once

// The body's orientation as coaches and the FIG count it: somersault, tilt and twist, and angle
// unwrapping so that several turns read as such. One definition for the metrics, the skill files,
// the reports and the sample generator.

#include <Eigen/Core>

namespace acro::analysis {

/// R = R_y(somersault) R_x(tilt) R_z(twist) (Yeadon 1990's somersault–tilt–twist sequence about
/// the lateral, the frontal and the long axis): somersault and twist in (−π, π], tilt in
/// [−π/2, π/2].
struct SomersaultTiltTwist {
  double somersault_rad = 0.0;
  double tilt_rad = 0.0;
  double twist_rad = 0.0;
};

/// The angles of a rotation matrix: row y of R is (cos t sin w, cos t cos w, −sin t) and its
/// column z is (cos t sin s, −sin t, cos t cos s).
SomersaultTiltTwist CalcSomersaultTiltTwist(const Eigen::Matrix3d& R);

/// `angle` plus the multiple of 2π that brings it nearest to `previous`.
double UnwrapAngle(double previous, double angle);

/// Unwraps a sampled angle in place: each sample nearest to the one before it.
void UnwrapAngles(Eigen::VectorXd* angles);

}  // namespace acro::analysis
