#pragma once

// Per-frame inverse kinematics: the configuration q of the standard human (root position, root
// quaternion on its manifold, Euler joint angles) that minimises the weighted squared distances
// between model markers and measured ones,
//   min_q  Σ_m ρ(w_m² |p_WM(q) − p̂_m|²) + Σ_j k² (max(0, θ_j − hi_j)² + min(0, θ_j − lo_j)²),
// with ρ a robust loss (Huber) so that a mislabelled or flying marker does not drag the fit, and
// soft anatomical joint limits. Solved by Ceres (Levenberg–Marquardt, dense normal equations) with
// analytic Jacobians from the dynamics layer's point Jacobians; warm-started from the previous
// frame. One InverseKinematics object per thread (it holds a Ceres problem and a workspace).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/dynamics/model.h"
#include "acro/reconstruct/markerset.h"

namespace acro::analysis {

/// Soft limits of one joint angle (radians).
struct JointLimit {
  double lower_rad = -1e9;
  double upper_rad = 1e9;
};

/// Anatomical ranges of the standard human's 32 joint angles (kStandardJoints order, axis by
/// axis), wide enough for acrobatics (arms overhead, pike, tuck, straddle); docs/reconstruction.md.
std::vector<JointLimit> StandardJointLimits(const dynamics::Model<double>& model);

struct InverseKinematicsOptions {
  /// Iterations of a warm-started frame, and of a cold start (no previous frame).
  int max_iterations = 10;
  int cold_start_iterations = 200;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-7;
  /// Huber loss scale on a marker's weighted distance (m); 0 disables the robust loss.
  double robust_scale_m = 0.04;
  /// Residual per radian beyond a joint limit (m/rad): 0.2 makes 5° past a limit cost like a
  /// 1.7 cm marker error.
  double joint_limit_stiffness_m_per_rad = 0.2;
  /// Optional prior pulling joint angles towards zero (the reference pose): residual w_j θ_j
  /// (m/rad), one weight per joint angle, or empty. For angles the markers cannot see (video
  /// keypoints: pelvis tilt against lumbar flexion, forearm pronation, wrists, ankles), so that
  /// they rest at the reference pose instead of drifting along the null space.
  std::vector<double> joint_prior_m_per_rad;
  /// Warm starts only: residual w (θ_j − θ_j,start) per joint angle (m/rad), pulling each angle
  /// towards its value at the warm start (the previous frame). 0 disables it. For sparse keypoint
  /// sets, where an angle is seen in one pose and not in the next (a hip's rotation while its knee
  /// is straight, a shoulder's while its elbow is): there the angle keeps the previous frame's
  /// value instead of flipping along the null space, and Levenberg–Marquardt converges. 0.02 m/rad
  /// makes a 0.1 rad change between frames cost like a 2 mm marker error (docs/reconstruction.md).
  double temporal_prior_m_per_rad = 0.0;
  /// Warm-started frames by a Levenberg–Marquardt that assembles the normal equations marker by
  /// marker on the columns each marker depends on (the root's six and its chain's joint axes; a
  /// dense JᵀJ of all 3M rows × 38 columns is what dominates Ceres's time here), with the root
  /// orientation in a chart q0 ⊗ exp(φ) around the previous frame's. Same objective (robust
  /// transform, limits, prior) as the ceres::Problem, which cold starts always use and warm starts
  /// use when this is false.
  bool structured_warm_start = true;
  /// Dense normal equations (Cholesky) rather than dense QR (ceres::Problem path).
  bool normal_cholesky = true;
  bool IsValid(std::string* why) const;
};

/// Fit of one frame.
struct IkFrameResult {
  double rms_m = 0.0;  ///< root mean square marker distance over the markers present
  double max_m = 0.0;  ///< largest marker distance
  int num_markers = 0;
  int iterations = 0;
  bool converged = false;
  double final_cost = 0.0;
};

/// How firmly SolveRays holds the root at its warm start.
struct RootPrior {
  double position = 0.0;            ///< m of ray distance per m
  double rotation_m_per_rad = 0.0;  ///< m of ray distance per rad
};

/// A marker seen by a camera: the ray from the camera's centre through its detection. The fit's
/// residual is the marker's distance from the ray, w (I − d dᵀ)(p_WM − o) — the reprojection
/// error measured in metres at the marker's depth, so that the joint limits and priors (m/rad) keep
/// their meaning (docs/markerless.md, "The model fitted to the views").
struct MarkerRay {
  int marker = 0;
  Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitZ();  ///< unit length
  double weight = 1.0;
};

class InverseKinematics {
 public:
  InverseKinematics(const dynamics::Model<double>& model,
                    std::vector<ModelMarker> markers,
                    std::vector<JointLimit> limits,
                    const InverseKinematicsOptions& options = {});
  ~InverseKinematics();
  InverseKinematics(const InverseKinematics&) = delete;
  InverseKinematics& operator=(const InverseKinematics&) = delete;

  int num_markers() const;
  const std::vector<ModelMarker>& markers() const;

  /// Solves one frame: `observed` is 3 × num_markers in W (NaN columns = missing); q is the warm
  /// start on entry and the solution on exit. `cold` first places the root on the markers
  /// (InitializeRoot), then fits with the root alone and then with all coordinates, using
  /// cold_start_iterations.
  IkFrameResult Solve(const Eigen::Matrix3Xd& observed, Eigen::VectorXd& q, bool cold = false);

  /// Solves one frame against rays instead of 3D positions (several cameras' detections of the
  /// markers, or one camera's): a warm start from q (the structured Levenberg–Marquardt, with the
  /// same robust loss, limits and priors; the temporal prior pulls towards q's angles). rms_m and
  /// max_m are the rays' distances from their markers.
  /// With `root_prior`, the root is also pulled towards q's root: its position by
  /// root_prior->position (a displacement costs like that many times its length in ray distance),
  /// its orientation by root_prior->rotation_m_per_rad (a turn of 1 rad costs like that ray
  /// distance) — a root held by something other than the rays (flight_physics.h).
  IkFrameResult SolveRays(const std::vector<MarkerRay>& rays,
                          Eigen::VectorXd& q,
                          const RootPrior* root_prior = nullptr);

  /// Places the root (position and orientation) so that the markers of the pelvis and thorax
  /// (and markers at the origins of their child segments) match `observed` best with the joint
  /// angles of q (Kabsch/Horn least-squares rotation). False when fewer than three are present.
  bool InitializeRoot(const Eigen::Matrix3Xd& observed, Eigen::VectorXd& q);

  /// Model marker positions p_WM at q (3 × num_markers).
  void CalcMarkerPositions(const Eigen::VectorXd& q, Eigen::Matrix3Xd& p_WM);

  /// Distances |p_WM(q) − observed| per marker (NaN where missing) and the frame's RMS/max.
  IkFrameResult Evaluate(const Eigen::Matrix3Xd& observed,
                         const Eigen::VectorXd& q,
                         Eigen::VectorXd* distances_m);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acro::analysis
