#pragma once

// The athlete's motion as reconstruction produces it and every later step (inverse dynamics,
// physical check, metrics) consumes it: configurations q(t) of a dynamics model
// (docs/notation.md: q = [p_WoBo_W, quaternion w x y z, joint angles]) at the trial's frame times,
// with the marker fit quality of each frame.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/dynamics/model.h"

namespace acro::analysis {

/// Marker fit of one frame.
struct FrameFit {
  double rms_m = 0.0;  ///< RMS distance model marker ↔ measured marker over the markers present
  double max_m = 0.0;  ///< the largest of those distances
  int num_markers =
      0;               ///< markers present in the frame (0: no fit; q is then interpolated or held)
  int iterations = 0;  ///< solver iterations
  bool converged = false;
  bool valid = false;  ///< false when too few markers were present to fit the frame
};

struct Motion {
  /// nq names: pelvis_tx, pelvis_ty, pelvis_tz (m), pelvis_qw … pelvis_qz, then the joint angles
  /// (MakeCoordinateNames; docs/reconstruction.md).
  std::vector<std::string> coordinate_names;
  Eigen::VectorXd time_s;  ///< per frame, seconds from the trial's first frame
  Eigen::MatrixXd q;       ///< nq × frames, radians for angles, metres for the root position
  std::vector<FrameFit> fit;
  std::vector<std::string> marker_names;
  /// Per marker (rows) and frame (columns): |p_WM(q) − measured| (m); NaN where missing.
  Eigen::MatrixXd marker_error_m;
  double rate_hz = 0.0;

  int num_frames() const { return static_cast<int>(q.cols()); }
  int nq() const { return static_cast<int>(q.rows()); }
  Eigen::VectorXd Configuration(int frame) const { return q.col(frame); }
};

/// Coordinate names of a standard human model (the root and 32 anatomical angle names such as
/// r_hip_flexion, l_knee_flexion, lumbar_bending); other models get "<segment>_<axis>".
std::vector<std::string> MakeCoordinateNames(const dynamics::Model<double>& model);

/// Per-frame RMS marker errors of the valid frames, sorted ascending (for percentiles).
std::vector<double> SortedFrameRms(const Motion& motion);

/// The p-th percentile (0–100) of sorted values by linear interpolation (NaN when empty).
double Percentile(const std::vector<double>& sorted, double p);

}  // namespace acro::analysis
