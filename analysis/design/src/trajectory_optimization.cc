// Model (1) in its local form: per-sample Ceres residual blocks over the gaps and the data of the
// two knots around each sample (docs/skill-design.md, "Model (1): local form"). This translation
// unit instantiates the inverse dynamics for the sample-state Jet.

#include "trajectory_optimization.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>

#include "acro/athlete/standard_human.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "hermite_trajectory.h"
#include "skill_solver.h"

namespace acro::analysis::internal {
namespace {

// Joint angles of the standard human (compile-time, for the Jet sizes).
constexpr int CountStandardJointDofs() {
  int n = 0;
  for (const StandardJoint& j : kStandardJoints) n += static_cast<int>(j.axis_sequence.size());
  return n;
}
constexpr int kNdof = CountStandardJointDofs();
// A sample's state, in the slot order of the chain rule below: root quaternion (4), w_WB_B (3),
// ẇ_WB_B (3), joint angles, rates and accelerations (3 kNdof).
constexpr int kStateDim = 10 + 3 * kNdof;
// Slots of the configuration within the state: the quaternion (0–3) and the joint angles.
constexpr int kJointAngleSlot = 10;
constexpr int kJointRateSlot = 10 + kNdof;
constexpr int kJointAccelerationSlot = 10 + 2 * kNdof;
// The residual depends nonlinearly only on the configuration: it is linear in the accelerations
// and quadratic in the velocities (τ = M(q) a + C(q, v) v + g(q), and the shift to the COM depends
// on q alone). Of the configuration, the root orientation only turns the moment into W: about the
// COM, uniform gravity has no moment, so n_B = R_WBᵀ n_W does not depend on it. A Jet carries the
// kNdof joint angles; the orientation's derivatives are ∂R/∂Q n_B, and the velocity and
// acceleration derivatives come exactly from the mass matrix and differences (SampleResidual).
using ConfigJet = ceres::Jet<double, kNdof>;
using QuaternionJet = ceres::Jet<double, 4>;
// The orientation's local inputs: h, then per knot (a, b) δ, w, ẇ.
constexpr int kOrientationInputs = 19;
using OrientationJet = ceres::Jet<double, kOrientationInputs>;

// Per knot: joint-angle offsets, orientation offset δ, joint rates, joint accelerations, angular
// velocity and acceleration; these are also its Ceres parameter blocks.
constexpr int kNumKnotBlocks = 5;
constexpr int kBlockSizes[kNumKnotBlocks] = {kNdof, 3, kNdof, kNdof, 6};
constexpr int kKnotParameters = 3 * kNdof + 9;
constexpr int kBlockOffsets[kNumKnotBlocks] = {0, kNdof, kNdof + 3, 2 * kNdof + 3, 3 * kNdof + 3};

// Workspaces handed out to concurrent evaluations: Take() reuses a free one or makes a new one, the
// lease gives it back. At most as many exist as evaluations ever ran at once.
template <typename T>
class WorkspacePool {
 public:
  explicit WorkspacePool(const dynamics::Model<T>& model) : model_(&model) {}
  class Lease {
   public:
    Lease(WorkspacePool& pool) : pool_(pool), ws_(pool.Take()) {}
    ~Lease() { pool_.Give(std::move(ws_)); }
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    dynamics::Workspace<T>& operator*() { return *ws_; }

   private:
    WorkspacePool& pool_;
    std::unique_ptr<dynamics::Workspace<T>> ws_;
  };

 private:
  std::unique_ptr<dynamics::Workspace<T>> Take() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<dynamics::Workspace<T>> ws = std::move(free_.back());
        free_.pop_back();
        return ws;
      }
    }
    return std::make_unique<dynamics::Workspace<T>>(*model_);
  }
  void Give(std::unique_ptr<dynamics::Workspace<T>> ws) {
    const std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(ws));
  }
  const dynamics::Model<T>* model_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<dynamics::Workspace<T>>> free_;
};

