#pragma once

// Scaling the standard human to an athlete's markers: one length factor per segment pair (left and
// right share it) and a correction of every marker's offset, fitted by least squares to a static
// trial (its mean frame) or to frames of a chosen window of the motion (video keypoints, which have
// no static trial), together with the pose of each frame used:
//   min Σ_frames Σ_m w_m² |p_WM(q_k, s, δ_m) − p̂_km|² + Σ_g (λ_s (s_g − 1))² + Σ_m (λ_δ |δ_m|)²,
// where segment g's factor s_g scales its children's joint positions, its centre of mass, its
// named points and its markers' default offsets (inertia by s², mass unchanged). Ceres with
// automatic differentiation.

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/dynamics/model.h"
#include "acro/reconstruct/inverse_kinematics.h"
#include "acro/reconstruct/markerset.h"

namespace acro::analysis {

struct ScalingOptions {
  /// Prior on each scale factor: a 100 % change costs like λ_s metres of marker error.
  double scale_prior_m = 0.05;
  /// Prior on each marker offset correction (dimensionless): a 1 cm correction costs λ_δ cm.
  double offset_prior = 0.5;
  /// Scale factors are kept within [min_scale, max_scale].
  double min_scale = 0.6;
  double max_scale = 1.6;
  int max_iterations = 100;
  bool IsValid(std::string* why) const;
};

struct ScalingResult {
  dynamics::Model<double> model;
  std::vector<ModelMarker> markers;
  /// Factor per segment group ("pelvis", "thorax", "head", "upper_arm", … "foot").
  std::map<std::string, double> scale;
  int frames_used = 0;
  /// The configuration of each frame used, fitted together with the factors (on `model`).
  std::vector<Eigen::VectorXd> poses;
  double rms_before_m = 0.0;  ///< marker RMS over the frames used, unscaled model (after IK)
  double rms_after_m = 0.0;   ///< after scaling
  bool converged = false;
  /// The largest marker offset correction |δ| and its marker.
  double largest_offset_m = 0.0;
  std::string largest_offset_marker;
  std::string BriefReport() const;
};

/// Fits scale factors and marker offsets to `frames` (each 3 × markers, NaN = missing). The
/// model's mass properties keep their masses. `initial_q` (one per frame, optional) starts the
/// poses; without it each frame is fitted by a cold-started inverse kinematics first. The joint
/// limits, their stiffness and the joint prior of `ik_options` enter the fit as in the inverse
/// kinematics, so that both minimise the same objective.
ScalingResult ScaleModel(const dynamics::Model<double>& model,
                         const std::vector<ModelMarker>& markers,
                         const std::vector<JointLimit>& limits,
                         const std::vector<Eigen::Matrix3Xd>& frames,
                         const ScalingOptions& options = {},
                         const std::vector<Eigen::VectorXd>* initial_q = nullptr,
                         const InverseKinematicsOptions& ik_options = {});

/// The model with segment group factors applied (missing groups: 1).
dynamics::Model<double> MakeScaledModel(const dynamics::Model<double>& model,
                                        const std::map<std::string, double>& scale);

/// "upper_arm" for "l_upper_arm": the group a segment's scale factor belongs to.
std::string ScaleGroupOf(const std::string& segment);

}  // namespace acro::analysis
