#pragma once

// Shared fixtures for the dynamics tests: random trees covering every joint type and axis
// sequence, random states, and finite differences on the configuration manifold.

#include <Eigen/Geometry>
#include <random>
#include <string>
#include <vector>

#include "acro/dynamics/configuration.h"
#include "acro/dynamics/model_builder.h"

namespace acro::dynamics::testing {

/// Every Euler-angle sequence of 1–3 axes without an axis twice in a row (3 + 6 + 12 = 21), then
/// "" (a fixed joint).
inline std::vector<std::string> AllJointSequences() {
  std::vector<std::string> out;
  const std::string axes = "xyz";
  for (char a : axes) out.push_back(std::string(1, a));
  for (char a : axes)
    for (char b : axes)
      if (a != b) out.push_back(std::string{a, b});
  for (char a : axes)
    for (char b : axes)
      for (char c : axes)
        if (a != b && b != c) out.push_back(std::string{a, b, c});
  out.push_back("");
  return out;
}

inline double Uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

inline Eigen::Vector3d RandomVector(std::mt19937& rng, double scale) {
  return Eigen::Vector3d(
      Uniform(rng, -scale, scale), Uniform(rng, -scale, scale), Uniform(rng, -scale, scale));
}

inline Eigen::Quaterniond RandomQuaternion(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q;
}

/// Random physical mass properties: principal moments (b+c, a+c, a+b) of positive second moments
/// a, b, c (so the triangle inequality holds), rotated at random.
inline MassProperties RandomMass(std::mt19937& rng) {
  MassProperties m;
  m.mass_kg = Uniform(rng, 0.5, 10.0);
  m.p_BoBcm_B = RandomVector(rng, 0.3);
  const double a = Uniform(rng, 0.01, 0.2), b = Uniform(rng, 0.01, 0.2),
               c = Uniform(rng, 0.01, 0.2);
  const Eigen::Matrix3d R = RandomQuaternion(rng).toRotationMatrix();
  m.I_BBcm_B = R * Eigen::Vector3d(b + c, a + c, a + b).asDiagonal() * R.transpose();
  m.I_BBcm_B = 0.5 * (m.I_BBcm_B + m.I_BBcm_B.transpose()).eval();
  return m;
}

/// A random tree of `num_segments` segments; joint k (k ≥ 1) uses sequence
/// AllJointSequences()[(k − 1 + offset) mod 22], its parent is a random earlier segment, and every
/// other joint frame is rotated at random.
inline Model<double> MakeRandomTree(std::mt19937& rng, int num_segments, int offset) {
  const std::vector<std::string> seqs = AllJointSequences();
  ModelBuilder b("s0", RandomMass(rng));
  for (int k = 1; k < num_segments; ++k) {
    JointSpec j;
    j.axis_sequence = seqs[static_cast<size_t>(k - 1 + offset) % seqs.size()];
    j.p_PoJo_P = RandomVector(rng, 0.5);
    if (k % 2 == 0) j.R_PJ = RandomQuaternion(rng).toRotationMatrix();
    const int parent = std::uniform_int_distribution<int>(0, k - 1)(rng);
    b.AddSegment("s" + std::to_string(k), "s" + std::to_string(parent), j, RandomMass(rng));
    b.AddPoint("p" + std::to_string(k), "s" + std::to_string(k), RandomVector(rng, 0.4));
  }
  b.AddPoint("p0", "s0", RandomVector(rng, 0.4));
  b.SetGravity(Eigen::Vector3d(0.3, -0.2, -9.81));
  return b.Build();
}

/// A random configuration: root anywhere within 2 m, random unit quaternion, angles in (−π, π).
inline Eigen::VectorXd RandomConfiguration(const Model<double>& model, std::mt19937& rng) {
  Eigen::VectorXd q(model.nq());
  q.head<3>() = RandomVector(rng, 2.0);
  SetRootQuaternion(RandomQuaternion(rng), q);
  for (int k = 7; k < model.nq(); ++k) q[k] = Uniform(rng, -M_PI, M_PI);
  return q;
}

inline Eigen::VectorXd RandomVelocity(const Model<double>& model, std::mt19937& rng, double scale) {
  Eigen::VectorXd v(model.nv());
  for (int k = 0; k < model.nv(); ++k) v[k] = Uniform(rng, -scale, scale);
  return v;
}

/// q ⊕ v·dt as a new vector.
inline Eigen::VectorXd Integrate(const Model<double>& model,
                                 const Eigen::VectorXd& q,
                                 const Eigen::VectorXd& v,
                                 double dt) {
  Eigen::VectorXd out(model.nq());
  IntegrateConfiguration(model, q, v, dt, out);
  return out;
}

/// Rotation vector φ with exp([φ]×) = R.
inline Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// max|a − b| / max(max|b|, floor): a relative error with a floor for near-zero references.
inline double RelativeError(const Eigen::MatrixXd& a,
                            const Eigen::MatrixXd& b,
                            double floor = 1.0) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), floor);
}

}  // namespace acro::dynamics::testing