// Everything a residual block needs besides the variables.
struct Model1Data {
  const SkillDesign* design = nullptr;
  const SkillTrajectory* base = nullptr;
  int n = 0;       // keyframes
  int P = 2;       // knots per keyframe interval
  int M = 4;       // Simpson intervals per knot interval
  double T = 0.0;  // flight time
  double height = 0.0;
  dynamics::Model<double> model_d;
  dynamics::Model<ConfigJet> model_j;
  // One workspace per concurrent evaluation (Ceres evaluates residual blocks on several threads).
  mutable WorkspacePool<double> ws_d;
  mutable WorkspacePool<ConfigJet> ws_j;
  // The segment whose joint each velocity coordinate belongs to (−1 for the root's).
  std::vector<int> segment_of_velocity;

  Model1Data(const SkillDesign& d, const SkillTrajectory& b, int samples)
      : design(&d),
        base(&b),
        n(d.num_keyframes()),
        P(b.knots_per_interval),
        M(samples),
        T(d.flight_time_s()),
        height(d.height_m()),
        model_d(d.model()),
        model_j(d.model().Cast<ConfigJet>()),
        ws_d(model_d),
        ws_j(model_j) {
    ACRO_DEMAND(d.num_joint_dofs() == kNdof);
    ACRO_DEMAND(b.has_knots() && b.num_knots() == P * (n - 1) + 1);
    ACRO_DEMAND(M >= 2 && M % 2 == 0);
    segment_of_velocity.assign(static_cast<size_t>(model_d.nv()), -1);
    for (int i = 1; i < model_d.num_segments(); ++i)
      for (int k = 0; k < model_d.segment(i).num_axes; ++k)
        segment_of_velocity[static_cast<size_t>(model_d.segment(i).v_start + k)] = i;
  }
  int num_knots() const { return P * (n - 1) + 1; }
};

// Absolute joint data of a knot: the base plus the knot's parameter blocks.
struct KnotValues {
  double y[kNdof], yd[kNdof], ydd[kNdof];
};

// The joint data (y, y', y'') of knot k in double.
void JointKnotData(const Model1Data& d, int k, const double* const* blocks, KnotValues& v) {
  const SkillTrajectory& b = *d.base;
  for (int j = 0; j < kNdof; ++j) {
    v.y[j] = b.knot_joint_angles_rad(j, k) + blocks[0][j];
    v.yd[j] = b.knot_joint_rates(j, k) + blocks[2][j];
    v.ydd[j] = b.knot_joint_accelerations(j, k) + blocks[3][j];
  }
}

// The orientation data of knot k, with the Jet's derivative slots from `slot` on for δ, w, ẇ (or
// none when slot < 0).
template <typename T>
OrientationKnot<T> OrientationKnotData(const Model1Data& d,
                                       int k,
                                       const double* const* blocks,
                                       int slot) {
  const SkillTrajectory& b = *d.base;
  auto seeded = [&](double value, int s) {
    T x(value);
    if constexpr (!std::is_same_v<T, double>) {
      if (slot >= 0) x.v[slot + s] = 1.0;
    }
    return x;
  };
  dynamics::Vector3<T> delta, w, wdot;
  for (int c = 0; c < 3; ++c) {
    delta[c] = seeded(blocks[1][c], c);
    w[c] = seeded(b.knot_angular_velocities_B(c, k) + blocks[4][c], 3 + c);
    wdot[c] = seeded(b.knot_angular_accelerations_B(c, k) + blocks[4][3 + c], 6 + c);
  }
  OrientationKnot<T> out;
  out.Q = Eigen::Quaternion<T>(b.knot_orientations[static_cast<size_t>(k)].cast<T>() *
                               dynamics::QuaternionExp<T>(delta));
  out.w = w;
  out.wdot = wdot;
  return out;
}

// Gap geometry: S = Σ g, the length h of the knot intervals of keyframe interval i and ∂h/∂g.
struct GapGeometry {
  double S = 0.0;
  GapGeometry(const Model1Data& d, const double* g) {
    for (int l = 0; l + 1 < d.n; ++l) S += g[l];
  }
  double h(const Model1Data& d, const double* g, int i) const { return d.T * g[i] / (S * d.P); }
  // ∂h_i/∂g_l = T/(S P) (δ_il − g_i/S).
  double dh(const Model1Data& d, const double* g, int i, int l) const {
    return d.T / (S * d.P) * ((l == i ? 1.0 : 0.0) - g[i] / S);
  }
};

