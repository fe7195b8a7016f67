#include "acro/analysis/inverse_kinematics.h"

#include <ceres/ceres.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include <Eigen/SVD>

#include "acro/analysis/standard_human.h"
#include "acro/base/demand.h"
#include "acro/dynamics/kinematics.h"

namespace acro::analysis {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// The shared kinematics of one configuration: marker positions and their Jacobians (3 × nv),
/// recomputed only when Ceres asks at a new q (it evaluates every marker block at the same q).
struct MarkerKinematics {
  MarkerKinematics(const dynamics::Model<double>& m, const std::vector<ModelMarker>& mk)
      : model(m),
        markers(mk),
        ws(m),
        q(Eigen::VectorXd::Constant(m.nq(), std::nan(""))),
        p_WM(3, static_cast<Eigen::Index>(mk.size())),
        J(mk.size(), Eigen::Matrix3Xd::Zero(3, m.nv())) {}

  /// Brings positions (and Jacobians if asked) up to date for parameters (p, quat, joints).
  void Update(const double* const* parameters, bool need_jacobians) {
    const int n = model.num_joint_dofs();
    const bool same = std::memcmp(q.data(), parameters[0], 3 * sizeof(double)) == 0 &&
                      std::memcmp(q.data() + 3, parameters[1], 4 * sizeof(double)) == 0 &&
                      std::memcmp(q.data() + 7, parameters[2], size_t(n) * sizeof(double)) == 0;
    if (!same) {
      std::memcpy(q.data(), parameters[0], 3 * sizeof(double));
      std::memcpy(q.data() + 3, parameters[1], 4 * sizeof(double));
      std::memcpy(q.data() + 7, parameters[2], size_t(n) * sizeof(double));
      // Ceres keeps the quaternion on the unit sphere; normalise against rounding drift.
      q.segment<4>(3).normalize();
      dynamics::CalcForwardKinematics(model, ws, q);
      for (size_t m = 0; m < markers.size(); ++m)
        p_WM.col(static_cast<Eigen::Index>(m)) =
            ws.X_WB[static_cast<size_t>(markers[m].segment)] * markers[m].p_BoM_B;
      have_jacobians = false;
    }
    if (need_jacobians && !have_jacobians) {
      for (size_t m = 0; m < markers.size(); ++m)
        dynamics::CalcPointJacobian(model, ws, markers[m].segment, markers[m].p_BoM_B, J[m]);
      // ∂w_WB_B/∂q_quat: w = 2 vec(q* ⊗ q̇) = G q̇ with G = 2 [−v | w I − [v]×] (docs/notation.md).
      const double w = q[3];
      const Eigen::Vector3d v(q[4], q[5], q[6]);
      G.col(0) = -2.0 * v;
      Eigen::Matrix3d skew;
      skew << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
      G.rightCols<3>() = 2.0 * (w * Eigen::Matrix3d::Identity() - skew);
      have_jacobians = true;
    }
  }

