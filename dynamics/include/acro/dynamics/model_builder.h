#pragma once

// Validating builder of a Model<double>. Every Add… call checks its input at once and throws
// acro::InputError naming the segment or point and the value at fault; Build() returns the const
// model (convert it with Model::Cast<U>() for another scalar type).

#include <string>
#include <vector>

#include "acro/dynamics/model.h"

namespace acro::dynamics {

/// Mass properties of a segment in its own frame B.
struct MassProperties {
  double mass_kg = 0.0;
  Eigen::Vector3d p_BoBcm_B = Eigen::Vector3d::Zero();
  /// Rotational inertia about the centre of mass, kg·m²; symmetric positive definite, principal
  /// moments satisfying the triangle inequality.
  Eigen::Matrix3d I_BBcm_B = Eigen::Matrix3d::Zero();
};

/// How a segment is attached to its parent P.
struct JointSpec {
  /// "" for a fixed joint, else 1–3 letters from {x, y, z}, no letter twice in a row.
  std::string axis_sequence;
  /// Joint centre in the parent frame; it becomes the child segment's origin.
  Eigen::Vector3d p_PoJo_P = Eigen::Vector3d::Zero();
  /// Orientation of the joint frame J (the child frame at zero angles) in the parent frame.
  Eigen::Matrix3d R_PJ = Eigen::Matrix3d::Identity();
};

class ModelBuilder {
 public:
  /// Starts a model whose root segment (free joint) is `root_name`.
  ModelBuilder(const std::string& root_name, const MassProperties& root_mass);

  /// Adds a segment under `parent_name`; returns its index. Throws acro::InputError on an unknown
  /// parent, a duplicate name, an invalid axis sequence or invalid mass properties.
  int AddSegment(const std::string& name,
                 const std::string& parent_name,
                 const JointSpec& joint,
                 const MassProperties& mass);

  /// Adds a named point fixed in segment `segment_name` at p_BoP_B; returns its index.
  int AddPoint(const std::string& name,
               const std::string& segment_name,
               const Eigen::Vector3d& p_BoP_B);

  /// Gravity in W; default (0, 0, −9.81) m/s².
  void SetGravity(const Eigen::Vector3d& gravity_W);

  Model<double> Build() const;

 private:
  Model<double> model_;
};

/// Throws acro::InputError (naming `what`) unless the mass properties are physical: finite
/// positive mass, finite centre of mass, inertia symmetric positive definite with principal moments
/// satisfying the triangle inequality.
void ValidateMassProperties(const std::string& what, const MassProperties& mass);

}  // namespace acro::dynamics