// The orientation sample at a knot itself.
template <typename T>
QuaternionSample<T> KnotSample(const OrientationKnot<T>& k) {
  QuaternionSample<T> r;
  r.q_WB = k.Q;
  r.w_WB_B = k.w;
  r.wdot_WB_B = k.wdot;
  return r;
}

// The normalised moment residual about the COM at one state (q, v, a: root at the origin, at rest
// in translation) and, when dn != nullptr, its derivatives over the state in the slot order of
// kStateDim. The joint angles' derivatives come from one ConfigJet pass, the orientation's from
// n_W = R(Q) n_B with n_B independent of Q (above). The residual is linear
// in a: its derivatives there are the root rows of the mass matrix M(q) carried to the COM,
// ∂n/∂a_k = (R M[3:6, k] − p_BoScm_W × M[0:3, k]) / (m g h). It is quadratic in v, so
// (n(v + e_k) − n(v − e_k))/2 is its exact partial derivative (no truncation error, whatever the
// step: unit steps keep rounding small): two double passes over the joint's subtree for a joint
// rate, two full passes at the configuration's poses for the root's angular velocity.
void SampleResidual(const Model1Data& d,
                    const Eigen::VectorXd& q,
                    const Eigen::VectorXd& v,
                    const Eigen::VectorXd& a,
                    double n[3],
                    double (*dn)[kStateDim]) {
  typename WorkspacePool<double>::Lease ws(d.ws_d);
  if (dn == nullptr) {
    dynamics::CalcInverseDynamics(d.model_d, *ws, q, v, a);
    const Eigen::Vector3d m =
        dynamics::CalcRootResidual(d.model_d, *ws, d.height).moment_per_weight_height;
    for (int c = 0; c < 3; ++c) n[c] = m[c];
    return;
  }
  // Configuration: the joint angles, then the quaternion (slots 0–3).
  {
    typename WorkspacePool<ConfigJet>::Lease wsj(d.ws_j);
    const dynamics::Model<ConfigJet>& m = d.model_j;
    dynamics::VectorX<ConfigJet> qj(m.nq()), vj(m.nv()), aj(m.nv());
    for (int k = 0; k < m.nq(); ++k) qj[k] = ConfigJet(q[k]);
    for (int k = 0; k < m.nv(); ++k) {
      vj[k] = ConfigJet(v[k]);
      aj[k] = ConfigJet(a[k]);
    }
    for (int j = 0; j < kNdof; ++j) qj[dynamics::kRootNq + j].v[j] = 1.0;
    dynamics::CalcInverseDynamics(m, *wsj, qj, vj, aj);
    const dynamics::RootResidual<ConfigJet> res =
        dynamics::CalcRootResidual(m, *wsj, ConfigJet(d.height));
    Eigen::Vector3d n_W;
    for (int c = 0; c < 3; ++c) {
      const ConfigJet& nc = res.moment_per_weight_height[c];
      n_W[c] = nc.a;
      for (int j = 0; j < kNdof; ++j) dn[c][kJointAngleSlot + j] = nc.v[j];
    }
    // ∂n_W/∂Q = ∂R(Q)/∂Q n_B, through the rotation formula the dynamics uses.
    const QuaternionJet w(q[3], 0), x(q[4], 1), y(q[5], 2), z(q[6], 3);
    const Eigen::Matrix3d R = dynamics::QuaternionToRotation<double>(q[3], q[4], q[5], q[6]);
    const Eigen::Vector3d n_B = R.transpose() * n_W;
    const dynamics::Vector3<QuaternionJet> nq =
        dynamics::QuaternionToRotation<QuaternionJet>(w, x, y, z) * n_B.cast<QuaternionJet>();
    for (int c = 0; c < 3; ++c) {
      n[c] = n_W[c];
      for (int k = 0; k < 4; ++k) dn[c][k] = nq[c].v[k];
    }
  }
  const dynamics::Model<double>& md = d.model_d;
  const double weight_height = md.total_mass() * md.gravity_W().norm() * d.height;
  // Accelerations (root angular acceleration: slots 7–9; joint accelerations) from M(q); the
  // mass matrix pass leaves the configuration's poses for the passes at (v, a) that follow, and
  // CalcRootResidual is called for the COM it leaves in mc_Bo_B.
  const Eigen::MatrixXd& M = dynamics::CalcMassMatrix(md, *ws, q);
  dynamics::CalcInverseDynamicsAtSameConfiguration(md, *ws, v, a);
  dynamics::CalcRootResidual(md, *ws, d.height);
  const Eigen::Matrix3d R_WB = (*ws).X_PB[0].rotation();
  const Eigen::Vector3d p_BoScm_W = R_WB * (*ws).mc_Bo_B[0] / md.total_mass();
  for (int k = 3; k < md.nv(); ++k) {
    const int a_slot = k < 6 ? 7 + (k - 3) : kJointAccelerationSlot + (k - 6);
    const Eigen::Vector3d dn_da =
        (R_WB * M.block<3, 1>(3, k) - p_BoScm_W.cross(M.block<3, 1>(0, k))) / weight_height;
    for (int c = 0; c < 3; ++c) dn[c][a_slot] = dn_da[c];
  }
  // Velocities (joint rates, then the root angular velocity: slots 4–6): the moment about the
  // COM of a changed root wrench, n_W = R (n_Bo − p_BoScm × f) / (m g h) with this configuration's
  // R and COM. A joint rate changes only its segment's subtree; the root's change everything.
  const Eigen::Vector3d p_BoScm_B = R_WB.transpose() * p_BoScm_W;
  const auto moment_of = [&](const dynamics::SpatialForce<double>& F_Bo_B) -> Eigen::Vector3d {
    return R_WB * F_Bo_B.Shift(p_BoScm_B).rotational() / weight_height;
  };
  Eigen::VectorXd vv = v;
  for (int k = 6; k < md.nv(); ++k) {
    const int segment = d.segment_of_velocity[static_cast<size_t>(k)];
    vv[k] = v[k] + 1.0;
    const Eigen::Vector3d plus =
        moment_of(dynamics::CalcRootWrenchWithJointChanged(md, *ws, segment, vv, a));
    vv[k] = v[k] - 1.0;
    const Eigen::Vector3d minus =
        moment_of(dynamics::CalcRootWrenchWithJointChanged(md, *ws, segment, vv, a));
    vv[k] = v[k];
    for (int c = 0; c < 3; ++c) dn[c][kJointRateSlot + (k - 6)] = 0.5 * (plus[c] - minus[c]);
  }
  for (int k = 3; k < 6; ++k) {
    vv[k] = v[k] + 1.0;
    dynamics::CalcInverseDynamicsAtSameConfiguration(md, *ws, vv, a);
    const Eigen::Vector3d plus = moment_of((*ws).F_Bo_B[0]);
    vv[k] = v[k] - 1.0;
    dynamics::CalcInverseDynamicsAtSameConfiguration(md, *ws, vv, a);
    const Eigen::Vector3d minus = moment_of((*ws).F_Bo_B[0]);
    vv[k] = v[k];
    for (int c = 0; c < 3; ++c) dn[c][4 + (k - 3)] = 0.5 * (plus[c] - minus[c]);
  }
}