  const dynamics::Model<double>& model;
  const std::vector<ModelMarker>& markers;
  dynamics::Workspace<double> ws;
  Eigen::VectorXd q;
  Eigen::Matrix3Xd p_WM;
  std::vector<Eigen::Matrix3Xd> J;
  Eigen::Matrix<double, 3, 4> G;
  bool have_jacobians = false;
};

/// r = w (p_WM(q) − p̂): three residuals, parameter blocks (p_WoBo_W 3, quaternion 4, joints n).
class MarkerCost : public ceres::CostFunction {
 public:
  MarkerCost(MarkerKinematics* kin, int marker, const double* target, const bool* present)
      : kin_(kin), marker_(marker), target_(target), present_(present) {
    set_num_residuals(3);
    mutable_parameter_block_sizes()->assign({3, 4, kin->model.num_joint_dofs()});
  }

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const int n = kin_->model.num_joint_dofs();
    if (!*present_) {
      // A missing marker contributes nothing (the block stays so that the problem is reused).
      residuals[0] = residuals[1] = residuals[2] = 0.0;
      if (jacobians) {
        if (jacobians[0]) std::fill(jacobians[0], jacobians[0] + 9, 0.0);
        if (jacobians[1]) std::fill(jacobians[1], jacobians[1] + 12, 0.0);
        if (jacobians[2]) std::fill(jacobians[2], jacobians[2] + 3 * n, 0.0);
      }
      return true;
    }
    kin_->Update(parameters, jacobians != nullptr);
    const double w = kin_->markers[static_cast<size_t>(marker_)].weight;
    const Eigen::Vector3d p = kin_->p_WM.col(marker_);
    for (int k = 0; k < 3; ++k) residuals[k] = w * (p[k] - target_[k]);
    if (jacobians) {
      const Eigen::Matrix3Xd& J = kin_->J[static_cast<size_t>(marker_)];
      // Row-major blocks as Ceres expects.
      if (jacobians[0]) {
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J_p(jacobians[0]);
        J_p = w * J.leftCols<3>();
      }
      if (jacobians[1]) {
        Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> J_quat(jacobians[1]);
        J_quat = w * J.middleCols<3>(3) * kin_->G;
      }
      if (jacobians[2]) {
        Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J_joints(
            jacobians[2], 3, n);
        J_joints = w * J.rightCols(n);
      }
    }
    return true;
  }

 private:
  MarkerKinematics* kin_;
  int marker_;
  const double* target_;
  const bool* present_;
};

/// Soft joint limits: r_j = k (max(0, θ_j − hi_j) + min(0, θ_j − lo_j)).
class JointLimitCost : public ceres::CostFunction {
 public:
  JointLimitCost(const std::vector<JointLimit>& limits, double k) : limits_(limits), k_(k) {
    set_num_residuals(static_cast<int>(limits.size()));
    mutable_parameter_block_sizes()->assign({static_cast<int>(limits.size())});
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const size_t n = limits_.size();
    if (jacobians && jacobians[0]) std::fill(jacobians[0], jacobians[0] + n * n, 0.0);
    for (size_t j = 0; j < n; ++j) {
      const double t = parameters[0][j];
      double r = 0.0;
      if (t > limits_[j].upper_rad) r = t - limits_[j].upper_rad;
      if (t < limits_[j].lower_rad) r = t - limits_[j].lower_rad;
      residuals[j] = k_ * r;
      if (jacobians && jacobians[0] && r != 0.0) jacobians[0][j * n + j] = k_;
    }
    return true;
  }

 private:
  std::vector<JointLimit> limits_;
  double k_;
};

/// Prior towards the reference pose: r_j = w_j θ_j.
class JointPriorCost : public ceres::CostFunction {
 public:
  explicit JointPriorCost(const std::vector<double>& w) : w_(w) {
    set_num_residuals(static_cast<int>(w.size()));
    mutable_parameter_block_sizes()->assign({static_cast<int>(w.size())});
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const size_t n = w_.size();
    if (jacobians && jacobians[0]) std::fill(jacobians[0], jacobians[0] + n * n, 0.0);
    for (size_t j = 0; j < n; ++j) {
      residuals[j] = w_[j] * parameters[0][j];
      if (jacobians && jacobians[0]) jacobians[0][j * n + j] = w_[j];
    }
    return true;
  }

 private:
  std::vector<double> w_;
};

/// Huber's loss that can be switched off (ρ(s) = s), so that a cold start reaches the right
/// basin by plain least squares before outlying markers are down-weighted: started far from the
/// solution, a robust loss would treat a whole limb's markers as outliers and keep it wrong.
class SwitchableHuberLoss : public ceres::LossFunction {
 public:
  explicit SwitchableHuberLoss(double scale) : huber_(scale) {}
  void Evaluate(double s, double rho[3]) const override {
    if (enabled) {
      huber_.Evaluate(s, rho);
    } else {
      rho[0] = s;
      rho[1] = 1.0;
      rho[2] = 0.0;
    }
  }
  bool enabled = true;

 private:
  ceres::HuberLoss huber_;
};

}  // namespace

