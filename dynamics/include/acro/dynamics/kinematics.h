#pragma once

// Forward kinematics, point and segment Jacobians, centre of mass and centroidal momentum.
// Free functions over (const Model, Workspace, q, v, a); none allocates. Call
// CalcForwardKinematics first: the other functions read the poses (and velocities) it leaves in
// the workspace, and demand ws.world_poses_current (inverse dynamics without applied wrenches
// leaves only the root's world pose). Conventions: docs/notation.md.

#include <cmath>

#include "acro/dynamics/configuration.h"
#include "acro/dynamics/fast_math.h"
#include "acro/dynamics/model.h"
#include "acro/dynamics/workspace.h"

namespace acro::dynamics {

/// Segment poses: fills X_PB, X_WB and the joint axes S_B.
template <typename T>
void CalcForwardKinematics(const Model<T>& model, Workspace<T>& ws, const VectorXcRef<T>& q);

/// Segment poses and spatial velocities: also fills V_WB_B.
template <typename T>
void CalcForwardKinematics(const Model<T>& model,
                           Workspace<T>& ws,
                           const VectorXcRef<T>& q,
                           const VectorXcRef<T>& v);

/// p_WoP_W of named point `point` (after CalcForwardKinematics with q).
template <typename T>
Vector3<T> CalcPointPosition(const Model<T>& model, const Workspace<T>& ws, int point);

/// v_WP_W of named point `point` (after CalcForwardKinematics with q and v).
template <typename T>
Vector3<T> CalcPointVelocity(const Model<T>& model, const Workspace<T>& ws, int point);

/// V_WB_W: angular velocity of segment B in W and velocity of Bo, both expressed in W.
template <typename T>
SpatialMotion<T> CalcSegmentSpatialVelocity(const Workspace<T>& ws, int segment);

/// Jv_WQ_W (3 × nv): v_WQ_W = J·v for the point Q fixed in `segment` at p_BoQ_B.
template <typename T>
void CalcPointJacobian(const Model<T>& model,
                       const Workspace<T>& ws,
                       int segment,
                       const Vector3<T>& p_BoQ_B,
                       Matrix3XRef<T> J);

/// Jv_WP_W (3 × nv) of named point `point`.
template <typename T>
void CalcPointJacobian(const Model<T>& model, const Workspace<T>& ws, int point, Matrix3XRef<T> J);

/// J_WB_W (6 × nv): V_WB_W = J·v, rows [w_WB_W; v_WBo_W].
template <typename T>
void CalcSegmentJacobian(const Model<T>& model,
                         const Workspace<T>& ws,
                         int segment,
                         Matrix6XRef<T> J);

/// Jv_WScm_W (3 × nv): v_WScm_W = J·v, the mass-weighted mean of the segments' centre-of-mass
/// Jacobians (after CalcForwardKinematics with q).
template <typename T>
void CalcCenterOfMassJacobian(const Model<T>& model, const Workspace<T>& ws, Matrix3XRef<T> J);

/// p_WoScm_W: the whole-body (system S) centre of mass (after CalcForwardKinematics with q).
template <typename T>
Vector3<T> CalcCenterOfMassPosition(const Model<T>& model, const Workspace<T>& ws);

/// v_WScm_W (after CalcForwardKinematics with q and v).
template <typename T>
Vector3<T> CalcCenterOfMassVelocity(const Model<T>& model, const Workspace<T>& ws);

/// a_WScm_W for generalised accelerations a (computes the kinematics itself; overwrites the
/// workspace's poses, velocities and accelerations).
template <typename T>
Vector3<T> CalcCenterOfMassAcceleration(const Model<T>& model,
                                        Workspace<T>& ws,
                                        const VectorXcRef<T>& q,
                                        const VectorXcRef<T>& v,
                                        const VectorXcRef<T>& a);

/// L_WScm_W: the system's angular momentum about its centre of mass and its linear momentum, in
/// W (after CalcForwardKinematics with q and v).
template <typename T>
SpatialMomentum<T> CalcCentroidalMomentum(const Model<T>& model, const Workspace<T>& ws);

// ---------------------------------------------------------------------------------------------
// Implementation.

namespace internal {

/// R ← R_axis(c, s)·R: rotates rows (i, j) of R, the pair following `axis` cyclically.
template <typename T>
inline void LeftMultiplyAxisRotation(int axis, const T& c, const T& s, Matrix3<T>& R) {
  const int i = (axis + 1) % 3;
  const int j = (axis + 2) % 3;
  for (int col = 0; col < 3; ++col) {
    const T ri = R(i, col);
    const T rj = R(j, col);
    R(i, col) = c * ri - s * rj;
    R(j, col) = s * ri + c * rj;
  }
}

/// Pose of segment i in its parent and its joint axes in B, from q.
///   Euler joint: R_PB = R_PJ·R_a1(θ1)·R_a2(θ2)·R_a3(θ3), p_PoBo_P = p_PoJo_P. The angular velocity
///   of B in P, in B, is Σ_k S_k θ̇_k with S_k = (R_a(k+1)⋯R_an)ᵀ e_ak (RBDA ch. 4, joint models, a
///   chain of revolute joints whose intermediate frames carry no mass).
/// sin and cos of every joint angle into ws.sin_q, ws.cos_q, in one loop of independent
/// iterations (so that they overlap in the processor's pipeline).
template <typename T>
inline void CalcJointSinCos(const Model<T>& model, Workspace<T>& ws, const VectorXcRef<T>& q) {
  SinCosArray(q.data() + 7, model.nq() - 7, ws.sin_q.data() + 7, ws.cos_q.data() + 7);
}

/// Pose of segment i in its parent and its joint axes in B, from q (and the joint angles' sines
/// and cosines from CalcJointSinCos).
template <typename T>
inline void CalcJointPose(const Segment<T>& seg,
                          const VectorXcRef<T>& q,
                          const Workspace<T>& ws,
                          RigidTransform<T>& X_PB,
                          std::array<Vector3<T>, 3>& S) {
  if (seg.joint_type == JointType::kFree) {
    X_PB.mutable_rotation() = QuaternionToRotation<T>(q[3], q[4], q[5], q[6]);
    X_PB.mutable_translation() = q.template head<3>();
    return;
  }
  Matrix3<T>& G = X_PB.mutable_rotation();
  if (seg.num_axes == 0) {
    G = seg.X_PJ.rotation();
    X_PB.mutable_translation() = seg.X_PJ.translation();
    return;
  }
  // Last axis first: G = R_an(θn), S_n = e_an; then G ← R_ak G with S_k = row a_k of G.
  const int last = seg.num_axes - 1;
  {
    const T& s = ws.sin_q[seg.q_start + last];
    const T& c = ws.cos_q[seg.q_start + last];
    const int axis = seg.axes[static_cast<size_t>(last)];
    const int i = (axis + 1) % 3;
    const int j = (axis + 2) % 3;
    G.setIdentity();
    G(i, i) = c;
    G(i, j) = -s;
    G(j, i) = s;
    G(j, j) = c;
    S[static_cast<size_t>(last)] = Vector3<T>::Unit(axis);
  }
  for (int k = last - 1; k >= 0; --k) {
    const int axis = seg.axes[static_cast<size_t>(k)];
    S[static_cast<size_t>(k)] = G.row(axis).transpose();
    LeftMultiplyAxisRotation(axis, ws.cos_q[seg.q_start + k], ws.sin_q[seg.q_start + k], G);
  }
  if (!seg.joint_rotation_is_identity) G = seg.X_PJ.rotation() * G.eval();
  X_PB.mutable_translation() = seg.X_PJ.translation();
}

/// Angular velocity of B relative to its parent, in B: ω_J = Σ S_k θ̇_k.
template <typename T>
inline Vector3<T> JointAngularVelocity(const Segment<T>& seg,
                                       const std::array<Vector3<T>, 3>& S,
                                       const VectorXcRef<T>& v) {
  Vector3<T> w = Vector3<T>::Zero();
  for (int k = 0; k < seg.num_axes; ++k) w += S[static_cast<size_t>(k)] * v[seg.v_start + k];
  return w;
}

/// Root spatial velocity about Bo in B: [w_WB_B; R_WBᵀ v_WBo_W].
template <typename T>
inline SpatialMotion<T> RootVelocity(const RigidTransform<T>& X_WB, const VectorXcRef<T>& v) {
  return SpatialMotion<T>(v.template segment<3>(3),
                          X_WB.rotation().transpose() * v.template head<3>());
}

/// X_WB of every segment from X_PB (after a pose pass).
template <typename T>
inline void ComposeWorldPoses(const Model<T>& model, Workspace<T>& ws) {
  ws.X_WB[0] = ws.X_PB[0];
  for (int i = 1; i < model.num_segments(); ++i) {
    const size_t ui = static_cast<size_t>(i);
    ws.X_WB[ui] = ws.X_WB[static_cast<size_t>(model.segment(i).parent)] * ws.X_PB[ui];
  }
  ws.world_poses_current = true;
  ws.poses_current = true;
  ws.plain_inverse_dynamics_current = false;
}

/// Root spatial acceleration about Bo in B with the base accelerating at −g_extra (RBDA ch. 5's
/// fictitious base acceleration when g_extra = gravity; the true acceleration when zero):
///   A = [ẇ_WB_B; R_WBᵀ(a_WBo_W − g_extra) − w × R_WBᵀ v_WBo_W]
/// (the linear part of a spatial acceleration is the classical one minus ω × v, RBDA ch. 2).
template <typename T>
inline SpatialMotion<T> RootAcceleration(const RigidTransform<T>& X_WB,
                                         const SpatialMotion<T>& V,
                                         const T* a,
                                         const Vector3<T>& g_extra) {
  Vector3<T> a_lin = -g_extra;
  Vector3<T> w_dot = Vector3<T>::Zero();
  if (a != nullptr) {
    a_lin += Vector3<T>(a[0], a[1], a[2]);
    w_dot = Vector3<T>(a[3], a[4], a[5]);
  }
  return SpatialMotion<T>(
      w_dot, X_WB.rotation().transpose() * a_lin - V.rotational().cross(V.translational()));
}

/// Velocity and acceleration of a non-root segment from its parent's (a = nullptr: zero):
///   V_B = X_BP V_P + [ω_J; 0]
///   A_B = X_BP A_P + [S θ̈ + c_J; 0] + V_B × [ω_J; 0]
/// (RBDA Table 5.1; c_J = S̊ θ̇ = Σ_k (Σ_{j<k} S_j θ̇_j) × S_k θ̇_k for the chain of revolute axes).
template <typename T>
inline void PropagateMotion(const Segment<T>& seg,
                            const RigidTransform<T>& X_PB,
                            const std::array<Vector3<T>, 3>& S,
                            const SpatialMotion<T>& V_P,
                            const SpatialMotion<T>& A_P,
                            const VectorXcRef<T>& v,
                            const T* a,
                            SpatialMotion<T>& V_B,
                            SpatialMotion<T>& A_B) {
  V_B = X_PB.ApplyInverse(V_P);
  A_B = X_PB.ApplyInverse(A_P);
  if (seg.num_axes == 0) return;
  Vector3<T> w_J = S[0] * v[seg.v_start];
  Vector3<T> alpha = Vector3<T>::Zero();
  if (a != nullptr) alpha = S[0] * a[seg.v_start];
  for (int k = 1; k < seg.num_axes; ++k) {
    const Vector3<T> wk = S[static_cast<size_t>(k)] * v[seg.v_start + k];
    alpha += w_J.cross(wk);
    if (a != nullptr) alpha += S[static_cast<size_t>(k)] * a[seg.v_start + k];
    w_J += wk;
  }
  V_B.mutable_rotational() += w_J;
  A_B.mutable_rotational() += alpha + V_B.rotational().cross(w_J);
  A_B.mutable_translational() += V_B.translational().cross(w_J);
}

/// Spatial accelerations of all segments, about Bo in B, given poses and velocities in ws and
/// generalised accelerations a (nullptr: zero), the base accelerating at −g_extra.
template <typename T>
inline void CalcAccelerations(const Model<T>& model,
                              Workspace<T>& ws,
                              const VectorXcRef<T>& v,
                              const T* a,
                              const Vector3<T>& g_extra) {
  ws.A_WB_B[0] = RootAcceleration(ws.X_WB[0], ws.V_WB_B[0], a, g_extra);
  SpatialMotion<T> V;
  for (int i = 1; i < model.num_segments(); ++i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const size_t up = static_cast<size_t>(seg.parent);
    PropagateMotion(
        seg, ws.X_PB[ui], ws.S_B[ui], ws.V_WB_B[up], ws.A_WB_B[up], v, a, V, ws.A_WB_B[ui]);
  }
}

}  // namespace internal

template <typename T>
void CalcForwardKinematics(const Model<T>& model, Workspace<T>& ws, const VectorXcRef<T>& q) {
  ACRO_DEMAND(q.size() == model.nq());
  ACRO_DEMAND(ws.IsFor(model));
  internal::CalcJointSinCos(model, ws, q);
  internal::CalcJointPose(model.segment(0), q, ws, ws.X_PB[0], ws.S_B[0]);
  ws.X_WB[0] = ws.X_PB[0];
  for (int i = 1; i < model.num_segments(); ++i) {
    const size_t ui = static_cast<size_t>(i);
    internal::CalcJointPose(model.segment(i), q, ws, ws.X_PB[ui], ws.S_B[ui]);
    ws.X_WB[ui] = ws.X_WB[static_cast<size_t>(model.segment(i).parent)] * ws.X_PB[ui];
  }
  ws.world_poses_current = true;
  ws.poses_current = true;
  ws.plain_inverse_dynamics_current = false;
}

template <typename T>
void CalcForwardKinematics(const Model<T>& model,
                           Workspace<T>& ws,
                           const VectorXcRef<T>& q,
                           const VectorXcRef<T>& v) {
  ACRO_DEMAND(v.size() == model.nv());
  CalcForwardKinematics(model, ws, q);
  // V_B = X_BP V_P + [ω_J; 0] (RBDA Table 5.1).
  ws.V_WB_B[0] = internal::RootVelocity(ws.X_WB[0], v);
  for (int i = 1; i < model.num_segments(); ++i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    SpatialMotion<T> V = ws.X_PB[ui].ApplyInverse(ws.V_WB_B[static_cast<size_t>(seg.parent)]);
    if (seg.num_axes > 0)
      V.mutable_rotational() += internal::JointAngularVelocity(seg, ws.S_B[ui], v);
    ws.V_WB_B[ui] = V;
  }
}

template <typename T>
Vector3<T> CalcPointPosition(const Model<T>& model, const Workspace<T>& ws, int point) {
  ACRO_DEMAND(ws.world_poses_current);
  const Point<T>& p = model.point(point);
  return ws.X_WB[static_cast<size_t>(p.segment)] * p.p_BoP_B;
}

template <typename T>
Vector3<T> CalcPointVelocity(const Model<T>& model, const Workspace<T>& ws, int point) {
  ACRO_DEMAND(ws.world_poses_current);
  const Point<T>& p = model.point(point);
  const size_t s = static_cast<size_t>(p.segment);
  const SpatialMotion<T>& V = ws.V_WB_B[s];
  // v_WP = R_WB (v_WBo_B + w_WB_B × p_BoP_B).
  return ws.X_WB[s].rotation() * (V.translational() + V.rotational().cross(p.p_BoP_B));
}

template <typename T>
SpatialMotion<T> CalcSegmentSpatialVelocity(const Workspace<T>& ws, int segment) {
  ACRO_DEMAND(ws.world_poses_current);
  const size_t s = static_cast<size_t>(segment);
  const Matrix3<T>& R = ws.X_WB[s].rotation();
  return SpatialMotion<T>(R * ws.V_WB_B[s].rotational(), R * ws.V_WB_B[s].translational());
}

namespace internal {

/// Columns of the 6 × nv Jacobian of the frame whose origin is Q (fixed in `segment`, at
/// p_WoQ_W): rows [ω; v_Q] in W. Each joint axis u (in W, through the joint centre Jo) adds
/// [u; u × (p_WoQ_W − p_WoJo_W)]; the root adds [0; I] for v_WBo_W and
/// [R_WB; −[p_WoQ_W − p_WoBo_W]× R_WB] for w_WB_B.
template <typename T, typename AngularRows, typename LinearRows>
void AccumulateJacobian(const Model<T>& model,
                        const Workspace<T>& ws,
                        int segment,
                        const Vector3<T>& p_WoQ_W,
                        AngularRows* J_w,
                        LinearRows& J_v) {
  ACRO_DEMAND(ws.world_poses_current);
  for (int j = segment; j >= 0; j = model.segment(j).parent) {
    const Segment<T>& seg = model.segment(j);
    const size_t uj = static_cast<size_t>(j);
    const Matrix3<T>& R = ws.X_WB[uj].rotation();
    const Vector3<T> r = p_WoQ_W - ws.X_WB[uj].translation();
    if (seg.joint_type == JointType::kFree) {
      J_v.template middleCols<3>(0).setIdentity();
      for (int k = 0; k < 3; ++k) {
        const Vector3<T> u = R.col(k);
        if (J_w) J_w->col(3 + k) = u;
        J_v.col(3 + k) = u.cross(r);
      }
      continue;
    }
    for (int k = 0; k < seg.num_axes; ++k) {
      const Vector3<T> u = R * ws.S_B[uj][static_cast<size_t>(k)];
      if (J_w) J_w->col(seg.v_start + k) = u;
      J_v.col(seg.v_start + k) = u.cross(r);
    }
  }
}

}  // namespace internal

template <typename T>
void CalcPointJacobian(const Model<T>& model,
                       const Workspace<T>& ws,
                       int segment,
                       const Vector3<T>& p_BoQ_B,
                       Matrix3XRef<T> J) {
  ACRO_DEMAND(J.cols() == model.nv());
  J.setZero();
  const Vector3<T> p_WoQ_W = ws.X_WB[static_cast<size_t>(segment)] * p_BoQ_B;
  Matrix3XRef<T>* no_angular = nullptr;
  internal::AccumulateJacobian(model, ws, segment, p_WoQ_W, no_angular, J);
}

template <typename T>
void CalcPointJacobian(const Model<T>& model, const Workspace<T>& ws, int point, Matrix3XRef<T> J) {
  const Point<T>& p = model.point(point);
  CalcPointJacobian(model, ws, p.segment, p.p_BoP_B, J);
}

template <typename T>
void CalcSegmentJacobian(const Model<T>& model,
                         const Workspace<T>& ws,
                         int segment,
                         Matrix6XRef<T> J) {
  ACRO_DEMAND(J.cols() == model.nv());
  J.setZero();
  auto J_w = J.template topRows<3>();
  auto J_v = J.template bottomRows<3>();
  internal::AccumulateJacobian(
      model, ws, segment, ws.X_WB[static_cast<size_t>(segment)].translation(), &J_w, J_v);
}

template <typename T>
void CalcCenterOfMassJacobian(const Model<T>& model, const Workspace<T>& ws, Matrix3XRef<T> J) {
  ACRO_DEMAND(J.cols() == model.nv());
  ACRO_DEMAND(ws.world_poses_current);
  // Σ_B (m_B / m) Jv_Bcm: each segment adds its weighted centre-of-mass Jacobian columns, one per
  // axis u (through Jo) of its ancestors, u × (p_WoBcm − p_WoJo) (as in AccumulateJacobian).
  J.setZero();
  for (int b = 0; b < model.num_segments(); ++b) {
    const Segment<T>& s = model.segment(b);
    const Vector3<T> p_WoBcm_W = ws.X_WB[static_cast<size_t>(b)] * s.p_BoBcm_B;
    const T w = s.mass / model.total_mass();
    for (int j = b; j >= 0; j = model.segment(j).parent) {
      const Segment<T>& sj = model.segment(j);
      const size_t uj = static_cast<size_t>(j);
      const Matrix3<T>& R = ws.X_WB[uj].rotation();
      const Vector3<T> r = p_WoBcm_W - ws.X_WB[uj].translation();
      if (sj.joint_type == JointType::kFree) {
        for (int k = 0; k < 3; ++k) {
          J(k, k) += w;
          J.col(3 + k) += w * R.col(k).cross(r);
        }
        continue;
      }
      for (int k = 0; k < sj.num_axes; ++k)
        J.col(sj.v_start + k) += w * (R * ws.S_B[uj][static_cast<size_t>(k)]).cross(r);
    }
  }
}

template <typename T>
Vector3<T> CalcCenterOfMassPosition(const Model<T>& model, const Workspace<T>& ws) {
  ACRO_DEMAND(ws.world_poses_current);
  // p_WoScm = Σ m_B p_WoBcm / Σ m_B.
  Vector3<T> sum = Vector3<T>::Zero();
  for (int i = 0; i < model.num_segments(); ++i) {
    const Segment<T>& seg = model.segment(i);
    sum += seg.mass * (ws.X_WB[static_cast<size_t>(i)] * seg.p_BoBcm_B);
  }
  return sum / model.total_mass();
}

template <typename T>
Vector3<T> CalcCenterOfMassVelocity(const Model<T>& model, const Workspace<T>& ws) {
  ACRO_DEMAND(ws.world_poses_current);
  // v_WScm = Σ m_B R_WB (v_WBo_B + w_WB_B × p_BoBcm_B) / Σ m_B.
  Vector3<T> sum = Vector3<T>::Zero();
  for (int i = 0; i < model.num_segments(); ++i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const SpatialMotion<T>& V = ws.V_WB_B[ui];
    sum += seg.mass *
           (ws.X_WB[ui].rotation() * (V.translational() + V.rotational().cross(seg.p_BoBcm_B)));
  }
  return sum / model.total_mass();
}

template <typename T>
Vector3<T> CalcCenterOfMassAcceleration(const Model<T>& model,
                                        Workspace<T>& ws,
                                        const VectorXcRef<T>& q,
                                        const VectorXcRef<T>& v,
                                        const VectorXcRef<T>& a) {
  ACRO_DEMAND(a.size() == model.nv());
  CalcForwardKinematics(model, ws, q, v);
  internal::CalcAccelerations(model, ws, v, a.data(), Vector3<T>::Zero().eval());
  // Classical acceleration of the body-fixed point c from the spatial acceleration [ẇ; a] about
  // Bo: a_c = a + ẇ × c + w × (v + w × c) (RBDA ch. 2, spatial acceleration), then Σ m a_c / Σ m.
  Vector3<T> sum = Vector3<T>::Zero();
  for (int i = 0; i < model.num_segments(); ++i) {
    const Segment<T>& seg = model.segment(i);
    const size_t ui = static_cast<size_t>(i);
    const SpatialMotion<T>& V = ws.V_WB_B[ui];
    const SpatialMotion<T>& A = ws.A_WB_B[ui];
    const Vector3<T>& c = seg.p_BoBcm_B;
    const Vector3<T>& w = V.rotational();
    const Vector3<T> a_c =
        A.translational() + A.rotational().cross(c) + w.cross(V.translational() + w.cross(c));
    sum += seg.mass * (ws.X_WB[ui].rotation() * a_c);
  }
  return sum / model.total_mass();
}

template <typename T>
SpatialMomentum<T> CalcCentroidalMomentum(const Model<T>& model, const Workspace<T>& ws) {
  ACRO_DEMAND(ws.world_poses_current);
  // Σ X_WB (I_B V_B) about Wo in W, then shifted to the centre of mass (RBDA ch. 2, spatial
  // momentum).
  SpatialMomentum<T> L_Wo_W = SpatialMomentum<T>::Zero();
  for (int i = 0; i < model.num_segments(); ++i) {
    const size_t ui = static_cast<size_t>(i);
    L_Wo_W += ws.X_WB[ui].Apply(model.segment(i).M_Bo_B.Momentum(ws.V_WB_B[ui]));
  }
  return L_Wo_W.Shift(CalcCenterOfMassPosition(model, ws));
}

// Explicit instantiations for double live in src/kinematics.cc.
extern template void CalcForwardKinematics<double>(const Model<double>&,
                                                   Workspace<double>&,
                                                   const Eigen::Ref<const VectorX<double>>&);
extern template void CalcForwardKinematics<double>(const Model<double>&,
                                                   Workspace<double>&,
                                                   const Eigen::Ref<const VectorX<double>>&,
                                                   const Eigen::Ref<const VectorX<double>>&);
extern template Vector3<double> CalcPointPosition<double>(const Model<double>&,
                                                          const Workspace<double>&,
                                                          int);
extern template Vector3<double> CalcPointVelocity<double>(const Model<double>&,
                                                          const Workspace<double>&,
                                                          int);
extern template SpatialMotion<double> CalcSegmentSpatialVelocity<double>(const Workspace<double>&,
                                                                         int);
extern template void CalcPointJacobian<double>(const Model<double>&,
                                               const Workspace<double>&,
                                               int,
                                               const Vector3<double>&,
                                               Matrix3XRef<double>);
extern template void CalcPointJacobian<double>(const Model<double>&,
                                               const Workspace<double>&,
                                               int,
                                               Matrix3XRef<double>);
extern template void CalcSegmentJacobian<double>(const Model<double>&,
                                                 const Workspace<double>&,
                                                 int,
                                                 Matrix6XRef<double>);
extern template void CalcCenterOfMassJacobian<double>(const Model<double>&,
                                                      const Workspace<double>&,
                                                      Matrix3XRef<double>);
extern template Vector3<double> CalcCenterOfMassPosition<double>(const Model<double>&,
                                                                 const Workspace<double>&);
extern template Vector3<double> CalcCenterOfMassVelocity<double>(const Model<double>&,
                                                                 const Workspace<double>&);
extern template Vector3<double> CalcCenterOfMassAcceleration<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&);
extern template SpatialMomentum<double> CalcCentroidalMomentum<double>(const Model<double>&,
                                                                       const Workspace<double>&);

}  // namespace acro::dynamics