// One quadrature sample: r = √W · n(t), with n the moment residual about the COM / (m g h) and W
// the Simpson weight over T. Interior samples (0 < u < 1 of knot interval k) depend on the gaps and
// knots k, k + 1; knot samples (at knot k, weights of both neighbouring intervals) on the gaps and
// knot k. Parameter blocks: the gaps, then the five blocks of knot k (and of knot k + 1).
class SampleCost : public ceres::CostFunction {
 public:
  // weights: (keyframe interval i, coefficient c) pairs, W = Σ c h_i / T.
  SampleCost(const Model1Data* d, int knot, double u, std::vector<std::pair<int, double>> weights)
      : d_(d), knot_(knot), interior_(u > 0.0), basis_(u), weights_(std::move(weights)) {
    set_num_residuals(3);
    mutable_parameter_block_sizes()->push_back(d->n - 1);
    for (int knot_count = 0; knot_count < (interior_ ? 2 : 1); ++knot_count)
      for (int s : kBlockSizes) mutable_parameter_block_sizes()->push_back(s);
  }

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const Model1Data& d = *d_;
    const double* g = p[0];
    const GapGeometry geo(d, g);
    const int i = knot_ / d.P;  // keyframe interval of the knot interval
    const double h = geo.h(d, g, i);
    // Weight and its gradient over the gaps.
    double W = 0.0;
    for (const auto& [wi, c] : weights_) W += c * geo.h(d, g, wi) / d.T;
    const double sW = std::sqrt(W);

