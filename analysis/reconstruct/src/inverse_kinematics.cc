#include "acro/reconstruct/inverse_kinematics.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include "acro/athlete/standard_human.h"
#include "acro/base/demand.h"
#include "acro/base/input_error.h"
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
    const bool same =
        std::memcmp(q.data(), parameters[0], 3 * sizeof(double)) == 0 &&
        std::memcmp(q.data() + 3, parameters[1], 4 * sizeof(double)) == 0 &&
        std::memcmp(q.data() + dynamics::kRootNq, parameters[2], size_t(n) * sizeof(double)) == 0;
    if (!same) {
      std::memcpy(q.data(), parameters[0], 3 * sizeof(double));
      std::memcpy(q.data() + 3, parameters[1], 4 * sizeof(double));
      std::memcpy(q.data() + dynamics::kRootNq, parameters[2], size_t(n) * sizeof(double));
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

/// All markers in one residual block (one block keeps Ceres's per-block overhead out of the
/// per-frame cost): r_m = w_m (p_WM(q) − p̂_m), three residuals per marker, zero for a missing one.
/// Huber's loss is applied per marker by transforming its residual so that |r̃|² = ρ(|r|²):
/// with x = |r| > δ, r̃ = (φ/x) r, φ = (2δx − δ²)^½, and the exact Jacobian
/// J̃ = (φ/x) J + (φ' − φ/x) r̂ r̂ᵀ J (φ' = δ/φ, r̂ = r/x); inside δ, r̃ = r. The transformed
/// problem has the robust cost as its sum of squares, so Gauss–Newton on it is a robust fit.
/// Parameter blocks: p_WoBo_W (3), quaternion (4), joints (n).
class AllMarkersCost : public ceres::CostFunction {
 public:
  AllMarkersCost(MarkerKinematics* kin,
                 const Eigen::Matrix3Xd* targets,
                 const bool* present,
                 const double* huber_scale,
                 const bool* robust)
      : kin_(kin), targets_(targets), present_(present), delta_(huber_scale), robust_(robust) {
    set_num_residuals(3 * static_cast<int>(kin->markers.size()));
    mutable_parameter_block_sizes()->assign({3, 4, kin->model.num_joint_dofs()});
  }

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const int n = kin_->model.num_joint_dofs();
    const int M = static_cast<int>(kin_->markers.size());
    const bool need = jacobians != nullptr;
    kin_->Update(parameters, need);
    using RowMajor3X = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>;
    for (int m = 0; m < M; ++m) {
      double* r = residuals + 3 * m;
      const bool here = present_[m];
      Eigen::Map<Eigen::Vector3d> res(r);
      const double w = kin_->markers[static_cast<size_t>(m)].weight;
      if (here) {
        res = w * (kin_->p_WM.col(m) - targets_->col(m));
      } else {
        res.setZero();
      }
      // Robust transform of this marker's residual.
      double scale = 1.0, extra = 0.0;  // J̃ = scale J + extra r̂ r̂ᵀ J
      Eigen::Vector3d rhat = Eigen::Vector3d::Zero();
      const double x = res.norm();
      if (here && *robust_ && *delta_ > 0 && x > *delta_) {
        const double d = *delta_;
        const double phi = std::sqrt(2.0 * d * x - d * d);
        scale = phi / x;
        extra = d / phi - scale;
        rhat = res / x;
        res *= scale;
      }
      if (!need) continue;
      const Eigen::Matrix3Xd& J = kin_->J[static_cast<size_t>(m)];
      // Row-major blocks, rows 3m … 3m + 2, as Ceres expects.
      auto fill = [&](double* out, int cols, const auto& block) {
        if (out == nullptr) return;
        Eigen::Map<RowMajor3X> dst(out + 3 * m * cols, 3, cols);
        if (!here) {
          dst.setZero();
          return;
        }
        dst = (w * scale) * block;
        if (extra != 0.0) dst += (w * extra) * rhat * (rhat.transpose() * block);
      };
      fill(jacobians[0], 3, J.leftCols<3>());
      fill(jacobians[1], 4, (J.middleCols<3>(3) * kin_->G).eval());
      fill(jacobians[2], n, J.rightCols(n));
    }
    return true;
  }

 private:
  MarkerKinematics* kin_;
  const Eigen::Matrix3Xd* targets_;
  const bool* present_;
  const double* delta_;
  const bool* robust_;
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

/// Prior towards the reference pose, r_j = w_j θ_j, or with `target` towards it,
/// r_j = w_j (θ_j − target_j) (the temporal prior: target = the warm start's angles, `active`
/// false in cold starts).
class JointPriorCost : public ceres::CostFunction {
 public:
  explicit JointPriorCost(const std::vector<double>& w,
                          const Eigen::VectorXd* target = nullptr,
                          const bool* active = nullptr)
      : w_(w), target_(target), active_(active) {
    set_num_residuals(static_cast<int>(w.size()));
    mutable_parameter_block_sizes()->assign({static_cast<int>(w.size())});
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const size_t n = w_.size();
    const bool on = active_ == nullptr || *active_;
    if (jacobians && jacobians[0]) std::fill(jacobians[0], jacobians[0] + n * n, 0.0);
    for (size_t j = 0; j < n; ++j) {
      const double w = on ? w_[j] : 0.0;
      residuals[j] = w * (parameters[0][j] - (target_ ? (*target_)[Eigen::Index(j)] : 0.0));
      if (jacobians && jacobians[0]) jacobians[0][j * n + j] = w;
    }
    return true;
  }

 private:
  std::vector<double> w_;
  const Eigen::VectorXd* target_;
  const bool* active_;
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
        limits[static_cast<size_t>(seg.q_start - dynamics::kRootNq + k)] = {lo, hi};
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
  if (!(temporal_prior_m_per_rad >= 0.0 && std::isfinite(temporal_prior_m_per_rad)))
    return fail("temporal_prior_m_per_rad must be finite and >= 0");
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
    DemandValidOptions(options, "inverse kinematics options");
    targets.setZero();
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(po);
    problem->AddParameterBlock(p.data(), 3);
    problem->AddParameterBlock(quat.data(), 4, new ceres::QuaternionManifold);
    problem->AddParameterBlock(joints.data(), static_cast<int>(joints.size()));
    for (size_t m = 0; m < markers.size(); ++m) present[m] = false;
    marker_cost =
        new AllMarkersCost(&kin, &targets, present.get(), &options.robust_scale_m, &robust);
    problem->AddResidualBlock(marker_cost, nullptr, p.data(), quat.data(), joints.data());
    if (options.joint_limit_stiffness_m_per_rad > 0)
      problem->AddResidualBlock(new JointLimitCost(limits, options.joint_limit_stiffness_m_per_rad),
                                nullptr,
                                joints.data());
    if (!options.joint_prior_m_per_rad.empty()) {
      ACRO_DEMAND(static_cast<int>(options.joint_prior_m_per_rad.size()) == model.num_joint_dofs());
      problem->AddResidualBlock(
          new JointPriorCost(options.joint_prior_m_per_rad), nullptr, joints.data());
    }
    if (options.temporal_prior_m_per_rad > 0)
      problem->AddResidualBlock(
          new JointPriorCost(std::vector<double>(joints.size(), options.temporal_prior_m_per_rad),
                             &joints_start,
                             &warm),
          nullptr,
          joints.data());
    for (const ModelMarker& marker : markers) {
      std::vector<int> cols = {0, 1, 2, 3, 4, 5};
      for (int j = marker.segment; j > 0; j = model.segment(j).parent)
        for (int k = 0; k < model.segment(j).num_axes; ++k)
          cols.push_back(model.segment(j).v_start + k);
      std::sort(cols.begin(), cols.end());
      columns.push_back(cols);
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
  bool robust = true;            // the Huber transform is on (off during a cold start's first fits)
  bool warm = false;             // a warm start: the temporal prior is on
  Eigen::VectorXd joints_start;  // the warm start's joint angles (the temporal prior's target)
  AllMarkersCost* marker_cost = nullptr;  // owned by the problem
  // Structured warm-start solver: per marker, the velocity columns its point depends on (the
  // root's six and its ancestors' joint axes), and scratch for the normal equations.
  std::vector<std::vector<int>> columns;
  Eigen::MatrixXd H, H_damped;
  Eigen::VectorXd g, x, x_new, step;
  Eigen::LDLT<Eigen::MatrixXd> ldlt;
  // SolveRays: the rays of the frame and their projectors I − d dᵀ.
  bool ray_mode = false;
  std::vector<MarkerRay> rays;
  std::vector<Eigen::Matrix3d> projectors;
  // SolveRays with a root prior: its weights and the warm start's root position.
  RootPrior root_prior;
  Eigen::Vector3d root_start = Eigen::Vector3d::Zero();

  /// ½ Σ r̃² at chart coordinates x (p, φ, θ) around q0; with `normal` also H = J̃ᵀJ̃, g = J̃ᵀr̃.
  double EvaluateChart(const Eigen::Quaterniond& q0, const Eigen::VectorXd& xc, bool normal);
  /// Levenberg–Marquardt on the chart (Nielsen's damping update); returns iterations.
  int SolveWarm(Eigen::VectorXd& q, bool* converged);
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
  dynamics::SetRootQuaternion<double>(quat, q);
  return true;
}

double InverseKinematics::Impl::EvaluateChart(const Eigen::Quaterniond& q0,
                                              const Eigen::VectorXd& xc,
                                              bool normal) {
  const int n = model.num_joint_dofs();
  const int nv = model.nv();
  // Configuration from the chart: root orientation q0 ⊗ exp(φ).
  const Eigen::Vector3d phi = xc.segment<3>(3);
  const Eigen::Quaterniond q_WB = q0 * dynamics::QuaternionExp<double>(phi);
  double quat_wxyz[4] = {q_WB.w(), q_WB.x(), q_WB.y(), q_WB.z()};
  const double* params[3] = {xc.data(), quat_wxyz, xc.data() + 6};
  kin.Update(params, normal);
  // ∂w_WB_B/∂φ = Jr(φ) (right Jacobian of SO(3)).
  Eigen::Matrix3d Jr = Eigen::Matrix3d::Identity();
  if (normal) {
    Eigen::Matrix3d K;
    K << 0, -phi.z(), phi.y(), phi.z(), 0, -phi.x(), -phi.y(), phi.x(), 0;
    const double th = phi.norm();
    if (th > 1e-8)
      Jr += -(1 - std::cos(th)) / (th * th) * K + (th - std::sin(th)) / (th * th * th) * K * K;
    else
      Jr -= 0.5 * K;
    H.setZero(nv, nv);
    g.setZero(nv);
  }
  double cost = 0.0;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 48> Jc;
  // One observation: a marker's residual r = w A (p_WM − b), A = I for a 3D target, the
  // projector I − d dᵀ off a ray's direction for a ray (nullptr: identity).
  const auto add = [&](size_t m, double w, const Eigen::Vector3d& at, const Eigen::Matrix3d* A) {
    Eigen::Vector3d r = w * (kin.p_WM.col(Eigen::Index(m)) - at);
    if (A != nullptr) r = *A * r;
    // Huber by the residual transform of AllMarkersCost.
    double scale = 1.0, extra = 0.0;
    Eigen::Vector3d rhat = Eigen::Vector3d::Zero();
    const double xr = r.norm();
    const double d = options.robust_scale_m;
    if (robust && d > 0 && xr > d) {
      const double phi_r = std::sqrt(2.0 * d * xr - d * d);
      scale = phi_r / xr;
      extra = d / phi_r - scale;
      rhat = r / xr;
      r *= scale;
    }
    cost += 0.5 * r.squaredNorm();
    if (!normal) return;
    // The marker's Jacobian on its columns, the root rotation through Jr, then transformed.
    const std::vector<int>& cols = columns[m];
    const Eigen::Matrix3Xd& J = kin.J[m];
    const int k = static_cast<int>(cols.size());
    Jc.resize(3, k);
    for (int c = 0; c < k; ++c) Jc.col(c) = w * J.col(cols[size_t(c)]);
    if (A != nullptr) Jc = (*A * Jc).eval();
    Jc.middleCols<3>(3) = (Jc.middleCols<3>(3) * Jr).eval();
    if (extra != 0.0) {
      const Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, 48> rtJ =
          rhat.transpose() * Jc;
      Jc = scale * Jc + extra * rhat * rtJ;
    } else if (scale != 1.0) {
      Jc *= scale;
    }
    // H += J̃ᵀJ̃, g += J̃ᵀr̃ on the marker's columns only.
    for (int a = 0; a < k; ++a) {
      const int ia = cols[size_t(a)];
      g[ia] += Jc.col(a).dot(r);
      for (int b = 0; b <= a; ++b) H(ia, cols[size_t(b)]) += Jc.col(a).dot(Jc.col(b));
    }
  };
  if (ray_mode) {
    for (size_t i = 0; i < rays.size(); ++i)
      add(size_t(rays[i].marker), rays[i].weight, rays[i].origin_W, &projectors[i]);
  } else {
    for (size_t m = 0; m < markers.size(); ++m)
      if (present[m]) add(m, markers[m].weight, targets.col(Eigen::Index(m)), nullptr);
  }
  // Soft joint limits and the prior (diagonal).
  const double kl = options.joint_limit_stiffness_m_per_rad;
  for (int j = 0; j < n; ++j) {
    const double t = xc[6 + j];
    double r = 0.0;
    if (t > limits[size_t(j)].upper_rad) r = t - limits[size_t(j)].upper_rad;
    if (t < limits[size_t(j)].lower_rad) r = t - limits[size_t(j)].lower_rad;
    cost += 0.5 * kl * kl * r * r;
    const double wp =
        options.joint_prior_m_per_rad.empty() ? 0.0 : options.joint_prior_m_per_rad[size_t(j)];
    cost += 0.5 * wp * wp * t * t;
    const double wt = options.temporal_prior_m_per_rad;  // SolveWarm only
    const double dt = t - joints_start[j];
    cost += 0.5 * wt * wt * dt * dt;
    if (normal) {
      H(6 + j, 6 + j) += wt * wt;
      g[6 + j] += wt * wt * dt;
      if (r != 0.0) {
        H(6 + j, 6 + j) += kl * kl;
        g[6 + j] += kl * kl * r;
      }
      H(6 + j, 6 + j) += wp * wp;
      g[6 + j] += wp * wp * t;
    }
  }
  // The root prior (ray mode only): towards the warm start's position and orientation (φ = 0).
  if (ray_mode && (root_prior.position > 0 || root_prior.rotation_m_per_rad > 0)) {
    const double wp = root_prior.position, wr = root_prior.rotation_m_per_rad;
    const Eigen::Vector3d dp = xc.head<3>() - root_start;
    cost += 0.5 * wp * wp * dp.squaredNorm() + 0.5 * wr * wr * phi.squaredNorm();
    if (normal)
      for (int i = 0; i < 3; ++i) {
        H(i, i) += wp * wp;
        g[i] += wp * wp * dp[i];
        H(3 + i, 3 + i) += wr * wr;
        g[3 + i] += wr * wr * phi[i];
      }
  }
  if (normal) H = H.selfadjointView<Eigen::Lower>();
  return cost;
}

int InverseKinematics::Impl::SolveWarm(Eigen::VectorXd& q, bool* converged) {
  const int n = model.num_joint_dofs();
  const int nv = model.nv();
  const Eigen::Quaterniond q0 = dynamics::GetRootQuaternion(q).normalized();
  x.resize(nv);
  x.head<3>() = q.head<3>();
  x.segment<3>(3).setZero();
  x.tail(n) = q.tail(n);
  // Levenberg–Marquardt with Marquardt's diagonal scaling and Nielsen's damping update
  // (Madsen, Nielsen & Tingleff 2004, Methods for Non-Linear Least Squares Problems, §3.2).
  double cost = EvaluateChart(q0, x, true);
  double mu = 1e-4, nu = 2.0;
  int it = 0;
  *converged = false;
  for (; it < options.max_iterations; ++it) {
    if (g.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) {
      *converged = true;
      break;
    }
    H_damped = H;
    H_damped.diagonal() += mu * H.diagonal().cwiseMax(1e-9);
    ldlt.compute(H_damped);
    step = -ldlt.solve(g);
    if (step.norm() < options.parameter_tolerance * (x.norm() + options.parameter_tolerance)) {
      *converged = true;
      break;
    }
    x_new = x + step;
    const double cost_new = EvaluateChart(q0, x_new, false);
    const double predicted = -(step.dot(g) + 0.5 * step.dot(H * step));
    const double rho = predicted > 0 ? (cost - cost_new) / predicted : -1.0;
    if (rho > 0) {
      const bool small = cost - cost_new < options.function_tolerance * cost;
      x = x_new;
      if (small) {
        // Converged: the normal equations at the new point are not needed.
        *converged = true;
        ++it;
        break;
      }
      cost = EvaluateChart(q0, x, true);
      mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      nu = 2.0;
    } else {
      mu *= nu;
      nu *= 2.0;
    }
  }
  const Eigen::Quaterniond q_WB =
      q0 * dynamics::QuaternionExp<double>(Eigen::Vector3d(x.segment<3>(3)));
  q.head<3>() = x.head<3>();
  q.segment<4>(3) << q_WB.w(), q_WB.x(), q_WB.y(), q_WB.z();
  q.segment<4>(3).normalize();
  q.tail(n) = x.tail(n);
  return it;
}

IkFrameResult InverseKinematics::SolveRays(const std::vector<MarkerRay>& rays,
                                           Eigen::VectorXd& q,
                                           const RootPrior* root_prior) {
  Impl& s = *impl_;
  ACRO_DEMAND(q.size() == s.model.nq());
  s.rays.clear();
  s.projectors.clear();
  for (const MarkerRay& ray : rays) {
    ACRO_DEMAND(ray.marker >= 0 && ray.marker < num_markers());
    if (!(ray.origin_W.allFinite() && ray.direction_W.allFinite() && std::isfinite(ray.weight) &&
          ray.weight > 0 && ray.direction_W.norm() > 0))
      continue;
    const Eigen::Vector3d d = ray.direction_W.normalized();
    s.rays.push_back(ray);
    s.projectors.push_back(Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  IkFrameResult result;
  if (s.rays.size() < 3) return result;
  s.joints_start = q.tail(s.model.num_joint_dofs());
  s.warm = true;
  s.ray_mode = true;
  s.root_prior = root_prior ? *root_prior : RootPrior{};
  s.root_start = q.head<3>();
  bool converged = false;
  result.iterations = s.SolveWarm(q, &converged);
  s.ray_mode = false;
  result.converged = converged;
  Eigen::Matrix3Xd p_WM;
  CalcMarkerPositions(q, p_WM);
  double sum = 0.0;
  for (size_t i = 0; i < s.rays.size(); ++i) {
    const double d = (s.projectors[i] * (p_WM.col(s.rays[i].marker) - s.rays[i].origin_W)).norm();
    sum += d * d;
    result.max_m = std::max(result.max_m, d);
  }
  result.num_markers = static_cast<int>(s.rays.size());
  result.rms_m = std::sqrt(sum / double(s.rays.size()));
  return result;
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
  s.joints_start = s.joints;
  s.warm = !cold;
  int iterations = 0;
  if (!cold && s.options.structured_warm_start) {
    bool converged = false;
    const int it = s.SolveWarm(q, &converged);
    result = Evaluate(observed, q, nullptr);
    result.iterations = it;
    result.converged = converged;
    return result;
  }
  if (cold) {
    // Plain least squares: the root first with the joints held, then everything; the robust
    // fit below then starts in the right basin.
    s.robust = false;
    s.problem->SetParameterBlockConstant(s.joints.data());
    s.solver_options.max_num_iterations = 50;
    ceres::Solve(s.solver_options, s.problem.get(), &s.summary);
    iterations += static_cast<int>(s.summary.iterations.size());
    s.problem->SetParameterBlockVariable(s.joints.data());
    s.solver_options.max_num_iterations = s.options.cold_start_iterations;
    ceres::Solve(s.solver_options, s.problem.get(), &s.summary);
    iterations += static_cast<int>(s.summary.iterations.size());
    s.robust = true;
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
