#pragma once

// Recursive Newton–Euler inverse dynamics (Featherstone 2008, RBDA Table 5.1), the
// composite-rigid-body mass matrix (RBDA Table 6.2), bias forces, the root residual at the
// whole-body centre of mass, and the root acceleration of a body in flight. Conventions:
// docs/notation.md. None of these allocates.

#include <Eigen/Cholesky>
#include <string>
#include <vector>

#include "acro/dynamics/kinematics.h"

namespace acro::dynamics {

/// τ = ID(q, v, a): the generalised forces (nv) that produce accelerations a at state (q, v)
/// under gravity and the optional applied wrenches F_ext_Bo_W (one per segment, about Bo,
/// expressed in W; nullptr for none). τ[0:3] is the root force in W, τ[3:6] the root moment about
/// the root origin in the root frame (the generalised forces of v_WBo_W and w_WB_B), τ[6:] one
/// torque per joint axis. Writes ws.tau (returned), the relative poses X_PB, velocities,
/// accelerations and joint wrenches ws.F_Bo_B; world poses X_WB only when F_ext_Bo_W is given
/// (else only the root's, and ws.world_poses_current is false).
template <typename T>
const VectorX<T>& CalcInverseDynamics(const Model<T>& model,
                                      Workspace<T>& ws,
                                      const VectorXcRef<T>& q,
                                      const VectorXcRef<T>& v,
                                      const VectorXcRef<T>& a,
                                      const std::vector<SpatialForce<T>>* F_ext_Bo_W = nullptr);

/// CalcInverseDynamics at the configuration q of the previous pose pass on ws (inverse dynamics,
/// mass matrix, forward kinematics: ws.poses_current), reusing its relative poses and joint axes
/// (for derivatives over v and a at a fixed q: no sines, cosines or joint rotations). Without
/// applied wrenches.
template <typename T>
const VectorX<T>& CalcInverseDynamicsAtSameConfiguration(const Model<T>& model,
                                                         Workspace<T>& ws,
                                                         const VectorXcRef<T>& v,
                                                         const VectorXcRef<T>& a);

/// The root wrench (about Bo in B, what ws.F_Bo_B[0] holds after inverse dynamics) that the last
/// inverse dynamics pass on ws (CalcInverseDynamics, CalcBiasForces or the same-configuration
/// pass, without applied wrenches and not followed by forward kinematics:
/// ws.plain_inverse_dynamics_current) would give with v and a replaced by v_new and a_new, which
/// differ from them only in the coordinates of segment `segment`'s joint (segment > 0). Only that
/// segment's subtree is recomputed; the rest of the last pass is reused and left as it was. For
/// derivatives of the root residual over one joint rate or acceleration at a time (for a hand, the
/// motion and force of one segment instead of all fifteen of the standard human, and four
/// transforms up to the root).
template <typename T>
SpatialForce<T> CalcRootWrenchWithJointChanged(const Model<T>& model,
                                               Workspace<T>& ws,
                                               int segment,
                                               const VectorXcRef<T>& v_new,
                                               const VectorXcRef<T>& a_new);

/// h(q, v) = ID(q, v, 0): Coriolis, centrifugal and gravity forces (nv). Writes ws.h (returned).
template <typename T>
const VectorX<T>& CalcBiasForces(const Model<T>& model,
                                 Workspace<T>& ws,
                                 const VectorXcRef<T>& q,
                                 const VectorXcRef<T>& v);

/// M(q) (nv × nv, symmetric) so that ID(q, v, a) = M(q)·a + h(q, v). Writes ws.M (returned) and
/// the composite inertias ws.Ic_Bo_B.
template <typename T>
const MatrixX<T>& CalcMassMatrix(const Model<T>& model, Workspace<T>& ws, const VectorXcRef<T>& q);

/// The root residual of the last CalcInverseDynamics as a wrench at the whole-body centre of mass
/// in W (DESIGN.md: F1..F6), and normalised: force / (m·|g|), moment / (m·|g|·height).
template <typename T>
struct RootResidual {
  SpatialForce<T> F_Scm_W;              ///< moment about the centre of mass (N·m), force (N), in W
  Vector3<T> force_per_weight;          ///< force / (m |g|), dimensionless
  Vector3<T> moment_per_weight_height;  ///< moment / (m |g| height), dimensionless
};

/// Reads the root wrench and the relative poses that CalcInverseDynamics left in ws; the centre of
/// mass comes from the subtrees' mass moments in their own frames (ws.mc_Bo_B), so the world
/// poses are neither needed nor completed. height_m > 0 is the athlete's stature; |g| comes from
/// the model (and must not be zero).
template <typename T>
RootResidual<T> CalcRootResidual(const Model<T>& model, Workspace<T>& ws, const T& height_m);

/// Normalises a wrench at the centre of mass: force / (m g), moment / (m g height).
template <typename T>
void NormalizeByBodyWeight(const SpatialForce<T>& F_Scm_W,
                           const T& mass_kg,
                           const T& gravity_mps2,
                           const T& height_m,
                           Vector3<T>& force_per_weight,
                           Vector3<T>& moment_per_weight_height);

/// Root accelerations of a body in flight: given the joint accelerations a[6:] (the root part of
/// a is overwritten), the root accelerations a[0:6] for which the root residual vanishes, so that
/// gravity and F_ext_Bo_W are the only external wrenches. One inverse dynamics pass plus the
/// whole-body composite inertia Ic about the root: Ic·ΔA = −F_root (RBDA ch. 9, floating bases).
/// ws is left with that pass (zero root acceleration) and with the composite inertias.
template <typename T>
void CalcFlightRootAcceleration(const Model<T>& model,
                                Workspace<T>& ws,
                                const VectorXcRef<T>& q,
                                const VectorXcRef<T>& v,
                                VectorXRef<T> a,
                                const std::vector<SpatialForce<T>>* F_ext_Bo_W = nullptr);

// ---------------------------------------------------------------------------------------------
// Implementation.

namespace internal {

/// RNEA (RBDA Table 5.1) with a = nullptr meaning zero accelerations; writes ws.tau. One fused
/// forward pass (pose, velocity, acceleration and net force of each segment) and one backward
/// pass. With reuse_poses the relative poses and joint axes already in ws are used (q is then
/// not read).
template <typename T>
void Rnea(const Model<T>& model,
          Workspace<T>& ws,
          const VectorXcRef<T>& q,
          const VectorXcRef<T>& v,
          const T* a,
          const std::vector<SpatialForce<T>>* F_ext_Bo_W,
          VectorX<T>& tau,
          bool reuse_poses = false) {
  ACRO_DEMAND(q.size() == model.nq() && v.size() == model.nv() && tau.size() == model.nv());
  ACRO_DEMAND(ws.IsFor(model));
  ACRO_DEMAND(!reuse_poses || ws.poses_current);
  const int n = model.num_segments();
  // Net force on segment i, f_B = I A + V ×* I V − f_ext (RBDA Table 5.1).
  auto net_force = [&](int i) {
    const size_t ui = static_cast<size_t>(i);
    const SpatialInertia<T>& I = model.segment(i).M_Bo_B;
    const SpatialMotion<T>& V = ws.V_WB_B[ui];
    ws.F_Bo_B[ui] = I * ws.A_WB_B[ui] + V.CrossForce(I * V);
    if (F_ext_Bo_W != nullptr) {
      const SpatialForce<T>& Fe = (*F_ext_Bo_W)[ui];
      const Matrix3<T>& R = ws.X_WB[ui].rotation();
      ws.F_Bo_B[ui] -=
          SpatialForce<T>(R.transpose() * Fe.rotational(), R.transpose() * Fe.translational());
    }
  };
  // Root: pose, velocity, and acceleration with the base accelerating at −g (RBDA ch. 5).
  {
    if (!reuse_poses) {
      CalcJointSinCos(model, ws, q);
      CalcJointPose(model.segment(0), q, ws, ws.X_PB[0], ws.S_B[0]);
    }
    ws.X_WB[0] = ws.X_PB[0];
    ws.V_WB_B[0] = RootVelocity(ws.X_WB[0], v);
    ws.A_WB_B[0] = RootAcceleration(ws.X_WB[0], ws.V_WB_B[0], a, model.gravity_W());
    net_force(0);
  }
  // Forward pass (RBDA Table 5.1).
  for (int i = 1; i < n; ++i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const size_t up = static_cast<size_t>(seg.parent);
    if (!reuse_poses) CalcJointPose(seg, q, ws, ws.X_PB[ui], ws.S_B[ui]);
    // World poses only where applied wrenches need them (CalcForwardKinematics composes them for
    // the callers that want them).
    if (F_ext_Bo_W != nullptr) ws.X_WB[ui] = ws.X_WB[up] * ws.X_PB[ui];
    PropagateMotion(seg,
                    ws.X_PB[ui],
                    ws.S_B[ui],
                    ws.V_WB_B[up],
                    ws.A_WB_B[up],
                    v,
                    a,
                    ws.V_WB_B[ui],
                    ws.A_WB_B[ui]);
    net_force(i);
  }
  // Backward pass: τ_k = S_kᵀ f_B and f_P += X_PB* f_B (RBDA Table 5.1).
  for (int i = n - 1; i > 0; --i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const SpatialForce<T>& F = ws.F_Bo_B[ui];
    for (int k = 0; k < seg.num_axes; ++k)
      tau[seg.v_start + k] = ws.S_B[ui][static_cast<size_t>(k)].dot(F.rotational());
    ws.F_Bo_B[static_cast<size_t>(seg.parent)] += ws.X_PB[ui].Apply(F);
  }
  // Root: the generalised forces of v_WBo_W (force in W) and w_WB_B (moment about Bo in B).
  tau.template head<3>() = ws.X_WB[0].rotation() * ws.F_Bo_B[0].translational();
  tau.template segment<3>(3) = ws.F_Bo_B[0].rotational();
  ws.world_poses_current = F_ext_Bo_W != nullptr;
  ws.poses_current = true;
  ws.plain_inverse_dynamics_current = F_ext_Bo_W == nullptr;
}

/// Column k of the root's motion subspace in B: v_WBo_W e_k ↦ [0; R_WBᵀ e_k], w_WB_B e_k ↦ [e_k;
/// 0].
template <typename T>
SpatialMotion<T> RootMotionColumn(const Matrix3<T>& R_WB, int k) {
  if (k < 3) return SpatialMotion<T>(Vector3<T>::Zero(), R_WB.row(k).transpose());
  return SpatialMotion<T>(Vector3<T>::Unit(k - 3), Vector3<T>::Zero());
}

}  // namespace internal

template <typename T>
const VectorX<T>& CalcInverseDynamics(const Model<T>& model,
                                      Workspace<T>& ws,
                                      const VectorXcRef<T>& q,
                                      const VectorXcRef<T>& v,
                                      const VectorXcRef<T>& a,
                                      const std::vector<SpatialForce<T>>* F_ext_Bo_W) {
  ACRO_DEMAND(a.size() == model.nv());
  ACRO_DEMAND(F_ext_Bo_W == nullptr ||
              F_ext_Bo_W->size() == static_cast<size_t>(model.num_segments()));
  internal::Rnea(model, ws, q, v, a.data(), F_ext_Bo_W, ws.tau);
  return ws.tau;
}

template <typename T>
const VectorX<T>& CalcInverseDynamicsAtSameConfiguration(const Model<T>& model,
                                                         Workspace<T>& ws,
                                                         const VectorXcRef<T>& v,
                                                         const VectorXcRef<T>& a) {
  ACRO_DEMAND(a.size() == model.nv());
  // q is not read when the poses are reused; sin_q has the configuration's size.
  internal::Rnea<T>(model, ws, ws.sin_q, v, a.data(), nullptr, ws.tau, true);
  return ws.tau;
}

template <typename T>
SpatialForce<T> CalcRootWrenchWithJointChanged(const Model<T>& model,
                                               Workspace<T>& ws,
                                               int segment,
                                               const VectorXcRef<T>& v_new,
                                               const VectorXcRef<T>& a_new) {
  const int n = model.num_segments();
  ACRO_DEMAND(segment > 0 && segment < n);
  ACRO_DEMAND(v_new.size() == model.nv() && a_new.size() == model.nv() && ws.IsFor(model));
  ACRO_DEMAND(ws.plain_inverse_dynamics_current);
  // The subtree: segments are in topological order, so its members follow `segment`.
  for (int i = segment; i < n; ++i) {
    const int p = model.segment(i).parent;
    ws.in_changed_subtree[static_cast<size_t>(i)] =
        i == segment || (p >= segment && ws.in_changed_subtree[static_cast<size_t>(p)]) ? 1 : 0;
  }
  auto changed = [&](int i) { return ws.in_changed_subtree[static_cast<size_t>(i)] != 0; };
  // Forward: motion and net force of each subtree segment from its parent's (the last pass's
  // outside the subtree), as in Rnea.
  for (int i = segment; i < n; ++i) {
    if (!changed(i)) continue;
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const size_t up = static_cast<size_t>(seg.parent);
    const bool parent_changed = i != segment;
    internal::PropagateMotion(seg,
                              ws.X_PB[ui],
                              ws.S_B[ui],
                              parent_changed ? ws.V_changed[up] : ws.V_WB_B[up],
                              parent_changed ? ws.A_changed[up] : ws.A_WB_B[up],
                              v_new,
                              a_new.data(),
                              ws.V_changed[ui],
                              ws.A_changed[ui]);
    const SpatialInertia<T>& I = seg.M_Bo_B;
    const SpatialMotion<T>& V = ws.V_changed[ui];
    ws.F_changed[ui] = I * ws.A_changed[ui] + V.CrossForce(I * V);
  }
  // Backward inside the subtree, then the change of the subtree's wrench carried to the root.
  for (int i = n - 1; i > segment; --i)
    if (changed(i))
      ws.F_changed[static_cast<size_t>(model.segment(i).parent)] +=
          ws.X_PB[static_cast<size_t>(i)].Apply(ws.F_changed[static_cast<size_t>(i)]);
  const size_t us = static_cast<size_t>(segment);
  SpatialForce<T> dF = ws.F_changed[us] - ws.F_Bo_B[us];
  for (int j = segment; model.segment(j).parent >= 0; j = model.segment(j).parent)
    dF = ws.X_PB[static_cast<size_t>(j)].Apply(dF);
  return ws.F_Bo_B[0] + dF;
}

template <typename T>
const VectorX<T>& CalcBiasForces(const Model<T>& model,
                                 Workspace<T>& ws,
                                 const VectorXcRef<T>& q,
                                 const VectorXcRef<T>& v) {
  internal::Rnea<T>(model, ws, q, v, nullptr, nullptr, ws.h);
  return ws.h;
}

template <typename T>
const MatrixX<T>& CalcMassMatrix(const Model<T>& model, Workspace<T>& ws, const VectorXcRef<T>& q) {
  const int n = model.num_segments();
  CalcForwardKinematics(model, ws, q);
  // Composite inertias: Ic_P += X_PB* Ic_B X_BP (RBDA Table 6.2).
  for (int i = 0; i < n; ++i) ws.Ic_Bo_B[static_cast<size_t>(i)] = model.segment(i).M_Bo_B;
  for (int i = n - 1; i > 0; --i) {
    const size_t ui = static_cast<size_t>(i);
    ws.Ic_Bo_B[static_cast<size_t>(model.segment(i).parent)] += ws.X_PB[ui].Apply(ws.Ic_Bo_B[ui]);
  }
  MatrixX<T>& M = ws.M;
  const Matrix3<T>& R0 = ws.X_WB[0].rotation();
  // Projects the spatial force F (in the frame of segment j) on joint j's motion subspace and
  // writes the entries M(v_j + l, col) and their symmetric twins.
  auto project = [&](int j, const SpatialForce<T>& F, int col) {
    const Segment<T>& seg = model.segment(j);
    if (seg.joint_type == JointType::kFree) {
      const Vector3<T> f_W = R0 * F.translational();
      for (int l = 0; l < 3; ++l) {
        M(l, col) = f_W[l];
        M(col, l) = f_W[l];
        M(3 + l, col) = F.rotational()[l];
        M(col, 3 + l) = F.rotational()[l];
      }
      return;
    }
    for (int l = 0; l < seg.num_axes; ++l) {
      const T m = ws.S_B[static_cast<size_t>(j)][static_cast<size_t>(l)].dot(F.rotational());
      M(seg.v_start + l, col) = m;
      M(col, seg.v_start + l) = m;
    }
  };
  // Each motion-subspace column s of segment i: F = Ic_i s, then F is carried inboard and
  // projected on every ancestor joint (RBDA Table 6.2, inner loop).
  for (int i = n - 1; i >= 0; --i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const int ncols = seg.joint_type == JointType::kFree ? 6 : seg.num_axes;
    for (int k = 0; k < ncols; ++k) {
      SpatialForce<T> F = seg.joint_type == JointType::kFree
                              ? ws.Ic_Bo_B[ui] * internal::RootMotionColumn(R0, k)
                              : ws.Ic_Bo_B[ui].MultiplyRotation(ws.S_B[ui][static_cast<size_t>(k)]);
      const int col = seg.v_start + k;
      project(i, F, col);
      for (int j = i; model.segment(j).parent >= 0; j = model.segment(j).parent) {
        F = ws.X_PB[static_cast<size_t>(j)].Apply(F);
        project(model.segment(j).parent, F, col);
      }
    }
  }
  return M;
}

template <typename T>
void NormalizeByBodyWeight(const SpatialForce<T>& F_Scm_W,
                           const T& mass_kg,
                           const T& gravity_mps2,
                           const T& height_m,
                           Vector3<T>& force_per_weight,
                           Vector3<T>& moment_per_weight_height) {
  ACRO_DEMAND(mass_kg > T(0) && gravity_mps2 > T(0) && height_m > T(0));
  const T weight = mass_kg * gravity_mps2;
  force_per_weight = F_Scm_W.translational() / weight;
  moment_per_weight_height = F_Scm_W.rotational() / (weight * height_m);
}

template <typename T>
RootResidual<T> CalcRootResidual(const Model<T>& model, Workspace<T>& ws, const T& height_m) {
  // The centre of mass in the root frame, p_BoScm_B = h_0 / m, from the subtrees' first mass
  // moments about their own origins: h_P += m_B p_PoBo_P + R_PB h_B (one rotation per segment
  // instead of composing every world pose).
  const int n = model.num_segments();
  for (int i = 0; i < n; ++i) {
    const size_t ui = static_cast<size_t>(i);
    ws.subtree_mass[ui] = model.segment(i).mass;
    ws.mc_Bo_B[ui] = model.segment(i).mass * model.segment(i).p_BoBcm_B;
  }
  for (int i = n - 1; i > 0; --i) {
    const size_t ui = static_cast<size_t>(i);
    const size_t up = static_cast<size_t>(model.segment(i).parent);
    const RigidTransform<T>& X_PB = ws.X_PB[ui];
    ws.mc_Bo_B[up] += ws.subtree_mass[ui] * X_PB.translation() + X_PB.rotation() * ws.mc_Bo_B[ui];
    ws.subtree_mass[up] += ws.subtree_mass[ui];
  }
  const Vector3<T> p_BoScm_B = ws.mc_Bo_B[0] / model.total_mass();
  // The root wrench about Bo in B, shifted to the centre of mass and re-expressed in W:
  // n_Scm = R (n_Bo − p_BoScm × f), f_W = R f_B.
  const Matrix3<T>& R_WB = ws.X_PB[0].rotation();
  const SpatialForce<T> F_Scm_B = ws.F_Bo_B[0].Shift(p_BoScm_B);
  RootResidual<T> out;
  out.F_Scm_W = SpatialForce<T>(R_WB * F_Scm_B.rotational(), R_WB * F_Scm_B.translational());
  NormalizeByBodyWeight(out.F_Scm_W,
                        model.total_mass(),
                        T(model.gravity_W().norm()),
                        height_m,
                        out.force_per_weight,
                        out.moment_per_weight_height);
  return out;
}

template <typename T>
void CalcFlightRootAcceleration(const Model<T>& model,
                                Workspace<T>& ws,
                                const VectorXcRef<T>& q,
                                const VectorXcRef<T>& v,
                                VectorXRef<T> a,
                                const std::vector<SpatialForce<T>>* F_ext_Bo_W) {
  ACRO_DEMAND(a.size() == model.nv());
  // Root residual F0 with zero root acceleration.
  a.template head<6>().setZero();
  internal::Rnea(model, ws, q, v, a.data(), F_ext_Bo_W, ws.tau);
  // Whole-body composite inertia about Bo in B.
  const int n = model.num_segments();
  for (int i = 0; i < n; ++i) ws.Ic_Bo_B[static_cast<size_t>(i)] = model.segment(i).M_Bo_B;
  for (int i = n - 1; i > 0; --i) {
    const size_t ui = static_cast<size_t>(i);
    ws.Ic_Bo_B[static_cast<size_t>(model.segment(i).parent)] += ws.X_PB[ui].Apply(ws.Ic_Bo_B[ui]);
  }
  // A change ΔA of the root's spatial acceleration changes the root wrench by Ic·ΔA; choose it
  // to cancel F0. Then ẇ_WB_B = ΔA_ω and a_WBo_W = R_WB ΔA_v.
  const Matrix6<T> Ic = ws.Ic_Bo_B[0].ToMatrix();
  const Vector6<T> dA = Ic.ldlt().solve(-ws.F_Bo_B[0].get_coeffs());
  a.template head<3>() = ws.X_WB[0].rotation() * dA.template tail<3>();
  a.template segment<3>(3) = dA.template head<3>();
}

// Explicit instantiations for double live in src/inverse_dynamics.cc.
extern template const VectorX<double>& CalcInverseDynamics<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const std::vector<SpatialForce<double>>*);
extern template const VectorX<double>& CalcInverseDynamicsAtSameConfiguration<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
extern template SpatialForce<double> CalcRootWrenchWithJointChanged<double>(
    const Model<double>&,
    Workspace<double>&,
    int,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
extern template const VectorX<double>& CalcBiasForces<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
extern template const MatrixX<double>& CalcMassMatrix<double>(
    const Model<double>&, Workspace<double>&, const Eigen::Ref<const VectorX<double>>&);
extern template RootResidual<double> CalcRootResidual<double>(const Model<double>&,
                                                              Workspace<double>&,
                                                              const double&);
extern template void CalcFlightRootAcceleration<double>(const Model<double>&,
                                                        Workspace<double>&,
                                                        const Eigen::Ref<const VectorX<double>>&,
                                                        const Eigen::Ref<const VectorX<double>>&,
                                                        Eigen::Ref<VectorX<double>>,
                                                        const std::vector<SpatialForce<double>>*);

}  // namespace acro::dynamics