    // Knot data.
    KnotValues ka, kb;
    JointKnotData(d, knot_, p + 1, ka);
    if (interior_) JointKnotData(d, knot_ + 1, p + 1 + kNumKnotBlocks, kb);

    // The orientation and its derivatives over the local inputs (h, then δ, w, ẇ of both knots;
    // all zero when only values are asked for: the Jet's cost is small beside the dynamics').
    const int slot_a = jacobians != nullptr ? 1 : -1;
    const int slot_b = jacobians != nullptr ? 10 : -1;
    const QuaternionSample<OrientationJet> rj =
        interior_
            ? EvalOrientationHermite<OrientationJet>(
                  basis_,
                  jacobians != nullptr ? OrientationJet(h, 0) : OrientationJet(h),
                  OrientationKnotData<OrientationJet>(d, knot_, p + 1, slot_a),
                  OrientationKnotData<OrientationJet>(d, knot_ + 1, p + 1 + kNumKnotBlocks, slot_b))
            : KnotSample(OrientationKnotData<OrientationJet>(d, knot_, p + 1, slot_a));
    // The orientation part of the state, in the slot order of kStateDim.
    const OrientationJet orient[10] = {rj.q_WB.w(),
                                       rj.q_WB.x(),
                                       rj.q_WB.y(),
                                       rj.q_WB.z(),
                                       rj.w_WB_B[0],
                                       rj.w_WB_B[1],
                                       rj.w_WB_B[2],
                                       rj.wdot_WB_B[0],
                                       rj.wdot_WB_B[1],
                                       rj.wdot_WB_B[2]};

    // The sample state in double (root at the origin, at rest in translation) and, for interior
    // samples, the joint state's derivative over h.
    const int nq = d.model_d.nq(), nv = d.model_d.nv();
    Eigen::VectorXd q = Eigen::VectorXd::Zero(nq), v = Eigen::VectorXd::Zero(nv),
                    a = Eigen::VectorXd::Zero(nv);
    for (int k = 0; k < 4; ++k) q[3 + k] = orient[k].a;
    for (int k = 0; k < 3; ++k) {
      v[3 + k] = orient[4 + k].a;
      a[3 + k] = orient[7 + k].a;
    }
    double joint_dh[3][kNdof];
    JointState(ka, kb, h, q, v, a, joint_dh);