std::vector<JointLimit> StandardJointLimits(const dynamics::Model<double>& model) {
  // Per joint, per axis in sequence order, degrees (lower, upper); sides mirrored about x and z.
  struct Range {
    const char* joint;
    double lo[3];
    double hi[3];
  };
  // Signs (docs/athlete-model.md): limb flexion negative about y, knee flexion positive; about x a
  // positive angle moves a hanging limb's lower end to the athlete's left.
  const Range kRanges[] = {
      {"thorax", {-45, -50, -60}, {110, 50, 60}},        // flexion, lateral bending, rotation
      {"head", {-80, -50, -85}, {80, 50, 85}},           // flexion, lateral bending, rotation
      {"l_upper_arm", {-210, -95, -60}, {80, 95, 200}},  // flexion, axial rotation, abduction
      {"l_forearm", {-165, -110, 0}, {15, 110, 0}},      // flexion, pronation
      {"l_hand", {-90, -45, 0}, {90, 45, 0}},            // flexion, deviation
      {"l_thigh", {-165, -60, -45}, {45, 60, 110}},      // flexion, axial rotation, abduction
      {"l_shank", {-15, 0, 0}, {165, 0, 0}},             // flexion
      {"l_foot", {-45, -45, 0}, {85, 45, 0}},            // plantar flexion, inversion
  };
  std::vector<JointLimit> limits(static_cast<size_t>(model.num_joint_dofs()));
  for (int s = 1; s < model.num_segments(); ++s) {
    const dynamics::Segment<double>& seg = model.segment(s);
    std::string name = seg.name;
    const bool right = name.rfind("r_", 0) == 0;
    if (right) name = "l_" + name.substr(2);
    for (const Range& r : kRanges) {
      if (name != r.joint) continue;
      for (int k = 0; k < seg.num_axes; ++k) {
        double lo = r.lo[k] * kDeg, hi = r.hi[k] * kDeg;
        // Mirroring about the sagittal plane negates rotations about x and z.
        if (right && seg.axes[static_cast<size_t>(k)] != 1) {
          const double mirrored_lo = -hi;
          hi = -lo;
          lo = mirrored_lo;
        }
        limits[static_cast<size_t>(seg.q_start - 7 + k)] = {lo, hi};
      }
    }
  }
  return limits;
}

bool InverseKinematicsOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (max_iterations < 1 || cold_start_iterations < 1) return fail("iterations must be >= 1");
  for (double w : joint_prior_m_per_rad)
    if (!(w >= 0.0)) return fail("joint_prior_m_per_rad must be >= 0");
  if (!(robust_scale_m >= 0.0)) return fail("robust_scale_m must be >= 0");
  if (!(joint_limit_stiffness_m_per_rad >= 0.0))
    return fail("joint_limit_stiffness_m_per_rad must be >= 0");
  if (!(function_tolerance > 0 && gradient_tolerance > 0 && parameter_tolerance > 0))
    return fail("tolerances must be positive");
  return true;
}

struct InverseKinematics::Impl {
  Impl(const dynamics::Model<double>& model_in,
       std::vector<ModelMarker> mk,
       std::vector<JointLimit> lim,
       const InverseKinematicsOptions& o)
      : model(model_in),
        markers(std::move(mk)),
        limits(std::move(lim)),
        options(o),
        kin(model, markers),
        targets(3, static_cast<Eigen::Index>(markers.size())),
        present(new bool[markers.size()]),
        p(Eigen::Vector3d::Zero()),
        quat(1, 0, 0, 0),
        joints(Eigen::VectorXd::Zero(model.num_joint_dofs())) {
    ACRO_DEMAND(static_cast<int>(limits.size()) == model.num_joint_dofs());
    std::string why;
    ACRO_DEMAND(options.IsValid(&why));
    targets.setZero();
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(po);
    if (options.robust_scale_m > 0)
      loss = std::make_unique<SwitchableHuberLoss>(options.robust_scale_m);
    problem->AddParameterBlock(p.data(), 3);
    problem->AddParameterBlock(quat.data(), 4, new ceres::QuaternionManifold);
    problem->AddParameterBlock(joints.data(), static_cast<int>(joints.size()));
    for (size_t m = 0; m < markers.size(); ++m) {
      present[m] = false;
      problem->AddResidualBlock(new MarkerCost(&kin,
                                               static_cast<int>(m),
                                               targets.col(static_cast<Eigen::Index>(m)).data(),
                                               &present[m]),
                                loss.get(),
                                p.data(),
                                quat.data(),
                                joints.data());
    }
    if (options.joint_limit_stiffness_m_per_rad > 0)
      problem->AddResidualBlock(new JointLimitCost(limits, options.joint_limit_stiffness_m_per_rad),
                                nullptr,
                                joints.data());
    if (!options.joint_prior_m_per_rad.empty()) {
      ACRO_DEMAND(static_cast<int>(options.joint_prior_m_per_rad.size()) == model.num_joint_dofs());
      problem->AddResidualBlock(
          new JointPriorCost(options.joint_prior_m_per_rad), nullptr, joints.data());
    }
    solver_options.linear_solver_type =
        options.normal_cholesky ? ceres::DENSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
    solver_options.num_threads = 1;
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;
    solver_options.function_tolerance = options.function_tolerance;
    solver_options.gradient_tolerance = options.gradient_tolerance;
    solver_options.parameter_tolerance = options.parameter_tolerance;
  }

