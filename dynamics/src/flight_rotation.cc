#include "acro/dynamics/flight_rotation.h"

#include "acro/base/demand.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/kinematics.h"
#include "acro/dynamics/workspace.h"

namespace acro::dynamics {

JointMotionSamples SampleJointMotion(const Model<double>& model,
                                     double duration_s,
                                     int num_steps,
                                     const JointTrajectory<double>& joints) {
  ACRO_DEMAND(num_steps > 0 && duration_s > 0.0);
  JointMotionSamples s;
  s.num_steps = num_steps;
  s.step_s = duration_s / num_steps;
  const auto nodes = static_cast<size_t>(2 * num_steps + 1);
  s.I_Scm_B_inverse.resize(nodes);
  s.H_joints_Scm_B.resize(nodes);
  // The root at rest at W's origin, so that W is B: poses, velocities and momenta come out in B.
  Workspace<double> ws(model);
  const int nj = model.num_joint_dofs();
  VectorX<double> q = MakeNeutralConfiguration(model);
  VectorX<double> v = VectorX<double>::Zero(model.nv());
  VectorX<double> a(nj);
  const double m = model.total_mass();
  for (size_t k = 0; k < nodes; ++k) {
    joints(0.5 * s.step_s * static_cast<double>(k), q.tail(nj), v.tail(nj), a);
    CalcForwardKinematics(model, ws, q, v);
    // The whole body's spatial inertia and the joints' momentum, both about Bo (RBDA ch. 2).
    SpatialInertia<double> I_Bo = SpatialInertia<double>::Zero();
    SpatialMomentum<double> L_Bo = SpatialMomentum<double>::Zero();
    for (int i = 0; i < model.num_segments(); ++i) {
      const auto ui = static_cast<size_t>(i);
      const SpatialInertia<double>& M = model.segment(i).M_Bo_B;
      I_Bo += ws.X_WB[ui].Apply(M);
      L_Bo += ws.X_WB[ui].Apply(M.Momentum(ws.V_WB_B[ui]));
    }
    // Moved to Scm: I_Scm = I_Bo + m [c]×[c]× (the parallel axis theorem, c = p_BoScm), and the
    // angular momentum about Scm is the one about Bo minus c × the linear momentum.
    const Vector3<double> c = I_Bo.first_moment() / m;
    const Matrix3<double> C = Skew(c);
    const Matrix3<double> I_Scm = I_Bo.rotational_inertia() + m * C * C;
    s.I_Scm_B_inverse[k] = I_Scm.inverse();
    s.H_joints_Scm_B[k] = L_Bo.rotational() - c.cross(L_Bo.translational());
  }
  return s;
}

std::vector<Eigen::Quaterniond> SimulateFlightRotation(const JointMotionSamples& samples,
                                                       const Eigen::Quaterniond& q_WB0,
                                                       const Vector3<double>& H_Scm_W) {
  using Vector4 = Eigen::Vector4d;  // w x y z, as the root's coordinates in q
  // q̇ = ½ q ⊗ (0, ω_B) with ω_B from (1) at sample k.
  auto derivative = [&](size_t k, const Vector4& y) {
    const Eigen::Quaterniond qn = Eigen::Quaterniond(y[0], y[1], y[2], y[3]).normalized();
    const Vector3<double> w =
        samples.I_Scm_B_inverse[k] *
        (qn.toRotationMatrix().transpose() * H_Scm_W - samples.H_joints_Scm_B[k]);
    return Vector4(-0.5 * (y[1] * w[0] + y[2] * w[1] + y[3] * w[2]),
                   0.5 * (y[0] * w[0] + y[2] * w[2] - y[3] * w[1]),
                   0.5 * (y[0] * w[1] + y[3] * w[0] - y[1] * w[2]),
                   0.5 * (y[0] * w[2] + y[1] * w[1] - y[2] * w[0]));
  };
  std::vector<Eigen::Quaterniond> out;
  out.reserve(static_cast<size_t>(samples.num_steps) + 1);
  const Eigen::Quaterniond q0 = q_WB0.normalized();
  Vector4 y(q0.w(), q0.x(), q0.y(), q0.z());
  out.push_back(q0);
  const double h = samples.step_s;
  for (int step = 0; step < samples.num_steps; ++step) {
    // Classical RK4 (Hairer, Nørsett & Wanner 1993, §II.1); samples 2k, 2k + 1, 2k + 2.
    const auto k = static_cast<size_t>(2 * step);
    const Vector4 k1 = derivative(k, y);
    const Vector4 k2 = derivative(k + 1, y + 0.5 * h * k1);
    const Vector4 k3 = derivative(k + 1, y + 0.5 * h * k2);
    const Vector4 k4 = derivative(k + 2, y + h * k3);
    y += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    y.normalize();
    out.emplace_back(y[0], y[1], y[2], y[3]);
  }
  return out;
}

}  // namespace acro::dynamics