    double n[3];
    if (jacobians == nullptr) {
      SampleResidual(d, q, v, a, n, nullptr);
      for (int c = 0; c < 3; ++c) residuals[c] = sW * n[c];
      return true;
    }
    double dn_dstate[3][kStateDim];
    SampleResidual(d, q, v, a, n, dn_dstate);
    for (int c = 0; c < 3; ++c) {
      residuals[c] = sW * n[c];
      ChainRule(geo, g, i, h, sW, n[c], dn_dstate[c], orient, joint_dh, c, jacobians);
    }
    return true;
  }

 private:
  // The joints' value, rate and acceleration at the sample (the knot's own at an end sample, the
  // quintic Hermite between two knots inside), into q, v, a; their derivatives over h.
  void JointState(const KnotValues& ka,
                  const KnotValues& kb,
                  double h,
                  Eigen::VectorXd& q,
                  Eigen::VectorXd& v,
                  Eigen::VectorXd& a,
                  double joint_dh[3][kNdof]) const {
    for (int j = 0; j < kNdof; ++j) {
      double value[3];
      if (interior_) {
        const double data[6] = {ka.y[j], ka.yd[j], ka.ydd[j], kb.y[j], kb.yd[j], kb.ydd[j]};
        for (int o = 0; o < 3; ++o) {
          value[o] = QuinticHermite<double, double>(basis_, o, h, data);
          // ∂/∂h of Σ_k H[o][k] h^(p_k − o) data_k.
          double dh = 0.0;
          for (int k = 0; k < 6; ++k) {
            const int e = QuinticHermiteBasis::Power(k) - o;
            if (e != 0) dh += e * basis_.H[o][k] * std::pow(h, e - 1) * data[k];
          }
          joint_dh[o][j] = dh;
        }
      } else {
        value[0] = ka.y[j];
        value[1] = ka.yd[j];
        value[2] = ka.ydd[j];
        for (int o = 0; o < 3; ++o) joint_dh[o][j] = 0.0;
      }
      q[dynamics::kRootNq + j] = value[0];
      v[6 + j] = value[1];
      a[6 + j] = value[2];
    }
  }

  // Residual c's row of every Jacobian asked for: ∂n/∂(local inputs) from ∂n/∂state (`dn`).
  void ChainRule(const GapGeometry& geo,
                 const double* g,
                 int i,
                 double h,
                 double sW,
                 double n,
                 const double* dn,
                 const OrientationJet (&orient)[10],
                 const double (&joint_dh)[3][kNdof],
                 int c,
                 double** jacobians) const {
    const Model1Data& d = *d_;
    // Through the orientation: ∂n/∂z_o = Σ_s ∂n/∂state_s ∂state_s/∂z_o.
    double dn_dz[kOrientationInputs] = {};
    for (int s = 0; s < 10; ++s)
      for (int o = 0; o < kOrientationInputs; ++o) dn_dz[o] += dn[s] * orient[s].v[o];
    // ∂n/∂h: the orientation's h slot plus the joints'.
    double dn_dh = dn_dz[0];
    for (int o = 0; o < 3; ++o)
      for (int j = 0; j < kNdof; ++j) dn_dh += dn[10 + o * kNdof + j] * joint_dh[o][j];
    // Gaps: r = √W n(h), ∂r/∂g_l = n ∂√W/∂g_l + √W ∂n/∂h ∂h/∂g_l.
    if (jacobians[0] != nullptr) {
      for (int l = 0; l + 1 < d.n; ++l) {
        double dW = 0.0;
        for (const auto& [wi, cw] : weights_) dW += cw * geo.dh(d, g, wi, l) / d.T;
        jacobians[0][c * (d.n - 1) + l] =
            n * dW / (2.0 * sW) + (interior_ ? sW * dn_dh * geo.dh(d, g, i, l) : 0.0);
      }
    }
    // Knot blocks.
    for (int knot_count = 0; knot_count < (interior_ ? 2 : 1); ++knot_count) {
      double** J = jacobians + 1 + kNumKnotBlocks * knot_count;
      const int zo = 1 + 9 * knot_count;  // δ, w, ẇ slots of this knot
      // Joint data k of this knot: H index 3·knot_count + p (p = 0 value, 1 rate, 2 acc).
      auto joint_coefficient = [&](int o, int p_kind) {
        if (!interior_) return o == p_kind ? 1.0 : 0.0;
        const int k = 3 * knot_count + p_kind;
        return basis_.H[o][k] * std::pow(h, p_kind - o);
      };
      for (int p_kind = 0; p_kind < 3; ++p_kind) {
        double coeff[3];
        for (int o = 0; o < 3; ++o) coeff[o] = joint_coefficient(o, p_kind);
        double* Jb = J[p_kind == 0 ? 0 : p_kind + 1];
        if (Jb == nullptr) continue;
        for (int j = 0; j < kNdof; ++j) {
          double sum = 0.0;
          for (int o = 0; o < 3; ++o) sum += dn[10 + o * kNdof + j] * coeff[o];
          Jb[c * kNdof + j] = sW * sum;
        }
      }
      if (J[1] != nullptr)
        for (int s = 0; s < 3; ++s) J[1][c * 3 + s] = sW * dn_dz[zo + s];
      if (J[4] != nullptr)
        for (int s = 0; s < 6; ++s) J[4][c * 6 + s] = sW * dn_dz[zo + 3 + s];
    }
  }

  const Model1Data* d_;
  int knot_;
  bool interior_;
  QuinticHermiteBasis basis_;
  std::vector<std::pair<int, double>> weights_;
};

// 10⁻² (Σg/T − 1): pins the scale of the gaps, a direction J does not see.
class GapScaleCost : public ceres::CostFunction {
 public:
  GapScaleCost(int num_gaps, double T, double weight) : n_(num_gaps), T_(T), w_(weight) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(num_gaps);
  }
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    double S = 0.0;
    for (int l = 0; l < n_; ++l) S += p[0][l];
    r[0] = w_ * (S / T_ - 1.0);
    if (J != nullptr && J[0] != nullptr)
      for (int l = 0; l < n_; ++l) J[0][l] = w_ / T_;
    return true;
  }

 private:
  int n_;
  double T_, w_;
};

