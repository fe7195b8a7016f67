#include "acro/capture/trial.h"

#include <cmath>

namespace acro::capture {
namespace {

// The label without a "Subject:" prefix (Vicon Nexus writes "Subject:Marker").
std::string_view WithoutSubject(std::string_view label) {
  const std::size_t colon = label.rfind(':');
  return colon == std::string_view::npos ? label : label.substr(colon + 1);
}

}  // namespace

int Trial::analog_samples_per_frame() const {
  if (analog.cols() == 0 || analog.rows() == 0) return 0;
  if (num_frames > 0) return static_cast<int>(analog.cols() / num_frames);
  if (point_rate_hz > 0) return static_cast<int>(std::lround(analog_rate_hz / point_rate_hz));
  return 0;
}

int Trial::FindPoint(const std::string& label) const {
  for (int i = 0; i < num_points(); ++i) {
    if (points[i].label == label) return i;
  }
  const std::string_view wanted = WithoutSubject(label);
  for (int i = 0; i < num_points(); ++i) {
    if (WithoutSubject(points[i].label) == wanted) return i;
  }
  return -1;
}

int Trial::FindAnalog(const std::string& label) const {
  for (int i = 0; i < num_analog_channels(); ++i) {
    if (analog_channels[i].label == label) return i;
  }
  return -1;
}

void RotateTrial(const Eigen::Matrix3d& R_new_old, Trial* trial) {
  trial->positions = R_new_old * trial->positions;  // NaN gaps stay NaN
  for (ForcePlate& plate : trial->force_plates) {
    plate.corners_W_m = R_new_old * plate.corners_W_m;
    for (Eigen::Matrix3Xd* m :
         {&plate.force_W_N, &plate.cop_W_m, &plate.free_moment_W_Nm, &plate.moment_at_origin_W_Nm})
      if (m->cols() > 0) *m = R_new_old * *m;
  }
}

}  // namespace acro::capture