  const dynamics::Model<double>& model;
  std::vector<ModelMarker> markers;
  std::vector<JointLimit> limits;
  InverseKinematicsOptions options;
  MarkerKinematics kin;
  Eigen::Matrix3Xd targets;
  std::unique_ptr<bool[]> present;
  Eigen::Vector3d p;
  Eigen::Vector4d quat;  // w x y z, as q stores it and as ceres::QuaternionManifold expects
  Eigen::VectorXd joints;
  std::unique_ptr<SwitchableHuberLoss> loss;
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Options solver_options;
  ceres::Solver::Summary summary;
};

InverseKinematics::InverseKinematics(const dynamics::Model<double>& model,
                                     std::vector<ModelMarker> markers,
                                     std::vector<JointLimit> limits,
                                     const InverseKinematicsOptions& options)
    : impl_(std::make_unique<Impl>(model, std::move(markers), std::move(limits), options)) {}

InverseKinematics::~InverseKinematics() = default;

int InverseKinematics::num_markers() const {
  return static_cast<int>(impl_->markers.size());
}
const std::vector<ModelMarker>& InverseKinematics::markers() const {
  return impl_->markers;
}

void InverseKinematics::CalcMarkerPositions(const Eigen::VectorXd& q, Eigen::Matrix3Xd& p_WM) {
  dynamics::Workspace<double>& ws = impl_->kin.ws;
  dynamics::CalcForwardKinematics(impl_->model, ws, q);
  impl_->kin.q.setConstant(std::nan(""));  // the cache no longer matches the workspace
  p_WM.resize(3, num_markers());
  for (int m = 0; m < num_markers(); ++m) {
    const ModelMarker& mk = impl_->markers[static_cast<size_t>(m)];
    p_WM.col(m) = ws.X_WB[static_cast<size_t>(mk.segment)] * mk.p_BoM_B;
  }
}

IkFrameResult InverseKinematics::Evaluate(const Eigen::Matrix3Xd& observed,
                                          const Eigen::VectorXd& q,
                                          Eigen::VectorXd* distances_m) {
  Eigen::Matrix3Xd p_WM;
  CalcMarkerPositions(q, p_WM);
  IkFrameResult r;
  if (distances_m) distances_m->setConstant(num_markers(), std::nan(""));
  double sum = 0.0;
  for (int m = 0; m < num_markers(); ++m) {
    if (std::isnan(observed(0, m))) continue;
    const double d = (p_WM.col(m) - observed.col(m)).norm();
    if (distances_m) (*distances_m)[m] = d;
    sum += d * d;
    r.max_m = std::max(r.max_m, d);
    ++r.num_markers;
  }
  r.rms_m = r.num_markers > 0 ? std::sqrt(sum / r.num_markers) : std::nan("");
  return r;
}