// Pointers to the parameter blocks inside x: the gaps, then four blocks per knot.
struct Model1Blocks {
  double* gaps = nullptr;
  std::vector<std::array<double*, kNumKnotBlocks>> knot;
};

Model1Blocks SplitParameters(const Model1Data& d, double* x) {
  Model1Blocks b;
  b.gaps = x;
  double* p = x + (d.n - 1);
  for (int k = 0; k < d.num_knots(); ++k, p += kKnotParameters)
    b.knot.push_back({p + kBlockOffsets[0],
                      p + kBlockOffsets[1],
                      p + kBlockOffsets[2],
                      p + kBlockOffsets[3],
                      p + kBlockOffsets[4]});
  return b;
}

// Every sample's residual block (and the gap-scale block when scale_weight > 0).
void AddModel1Residuals(ceres::Problem& problem,
                        const Model1Data& d,
                        const Model1Blocks& b,
                        double scale_weight) {
  const int K = d.num_knots();
  // Composite Simpson on M intervals per knot interval: coefficients (1, 4, 2, …, 4, 1)/(3M).
  const double c0 = 1.0 / (3.0 * d.M);
  for (int k = 0; k < K; ++k) {
    // The knot sample: its weight collects both neighbouring intervals' end coefficients.
    std::vector<std::pair<int, double>> w;
    if (k > 0) w.emplace_back((k - 1) / d.P, c0);
    if (k + 1 < K) w.emplace_back(k / d.P, c0);
    std::vector<double*> blocks = {b.gaps};
    for (double* q : b.knot[static_cast<size_t>(k)]) blocks.push_back(q);
    problem.AddResidualBlock(new SampleCost(&d, k, 0.0, w), nullptr, blocks);
    if (k + 1 == K) break;
    // Interior samples of knot interval k.
    for (double* q : b.knot[static_cast<size_t>(k + 1)]) blocks.push_back(q);
    for (int s = 1; s < d.M; ++s) {
      const double c = (s % 2 ? 4.0 : 2.0) * c0;
      problem.AddResidualBlock(
          new SampleCost(&d, k, static_cast<double>(s) / d.M, {{k / d.P, c}}), nullptr, blocks);
    }
  }
  if (scale_weight > 0.0)
    problem.AddResidualBlock(
        new GapScaleCost(d.n - 1, d.T, scale_weight), nullptr, std::vector<double*>{b.gaps});
}

}  // namespace

int NumModel1Parameters(const SkillDesign& design, int knots_per_interval) {
  return design.num_keyframes() - 1 +
         (knots_per_interval * (design.num_keyframes() - 1) + 1) * kKnotParameters;
}

SkillTrajectory Model1TrajectoryFromParameters(const SkillDesign& design,
                                               const SkillTrajectory& base,
                                               const Eigen::VectorXd& x) {
  ACRO_DEMAND(base.has_knots());
  ACRO_DEMAND(x.size() == NumModel1Parameters(design, base.knots_per_interval));
  const int n = design.num_keyframes();
  const int P = base.knots_per_interval;
  SkillTrajectory t = base;
  // Keyframe times from the gaps.
  double S = 0.0;
  for (int l = 0; l + 1 < n; ++l) S += x[l];
  double cum = 0.0;
  t.times_s[0] = 0.0;
  for (int i = 1; i < n; ++i) {
    cum += x[i - 1];
    t.times_s[i] = i + 1 == n ? design.flight_time_s() : design.flight_time_s() * cum / S;
  }
  // Knot data: base plus offsets; the keyframe poses are the keyframe knots'.
  for (int k = 0; k < base.num_knots(); ++k) {
    const double* p = x.data() + (n - 1) + k * kKnotParameters;
    for (int j = 0; j < kNdof; ++j) {
      t.knot_joint_angles_rad(j, k) += p[kBlockOffsets[0] + j];
      t.knot_joint_rates(j, k) += p[kBlockOffsets[2] + j];
      t.knot_joint_accelerations(j, k) += p[kBlockOffsets[3] + j];
    }
    const Eigen::Vector3d delta(p + kBlockOffsets[1]);
    t.knot_orientations[static_cast<size_t>(k)] =
        (base.knot_orientations[static_cast<size_t>(k)] * dynamics::QuaternionExp<double>(delta))
            .normalized();
    t.knot_angular_velocities_B.col(k) += Eigen::Vector3d(p + kBlockOffsets[4]);
    t.knot_angular_accelerations_B.col(k) += Eigen::Vector3d(p + kBlockOffsets[4] + 3);
    if (k % P == 0) {
      t.joint_angles_rad.col(k / P) = t.knot_joint_angles_rad.col(k);
      t.keyframe_orientations[static_cast<size_t>(k / P)] =
          t.knot_orientations[static_cast<size_t>(k)];
    }
  }
  return t;
}

