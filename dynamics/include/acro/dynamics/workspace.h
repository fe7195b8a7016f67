#pragma once

// Preallocated per-model scratch and results (Pinocchio's "Data", MuJoCo's mjData). Made once
// for a model; every algorithm writes into it and none allocates afterwards. One workspace per
// thread.

#include <array>
#include <vector>

#include "acro/dynamics/model.h"

namespace acro::dynamics {

template <typename T>
struct Workspace {
  explicit Workspace(const Model<T>& model)
      : X_PB(Size(model)),
        X_WB(Size(model)),
        S_B(Size(model)),
        V_WB_B(Size(model)),
        A_WB_B(Size(model)),
        F_Bo_B(Size(model)),
        Ic_Bo_B(Size(model)),
        mc_Bo_B(Size(model)),
        subtree_mass(Size(model)),
        V_changed(Size(model)),
        A_changed(Size(model)),
        F_changed(Size(model)),
        in_changed_subtree(Size(model), 0),
        tau(model.nv()),
        M(model.nv(), model.nv()),
        h(model.nv()),
        sin_q(model.nq()),
        cos_q(model.nq()) {
    tau.setZero();
    M.setZero();
    h.setZero();
    sin_q.setZero();
    cos_q.setZero();
  }

  /// True when this workspace was sized for a model of this shape (checked by the algorithms).
  bool IsFor(const Model<T>& model) const {
    return X_PB.size() == Size(model) && tau.size() == model.nv() && sin_q.size() == model.nq();
  }

  // Position kinematics (CalcForwardKinematics with q).
  std::vector<RigidTransform<T>> X_PB;  ///< segment B in its parent P (the root: in W)
  std::vector<RigidTransform<T>> X_WB;  ///< segment B in the world W
  /// False after an inverse dynamics without applied wrenches, which computes only X_WB[0]
  /// (the rest is not needed there); CalcForwardKinematics makes all current again.
  bool world_poses_current = false;
  /// True once a pose pass (inverse dynamics, forward kinematics) has filled X_PB and S_B, which
  /// CalcInverseDynamicsAtSameConfiguration reuses.
  bool poses_current = false;
  /// True while V_WB_B, A_WB_B and F_Bo_B are those of an inverse dynamics pass without applied
  /// wrenches at the poses in X_PB (what CalcRootWrenchWithJointChanged builds on); forward
  /// kinematics and a pass with applied wrenches make it false.
  bool plain_inverse_dynamics_current = false;
  /// Joint axes as angular-velocity directions in B: column k of the motion subspace of B's
  /// inboard Euler joint is [S_B[B][k]; 0] (RBDA ch. 4, joint models).
  std::vector<std::array<Vector3<T>, 3>> S_B;

  // Velocity and acceleration kinematics, about Bo, expressed in B.
  std::vector<SpatialMotion<T>> V_WB_B;
  /// Spatial accelerations; after inverse dynamics they include the fictitious −g of the base
  /// (RBDA ch. 5), after CalcCenterOfMassAcceleration they are the true accelerations.
  std::vector<SpatialMotion<T>> A_WB_B;

  /// After inverse dynamics: the spatial force that B's inboard joint transmits to B, about Bo in
  /// B (RBDA Table 5.1). For the root this is the net external wrench the motion needs besides
  /// gravity and the applied wrenches: the root residual.
  std::vector<SpatialForce<T>> F_Bo_B;
  /// Composite inertia of the subtree rooted at B, about Bo in B (RBDA Table 6.2).
  std::vector<SpatialInertia<T>> Ic_Bo_B;
  /// First mass moment of the subtree rooted at B about Bo in B (Σ m p_BoBcm_B over the subtree),
  /// and the subtree's mass; from CalcRootResidual.
  std::vector<Vector3<T>> mc_Bo_B;
  std::vector<T> subtree_mass;
  /// Scratch of CalcRootWrenchWithJointChanged: the changed subtree's motion and wrenches.
  std::vector<SpatialMotion<T>> V_changed;
  std::vector<SpatialMotion<T>> A_changed;
  std::vector<SpatialForce<T>> F_changed;
  std::vector<unsigned char> in_changed_subtree;

  VectorX<T> tau;  ///< generalised forces from inverse dynamics (nv)
  MatrixX<T> M;    ///< joint-space mass matrix from CalcMassMatrix (nv × nv)
  VectorX<T> h;    ///< bias forces from CalcBiasForces (nv)

  VectorX<T> sin_q;  ///< sin of the joint angles (entries 7… of q), from the last pose pass
  VectorX<T> cos_q;  ///< cos of the joint angles

 private:
  static size_t Size(const Model<T>& model) { return static_cast<size_t>(model.num_segments()); }
};

}  // namespace acro::dynamics
