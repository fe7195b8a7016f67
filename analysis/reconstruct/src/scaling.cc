#include "acro/reconstruct/scaling.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/model_builder.h"

namespace acro::analysis {

namespace {

/// r = w (p_WM − p̂) for one marker in one frame, with the chain's joint positions scaled:
///   p_WBo(child) = p_WBo(parent) + R_WP (s_parent p_PoJo_P), R_WB = R_WP R_PJ R_a1(θ1)…,
///   p_WM = p_WBo + R_WB (s_B p_BoM_B + δ).
/// Parameter blocks: p (3), quaternion (4), joints (n), scales (G), δ (3).
struct ScaledMarkerResidual {
  const dynamics::Model<double>* model;
  std::vector<int> chain;     // root … segment
  std::vector<int> group_of;  // per segment
  Eigen::Vector3d p_BoM_B;
  Eigen::Vector3d observed;
  double weight;

  template <typename T>
  bool operator()(T const* const* x, T* residual) const {
    using V3 = Eigen::Matrix<T, 3, 1>;
    using M3 = Eigen::Matrix<T, 3, 3>;
    const T* p = x[0];
    const T* quat = x[1];
    const T* joints = x[2];
    const T* scales = x[3];
    const T* delta = x[4];
    M3 R = dynamics::QuaternionToRotation<T>(quat[0], quat[1], quat[2], quat[3]);
    R /= (quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    V3 pos(p[0], p[1], p[2]);
    for (size_t c = 1; c < chain.size(); ++c) {
      const dynamics::Segment<double>& seg = model->segment(chain[c]);
      const T s_parent = scales[group_of[size_t(seg.parent)]];
      pos += R * (seg.X_PJ.translation().template cast<T>() * s_parent);
      R = R * seg.X_PJ.rotation().template cast<T>();
      for (int k = 0; k < seg.num_axes; ++k) {
        const T th = joints[seg.q_start - dynamics::kRootNq + k];
        const T c0 = cos(th), s0 = sin(th);
        M3 E = M3::Identity();
        const int a = seg.axes[size_t(k)], i = (a + 1) % 3, j = (a + 2) % 3;
        E(i, i) = c0;
        E(i, j) = -s0;
        E(j, i) = s0;
        E(j, j) = c0;
        R = R * E;
      }
    }
    const T s_own = scales[group_of[size_t(chain.back())]];
    const V3 local = p_BoM_B.template cast<T>() * s_own + V3(delta[0], delta[1], delta[2]);
    const V3 m = pos + R * local;
    for (int k = 0; k < 3; ++k) residual[k] = T(weight) * (m[k] - T(observed[k]));
    return true;
  }
};

struct PriorResidual {
  int size;
  double weight;
  double center;
  template <typename T>
  bool operator()(T const* const* x, T* r) const {
    for (int k = 0; k < size; ++k) r[k] = T(weight) * (x[0][k] - T(center));
    return true;
  }
};

/// The inverse kinematics' soft joint limits, so that scaling fits the same objective.
struct LimitResidual {
  std::vector<JointLimit> limits;
  double k;
  std::vector<double> prior;  // empty or one weight per joint angle
  template <typename T>
  bool operator()(T const* const* x, T* r) const {
    const size_t n = limits.size();
    for (size_t j = 0; j < n; ++j) {
      const T t = x[0][j];
      r[j] = T(0.0);
      if (t > T(limits[j].upper_rad)) r[j] = T(k) * (t - T(limits[j].upper_rad));
      if (t < T(limits[j].lower_rad)) r[j] = T(k) * (t - T(limits[j].lower_rad));
      if (!prior.empty()) r[n + j] = T(prior[j]) * t;
    }
    return true;
  }
};

}  // namespace

std::string ScaleGroupOf(const std::string& segment) {
  if (segment.rfind("l_", 0) == 0 || segment.rfind("r_", 0) == 0) return segment.substr(2);
  return segment;
}

bool ScalingOptions::IsValid(std::string* why) const {
  if (!(scale_prior_m > 0 && offset_prior >= 0 && min_scale > 0 && max_scale > min_scale &&
        max_iterations > 0)) {
    if (why) *why = "priors must be positive, 0 < min_scale < max_scale, iterations > 0";
    return false;
  }
  return true;
}

std::string ScalingResult::BriefReport() const {
  std::string out = fmt::format("scaled to {} frame(s): marker RMS {:.1f} mm → {:.1f} mm; factors",
                                frames_used,
                                rms_before_m * 1e3,
                                rms_after_m * 1e3);
  for (const auto& [g, s] : scale) out += fmt::format(" {} {:.3f}", g, s);
  out += fmt::format("; largest marker offset correction {:.1f} mm ({})",
                     largest_offset_m * 1e3,
                     largest_offset_marker);
  return out;
}

dynamics::Model<double> MakeScaledModel(const dynamics::Model<double>& model,
                                        const std::map<std::string, double>& scale) {
  auto factor = [&](int segment) {
    const auto it = scale.find(ScaleGroupOf(model.segment(segment).name));
    return it == scale.end() ? 1.0 : it->second;
  };
  auto mass_of = [&](int i) {
    const dynamics::Segment<double>& s = model.segment(i);
    const double f = factor(i);
    dynamics::MassProperties m;
    m.mass_kg = s.mass;
    m.p_BoBcm_B = f * s.p_BoBcm_B;
    m.I_BBcm_B = f * f * s.I_BBcm_B;
    return m;
  };
  dynamics::ModelBuilder builder(model.segment(0).name, mass_of(0));
  for (int i = 1; i < model.num_segments(); ++i) {
    const dynamics::Segment<double>& s = model.segment(i);
    dynamics::JointSpec joint;
    joint.axis_sequence = s.axis_sequence;
    joint.p_PoJo_P = factor(s.parent) * s.X_PJ.translation();
    joint.R_PJ = s.X_PJ.rotation();
    builder.AddSegment(s.name, model.segment(s.parent).name, joint, mass_of(i));
  }
  for (const dynamics::Point<double>& p : model.points())
    builder.AddPoint(p.name, model.segment(p.segment).name, factor(p.segment) * p.p_BoP_B);
  builder.SetGravity(model.gravity_W());
  return builder.Build();
}

namespace {

// The scale groups (one factor per group, ScaleGroupOf) and each segment's group.
struct ScaleGroups {
  std::vector<std::string> names;
  std::vector<int> of_segment;
};

ScaleGroups MakeScaleGroups(const dynamics::Model<double>& model) {
  ScaleGroups out;
  out.of_segment.resize(size_t(model.num_segments()));
  for (int s = 0; s < model.num_segments(); ++s) {
    const std::string g = ScaleGroupOf(model.segment(s).name);
    auto it = std::find(out.names.begin(), out.names.end(), g);
    if (it == out.names.end()) {
      out.names.push_back(g);
      it = out.names.end() - 1;
    }
    out.of_segment[size_t(s)] = static_cast<int>(it - out.names.begin());
  }
  return out;
}

// The markers' RMS error over the frames at the poses `q`: evaluated there, or (solve) each pose
// solved first.
double MarkerRmsOverFrames(InverseKinematics& ik,
                           const std::vector<Eigen::Matrix3Xd>& frames,
                           std::vector<Eigen::VectorXd>& q,
                           bool solve) {
  double sum = 0;
  int count = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const IkFrameResult r =
        solve ? ik.Solve(frames[k], q[k], true) : ik.Evaluate(frames[k], q[k], nullptr);
    if (r.num_markers > 0) {
      sum += r.rms_m * r.rms_m * r.num_markers;
      count += r.num_markers;
    }
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

// The priors of the joint problem: the scales near 1 within their bounds, the markers' offsets
// near their defaults.
void AddScalingPriors(const ScalingOptions& options,
                      std::vector<double>& scales,
                      std::vector<Eigen::Vector3d>& delta,
                      ceres::Problem& problem) {
  {
    auto* prior = new ceres::DynamicAutoDiffCostFunction<PriorResidual, 16>(
        new PriorResidual{static_cast<int>(scales.size()), options.scale_prior_m, 1.0});
    prior->AddParameterBlock(static_cast<int>(scales.size()));
    prior->SetNumResiduals(static_cast<int>(scales.size()));
    problem.AddResidualBlock(prior, nullptr, scales.data());
    for (size_t g = 0; g < scales.size(); ++g) {
      problem.SetParameterLowerBound(scales.data(), static_cast<int>(g), options.min_scale);
      problem.SetParameterUpperBound(scales.data(), static_cast<int>(g), options.max_scale);
    }
  }
  for (size_t m = 0; m < delta.size(); ++m) {
    double* d = delta[size_t(m)].data();
    if (!problem.HasParameterBlock(d)) continue;
    auto* prior = new ceres::DynamicAutoDiffCostFunction<PriorResidual, 4>(
        new PriorResidual{3, options.offset_prior, 0.0});
    prior->AddParameterBlock(3);
    prior->SetNumResiduals(3);
    problem.AddResidualBlock(prior, nullptr, d);
  }
}

}  // namespace

ScalingResult ScaleModel(const dynamics::Model<double>& model,
                         const std::vector<ModelMarker>& markers,
                         const std::vector<JointLimit>& limits,
                         const std::vector<Eigen::Matrix3Xd>& frames,
                         const ScalingOptions& options,
                         const std::vector<Eigen::VectorXd>* initial_q,
                         const InverseKinematicsOptions& ik_options) {
  DemandValidOptions(options, "scaling options");
  ACRO_DEMAND(!frames.empty());
  const int n = model.num_joint_dofs();
  const int M = static_cast<int>(markers.size());
  const ScaleGroups scale_groups = MakeScaleGroups(model);
  const std::vector<std::string>& groups = scale_groups.names;
  const std::vector<int>& group_of = scale_groups.of_segment;
  // Initial poses: inverse kinematics of each frame with the unscaled model.
  InverseKinematics ik(model, markers, limits, ik_options);
  std::vector<Eigen::VectorXd> q(frames.size(), dynamics::MakeNeutralConfiguration(model));
  if (initial_q) {
    ACRO_DEMAND(initial_q->size() == frames.size());
    q = *initial_q;
  }
  ScalingResult result;
  // With given poses, their fit as they are.
  result.rms_before_m = MarkerRmsOverFrames(ik, frames, q, initial_q == nullptr);
  result.frames_used = static_cast<int>(frames.size());

  // The joint problem.
  std::vector<double> scales(groups.size(), 1.0);
  std::vector<Eigen::Vector3d> delta(size_t(M), Eigen::Vector3d::Zero());
  ceres::Problem problem;
  for (size_t k = 0; k < frames.size(); ++k) {
    double* pk = q[k].data();
    problem.AddParameterBlock(pk, 3);
    problem.AddParameterBlock(pk + 3, 4, new ceres::QuaternionManifold);
    problem.AddParameterBlock(pk + dynamics::kRootNq, n);
    {
      auto* lim = new ceres::DynamicAutoDiffCostFunction<LimitResidual, 16>(new LimitResidual{
          limits, ik_options.joint_limit_stiffness_m_per_rad, ik_options.joint_prior_m_per_rad});
      lim->AddParameterBlock(n);
      lim->SetNumResiduals(ik_options.joint_prior_m_per_rad.empty() ? n : 2 * n);
      problem.AddResidualBlock(lim, nullptr, pk + dynamics::kRootNq);
    }
    for (int m = 0; m < M; ++m) {
      if (std::isnan(frames[k](0, m))) continue;
      auto* f = new ScaledMarkerResidual;
      f->model = &model;
      for (int s = markers[size_t(m)].segment; s >= 0; s = model.segment(s).parent)
        f->chain.insert(f->chain.begin(), s);
      f->group_of = group_of;
      f->p_BoM_B = markers[size_t(m)].p_BoM_B;
      f->observed = frames[k].col(m);
      f->weight = markers[size_t(m)].weight;
      auto* cost = new ceres::DynamicAutoDiffCostFunction<ScaledMarkerResidual, 8>(f);
      cost->AddParameterBlock(3);
      cost->AddParameterBlock(4);
      cost->AddParameterBlock(n);
      cost->AddParameterBlock(static_cast<int>(scales.size()));
      cost->AddParameterBlock(3);
      cost->SetNumResiduals(3);
      problem.AddResidualBlock(
          cost,
          new ceres::HuberLoss(ik_options.robust_scale_m),
          {pk, pk + 3, pk + dynamics::kRootNq, scales.data(), delta[size_t(m)].data()});
    }
  }
  AddScalingPriors(options, scales, delta, problem);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(so.sparse_linear_algebra_library_type))
    so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = options.max_iterations;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  result.converged = summary.termination_type == ceres::CONVERGENCE;

  // The scaled model and markers.
  for (size_t g = 0; g < groups.size(); ++g) result.scale[groups[g]] = scales[g];
  result.model = MakeScaledModel(model, result.scale);
  result.markers = markers;
  for (int m = 0; m < M; ++m) {
    ModelMarker& mk = result.markers[size_t(m)];
    mk.p_BoM_B = scales[size_t(group_of[size_t(mk.segment)])] * mk.p_BoM_B + delta[size_t(m)];
    if (delta[size_t(m)].norm() > result.largest_offset_m) {
      result.largest_offset_m = delta[size_t(m)].norm();
      result.largest_offset_marker = mk.name;
    }
  }
  // Fit after scaling, at the poses fitted with it.
  InverseKinematics ik_scaled(result.model, result.markers, limits, ik_options);
  for (Eigen::VectorXd& pose : q) pose.segment<4>(3).normalize();
  result.rms_after_m = MarkerRmsOverFrames(ik_scaled, frames, q, false);
  result.poses = q;
  return result;
}

}  // namespace acro::analysis
