#include "acro/dynamics/model_builder.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "acro/base/input_error.h"

namespace acro::dynamics {
namespace {

constexpr char kSource[] = "ModelBuilder";
constexpr double kEps = std::numeric_limits<double>::epsilon();

std::string Quoted(const std::string& s) {
  return "'" + s + "'";
}

std::string Format(const Eigen::MatrixXd& m) {
  std::ostringstream out;
  out.precision(6);
  out << "[";
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) out << (c ? " " : "") << m(r, c);
    out << (r + 1 < m.rows() ? "; " : "");
  }
  out << "]";
  return out.str();
}

Segment<double> MakeSegment(const std::string& name, const MassProperties& mass) {
  Segment<double> s;
  s.name = name;
  s.mass = mass.mass_kg;
  s.p_BoBcm_B = mass.p_BoBcm_B;
  s.I_BBcm_B = mass.I_BBcm_B;
  s.M_Bo_B =
      SpatialInertia<double>::FromMassComInertia(mass.mass_kg, mass.p_BoBcm_B, mass.I_BBcm_B);
  s.X_PJ = RigidTransform<double>::Identity();
  return s;
}

}  // namespace

void ValidateMassProperties(const std::string& what, const MassProperties& mass) {
  if (!(std::isfinite(mass.mass_kg) && mass.mass_kg > 0.0))
    throw InputError(kSource, what, "mass must be positive, got " + std::to_string(mass.mass_kg));
  if (!mass.p_BoBcm_B.allFinite())
    throw InputError(kSource, what, "centre of mass is not finite: " + Format(mass.p_BoBcm_B));
  const Eigen::Matrix3d& I = mass.I_BBcm_B;
  if (!I.allFinite()) throw InputError(kSource, what, "inertia is not finite: " + Format(I));
  const double scale = I.cwiseAbs().maxCoeff();
  // Symmetry to rounding: a few ulps of the largest entry.
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > 8 * kEps * scale)
    throw InputError(kSource, what, "inertia is not symmetric: " + Format(I));
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  if (!(moments.minCoeff() > 0.0))
    throw InputError(kSource, what, "inertia is not positive definite: " + Format(I));
  // Triangle inequality of principal moments (each ≤ sum of the others), allowing the
  // eigen-solver's rounding (a few ulps of the largest moment): a thin rod or flat plate is the
  // limiting case.
  const double largest = moments.maxCoeff();
  if (moments.sum() - 2.0 * largest < -16 * kEps * largest)
    throw InputError(
        kSource,
        what,
        "principal moments " + Format(moments.transpose()) + " violate the triangle inequality");
}

ModelBuilder::ModelBuilder(const std::string& root_name, const MassProperties& root_mass) {
  if (root_name.empty()) throw InputError(kSource, "root segment", "name is empty");
  ValidateMassProperties("segment " + Quoted(root_name), root_mass);
  Segment<double> root = MakeSegment(root_name, root_mass);
  root.parent = -1;
  root.joint_type = JointType::kFree;
  root.q_start = 0;
  root.v_start = 0;
  model_.segments_.push_back(root);
  model_.gravity_W_ = Eigen::Vector3d(0.0, 0.0, -9.81);
  model_.total_mass_ = root_mass.mass_kg;
  model_.nq_ = 7;
  model_.nv_ = 6;
  model_.max_depth_ = 1;
}

int ModelBuilder::AddSegment(const std::string& name,
                             const std::string& parent_name,
                             const JointSpec& joint,
                             const MassProperties& mass) {
  const std::string what = "segment " + Quoted(name);
  if (name.empty())
    throw InputError(kSource, "segment under " + Quoted(parent_name), "name is empty");
  if (model_.FindSegment(name) >= 0) throw InputError(kSource, what, "duplicate segment name");
  const int parent = model_.FindSegment(parent_name);
  if (parent < 0) throw InputError(kSource, what, "unknown parent " + Quoted(parent_name));
  ValidateMassProperties(what, mass);

  // Axis sequence: 0–3 letters from {x, y, z}, none repeated twice in a row.
  const std::string& seq = joint.axis_sequence;
  if (seq.size() > 3)
    throw InputError(kSource, what, "axis sequence " + Quoted(seq) + " has more than 3 axes");
  Segment<double> s = MakeSegment(name, mass);
  for (size_t k = 0; k < seq.size(); ++k) {
    const char c = seq[k];
    if (c != 'x' && c != 'y' && c != 'z')
      throw InputError(
          kSource, what, "axis sequence " + Quoted(seq) + " has a letter other than x, y, z");
    if (k > 0 && seq[k - 1] == c)
      throw InputError(
          kSource, what, "axis sequence " + Quoted(seq) + " repeats an axis twice in a row");
    s.axes[k] = c - 'x';
  }
  if (!joint.p_PoJo_P.allFinite())
    throw InputError(kSource, what, "joint centre is not finite: " + Format(joint.p_PoJo_P));
  const Eigen::Matrix3d& R = joint.R_PJ;
  // A rotation to rounding: orthonormal and right-handed (tolerance: a few ulps per entry).
  if (!R.allFinite() ||
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 64 * kEps ||
      R.determinant() <= 0.0)
    throw InputError(kSource, what, "joint frame R_PJ is not a rotation: " + Format(R));

  s.parent = parent;
  s.joint_type = seq.empty() ? JointType::kFixed : JointType::kEuler;
  s.axis_sequence = seq;
  s.num_axes = static_cast<int>(seq.size());
  s.q_start = model_.nq_;
  s.v_start = model_.nv_;
  s.X_PJ = RigidTransform<double>(R, joint.p_PoJo_P);
  s.joint_rotation_is_identity = (R == Eigen::Matrix3d::Identity());
  model_.segments_.push_back(s);
  model_.nq_ += s.num_axes;
  model_.nv_ += s.num_axes;
  model_.total_mass_ += mass.mass_kg;

  // Depth of the new leaf.
  int depth = 1;
  for (int i = model_.num_segments() - 1; model_.segment(i).parent >= 0;
       i = model_.segment(i).parent)
    ++depth;
  model_.max_depth_ = std::max(model_.max_depth_, depth);
  return model_.num_segments() - 1;
}

int ModelBuilder::AddPoint(const std::string& name,
                           const std::string& segment_name,
                           const Eigen::Vector3d& p_BoP_B) {
  const std::string what = "point " + Quoted(name);
  if (name.empty()) throw InputError(kSource, "point on " + Quoted(segment_name), "name is empty");
  if (model_.FindPoint(name) >= 0) throw InputError(kSource, what, "duplicate point name");
  const int segment = model_.FindSegment(segment_name);
  if (segment < 0) throw InputError(kSource, what, "unknown segment " + Quoted(segment_name));
  if (!p_BoP_B.allFinite())
    throw InputError(kSource, what, "position is not finite: " + Format(p_BoP_B));
  Point<double> p;
  p.name = name;
  p.segment = segment;
  p.p_BoP_B = p_BoP_B;
  model_.points_.push_back(p);
  return model_.num_points() - 1;
}

void ModelBuilder::SetGravity(const Eigen::Vector3d& gravity_W) {
  if (!gravity_W.allFinite())
    throw InputError(kSource, "gravity", "not finite: " + Format(gravity_W));
  model_.gravity_W_ = gravity_W;
}

Model<double> ModelBuilder::Build() const {
  return model_;
}

}  // namespace acro::dynamics
