#include "acro/athlete/orientation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace acro::analysis {

SomersaultTiltTwist CalcSomersaultTiltTwist(const Eigen::Matrix3d& R) {
  SomersaultTiltTwist out;
  out.somersault_rad = std::atan2(R(0, 2), R(2, 2));
  out.tilt_rad = std::asin(std::clamp(-R(1, 2), -1.0, 1.0));
  out.twist_rad = std::atan2(R(1, 0), R(1, 1));
  return out;
}

double UnwrapAngle(double previous, double angle) {
  return previous + std::remainder(angle - previous, 2.0 * std::numbers::pi);
}

void UnwrapAngles(Eigen::VectorXd* angles) {
  for (Eigen::Index i = 1; i < angles->size(); ++i)
    (*angles)[i] = UnwrapAngle((*angles)[i - 1], (*angles)[i]);
}

}  // namespace acro::analysis