double CalcModel1Objective(const SkillDesign& design,
                           const SkillTrajectory& base,
                           const Eigen::VectorXd& x,
                           int samples_per_knot_interval,
                           Eigen::VectorXd* gradient) {
  const Model1Data d(design, base, samples_per_knot_interval);
  ACRO_DEMAND(x.size() == NumModel1Parameters(design, base.knots_per_interval));
  Eigen::VectorXd xc = x;
  const Model1Blocks b = SplitParameters(d, xc.data());
  ceres::Problem problem;
  AddModel1Residuals(problem, d, b, 0.0);
  // Evaluate in the order of x; J = 2 · cost, ∇J = 2 · ∇cost.
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks.push_back(b.gaps);
  for (const auto& k : b.knot)
    for (double* q : k) eo.parameter_blocks.push_back(q);
  double cost = 0.0;
  std::vector<double> grad;
  problem.Evaluate(eo, &cost, nullptr, gradient != nullptr ? &grad : nullptr, nullptr);
  if (gradient != nullptr)
    *gradient = 2.0 * Eigen::Map<const Eigen::VectorXd>(grad.data(), x.size());
  return 2.0 * cost;
}

Eigen::VectorXd SolveModel1(const SkillDesign& design,
                            const SkillTrajectory& base,
                            const SkillOptimizationOptions& options,
                            SkillOptimizationSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  const Model1Data d(design, base, options.model1_samples_per_knot_interval);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(NumModel1Parameters(design, base.knots_per_interval));
  const int n = design.num_keyframes();
  for (int j = 0; j + 1 < n; ++j) x[j] = base.times_s[j + 1] - base.times_s[j];
  const Model1Blocks b = SplitParameters(d, x.data());

  ceres::Problem problem;
  AddModel1Residuals(problem, d, b, 1e-2);
  // Ordering kept by positive gaps: g_j ≥ min_gap_fraction · T/(n − 1).
  const double min_gap = options.min_gap_fraction * design.flight_time_s() / (n - 1);
  for (int j = 0; j + 1 < n; ++j) problem.SetParameterLowerBound(b.gaps, j, min_gap);
  // Keyframe tolerances as bounds on the keyframe knots: |Δθ| ≤ e₂ per joint angle, each
  // component of δ within e₂/√3 so that the geodesic distance |δ| ≤ e₂.
  for (int i = 0; i < n; ++i) {
    const double e2 = design.skill().keyframes[static_cast<size_t>(i)].tolerance_angle_rad;
    const auto& k = b.knot[static_cast<size_t>(i * d.P)];
    for (int j = 0; j < kNdof; ++j) {
      problem.SetParameterLowerBound(k[0], j, -e2);
      problem.SetParameterUpperBound(k[0], j, e2);
    }
    for (int c = 0; c < 3; ++c) {
      problem.SetParameterLowerBound(k[1], c, -e2 / std::sqrt(3.0));
      problem.SetParameterUpperBound(k[1], c, e2 / std::sqrt(3.0));
    }
  }
  if (!options.model1_vary_joints)
    for (const auto& k : b.knot) {
      problem.SetParameterBlockConstant(k[0]);
      problem.SetParameterBlockConstant(k[2]);
      problem.SetParameterBlockConstant(k[3]);
    }

  const int threads = SkillSolverThreads(options);
  ceres::Solver::Options so =
      MakeSkillSolverOptions(options, ceres::SPARSE_NORMAL_CHOLESKY, threads);
  so.function_tolerance = options.model1_function_tolerance;
  SkillProgressCallback callback(options, "model 1");
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);

  *summary = MakeStageSummary(s, start);
  return x;
}

}  // namespace acro::analysis::internal