bool InverseKinematics::InitializeRoot(const Eigen::Matrix3Xd& observed, Eigen::VectorXd& q) {
  // Model markers with the root at the identity and the joints of q.
  Eigen::VectorXd q0 = q;
  q0.head<3>().setZero();
  q0.segment<4>(3) << 1, 0, 0, 0;
  Eigen::Matrix3Xd p_model;
  CalcMarkerPositions(q0, p_model);
  // Markers that move with the trunk: on the pelvis or thorax, or at the origin of their children.
  std::vector<int> use;
  for (int m = 0; m < num_markers(); ++m) {
    if (std::isnan(observed(0, m))) continue;
    const ModelMarker& mk = impl_->markers[static_cast<size_t>(m)];
    int seg = mk.segment;
    if (mk.p_BoM_B.norm() < 1e-9 && seg > 0) seg = impl_->model.segment(seg).parent;
    if (seg <= 1) use.push_back(m);
  }
  if (use.size() < 3) {
    use.clear();
    for (int m = 0; m < num_markers(); ++m)
      if (!std::isnan(observed(0, m))) use.push_back(m);
  }
  if (use.size() < 3) return false;
  // Horn/Kabsch: R minimising Σ |R a_i + t − b_i|² from the cross-covariance's SVD.
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (int m : use) {
    ca += p_model.col(m);
    cb += observed.col(m);
  }
  ca /= double(use.size());
  cb /= double(use.size());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (int m : use) H += (p_model.col(m) - ca) * (observed.col(m) - cb).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) D(2, 2) = -1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  const Eigen::Quaterniond quat(R);
  q.head<3>() = cb - R * ca;
  q[3] = quat.w();
  q[4] = quat.x();
  q[5] = quat.y();
  q[6] = quat.z();
  return true;
}

IkFrameResult InverseKinematics::Solve(const Eigen::Matrix3Xd& observed,
                                       Eigen::VectorXd& q,
                                       bool cold) {
  Impl& s = *impl_;
  ACRO_DEMAND(observed.cols() == num_markers() && q.size() == s.model.nq());
  // Targets and presence.
  int present = 0;
  for (int m = 0; m < num_markers(); ++m) {
    s.present[static_cast<size_t>(m)] = !std::isnan(observed(0, m));
    if (s.present[static_cast<size_t>(m)]) {
      s.targets.col(m) = observed.col(m);
      ++present;
    }
  }
  IkFrameResult result;
  if (present < 3) {
    result = Evaluate(observed, q, nullptr);
    result.converged = false;
    return result;
  }
  if (cold) InitializeRoot(observed, q);
  s.p = q.head<3>();
  s.quat = q.segment<4>(3).normalized();
  s.joints = q.tail(s.model.num_joint_dofs());
  int iterations = 0;
  if (cold) {
    // Plain least squares: the root first with the joints held, then everything; the robust
    // fit below then starts in the right basin.
    if (s.loss) s.loss->enabled = false;
    s.problem->SetParameterBlockConstant(s.joints.data());
    s.solver_options.max_num_iterations = 50;
    ceres::Solve(s.solver_options, s.problem.get(), &s.summary);
    iterations += static_cast<int>(s.summary.iterations.size());
    s.problem->SetParameterBlockVariable(s.joints.data());
    s.solver_options.max_num_iterations = s.options.cold_start_iterations;
    ceres::Solve(s.solver_options, s.problem.get(), &s.summary);
    iterations += static_cast<int>(s.summary.iterations.size());
    if (s.loss) s.loss->enabled = true;
  }
  s.solver_options.max_num_iterations =
      cold ? s.options.cold_start_iterations : s.options.max_iterations;
  ceres::Solve(s.solver_options, s.problem.get(), &s.summary);
  iterations += static_cast<int>(s.summary.iterations.size());
  q.head<3>() = s.p;
  q.segment<4>(3) = s.quat.normalized();
  q.tail(s.model.num_joint_dofs()) = s.joints;
  result = Evaluate(observed, q, nullptr);
  result.iterations = iterations;
  result.converged = s.summary.termination_type == ceres::CONVERGENCE;
  result.final_cost = s.summary.final_cost;
  return result;
}

}  // namespace acro::analysis
