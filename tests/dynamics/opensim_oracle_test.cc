// OpenSim's inverse dynamics as an oracle: the Arm26 example of opensim-models
// (../shared/refdata/opensim-models, Tutorials/Computed_Muscle_Control/OutputReference): a
// two-degree-of-freedom arm (shoulder elevation, elbow flexion) under gravity alone, its IK
// coordinates and the joint moments OpenSim's InverseDynamicsTool computed from them. The model is
// read from arm26.osim here (bodies, joints, gravity), built with our ModelBuilder, and driven by
// the same coordinates; the moments are compared joint by joint.
//
// How the models correspond: an OpenSim CustomJoint turns its child about an axis a given in the
// parent's offset frame; our Euler joints turn about an axis of the joint frame J. The joint frame
// is chosen with z = a, so our child frame O and OpenSim's body frame B differ by a constant
// rotation, B = O·M with M = R_PJᵀ M_parent; mass properties and child joint locations are carried
// into O with M (p_O = M p_B, I_O = M I_B Mᵀ).
//
// Derivatives: OpenSim fits GCV splines to the coordinates; here a natural cubic spline through
// the same samples gives q̇ and q̈. The unfiltered result isolates the dynamics from the filter
// (the setup's 6 Hz low-pass differs between implementations and changes the moments by up to
// 0.13 N·m: expected.md), so that is the one compared.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <pugixml.hpp>

#include "acro/base/cubic_spline.h"
#include "acro/capture/storage.h"
#include "acro/dynamics/configuration.h"
#include "acro/dynamics/inverse_dynamics.h"
#include "acro/dynamics/model_builder.h"
#include "refdata.h"

namespace acro::dynamics {
namespace {

constexpr const char* kArm26 = "opensim-models/Tutorials/Computed_Muscle_Control/OutputReference";

Eigen::Vector3d ReadVector(const pugi::xml_node& node) {
  std::istringstream in(node.child_value());
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

// A body of the .osim: mass, centre of mass and inertia about it in the body frame.
MassProperties ReadBody(const pugi::xml_document& doc, const std::string& name) {
  const pugi::xml_node body =
      doc.select_node(("//BodySet/objects/Body[@name='" + name + "']").c_str()).node();
  EXPECT_TRUE(body) << name;
  MassProperties m;
  m.mass_kg = std::stod(body.child("mass").child_value());
  m.p_BoBcm_B = ReadVector(body.child("mass_center"));
  std::istringstream in(body.child("inertia").child_value());
  double xx, yy, zz, xy, xz, yz;
  in >> xx >> yy >> zz >> xy >> xz >> yz;
  m.I_BBcm_B << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return m;
}

// A CustomJoint with one rotational coordinate: where it sits in the parent body, about which axis
// it turns (both in the parent body's frame: the offset frames of Arm26 are not rotated).
struct OsimJoint {
  Eigen::Vector3d location_in_parent = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  std::string coordinate;
};

OsimJoint ReadJoint(const pugi::xml_document& doc, const std::string& name) {
  const pugi::xml_node joint =
      doc.select_node(("//JointSet/objects/CustomJoint[@name='" + name + "']").c_str()).node();
  EXPECT_TRUE(joint) << name;
  OsimJoint out;
  const std::string parent_frame = joint.child("socket_parent_frame").child_value();
  for (const pugi::xml_node frame : joint.child("frames").children("PhysicalOffsetFrame")) {
    EXPECT_EQ(ReadVector(frame.child("orientation")).norm(), 0.0) << name << ": rotated frame";
    if (frame.attribute("name").value() == parent_frame)
      out.location_in_parent = ReadVector(frame.child("translation"));
  }
  // The one transform axis that has a coordinate; every other axis has none (stays at zero).
  int with_coordinate = 0;
  for (const pugi::xml_node axis : joint.child("SpatialTransform").children("TransformAxis")) {
    std::istringstream coordinates(axis.child_value("coordinates"));
    std::string coordinate;
    if (!(coordinates >> coordinate)) continue;
    ++with_coordinate;
    EXPECT_EQ(std::string(axis.attribute("name").value()), "rotation1") << name;
    out.axis = ReadVector(axis.child("axis")).normalized();
    out.coordinate = coordinate;
  }
  EXPECT_EQ(with_coordinate, 1) << name;
  return out;
}

// A rotation whose z column is `axis`.
Eigen::Matrix3d FrameWithZ(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d helper =
      std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = helper.cross(z).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return R;
}

MassProperties InFrame(const MassProperties& m, const Eigen::Matrix3d& M) {
  MassProperties out = m;
  out.p_BoBcm_B = M * m.p_BoBcm_B;
  out.I_BBcm_B = M * m.I_BBcm_B * M.transpose();
  return out;
}

TEST(OpenSimOracleTest, Arm26JointMomentsMatchOpenSimsInverseDynamics) {
  const std::filesystem::path dir = acro::testing::RefdataFile(kArm26);
  ACRO_REQUIRE_REFDATA_FILE(dir / "arm26.osim");
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file((dir / "arm26.osim").c_str()));

  // The model: base (welded to the ground 0.8 m up; our free root, held still), humerus, forearm.
  const Eigen::Vector3d gravity = ReadVector(doc.select_node("//Model/gravity").node());
  const Eigen::Vector3d base_in_ground = ReadVector(
      doc.select_node("//WeldJoint/frames/PhysicalOffsetFrame[@name='ground_offset']/translation")
          .node());
  const OsimJoint shoulder = ReadJoint(doc, "r_shoulder");
  const OsimJoint elbow = ReadJoint(doc, "r_elbow");
  ASSERT_EQ(shoulder.coordinate, "r_shoulder_elev");
  ASSERT_EQ(elbow.coordinate, "r_elbow_flex");
  // The base has no mass in OpenSim; any mass will do, held still it adds nothing to the joints.
  MassProperties base;
  base.mass_kg = 1.0;
  base.I_BBcm_B = 0.01 * Eigen::Matrix3d::Identity();
  ModelBuilder builder("base", base);
  builder.SetGravity(gravity);
  JointSpec shoulder_joint;
  shoulder_joint.axis_sequence = "z";
  shoulder_joint.p_PoJo_P = shoulder.location_in_parent;
  shoulder_joint.R_PJ = FrameWithZ(shoulder.axis);
  const Eigen::Matrix3d M_humerus = shoulder_joint.R_PJ.transpose();
  builder.AddSegment(
      "r_humerus", "base", shoulder_joint, InFrame(ReadBody(doc, "r_humerus"), M_humerus));
  JointSpec elbow_joint;
  elbow_joint.axis_sequence = "z";
  elbow_joint.p_PoJo_P = M_humerus * elbow.location_in_parent;
  elbow_joint.R_PJ = FrameWithZ(M_humerus * elbow.axis);
  const Eigen::Matrix3d M_forearm = elbow_joint.R_PJ.transpose() * M_humerus;
  builder.AddSegment("r_ulna_radius_hand",
                     "r_humerus",
                     elbow_joint,
                     InFrame(ReadBody(doc, "r_ulna_radius_hand"), M_forearm));
  const Model<double> model = builder.Build();
  ASSERT_EQ(model.nv(), 8);

  // The coordinates (degrees in the file) and their spline derivatives.
  const capture::Storage ik =
      capture::ReadStorage(dir / "InverseKinematics/arm26_InverseKinematics.mot");
  const capture::Storage reference =
      capture::ReadStorage(dir / "InverseDynamics/UnfilteredResults/arm26_InverseDynamics.sto");
  const int n = static_cast<int>(ik.time_s.size());
  ASSERT_EQ(reference.time_s.size(), n);
  const std::vector<double> t(ik.time_s.data(), ik.time_s.data() + n);
  std::vector<CubicSpline<double>> splines;
  for (const char* name : {"r_shoulder_elev", "r_elbow_flex"}) {
    const int c = ik.FindColumn(name);
    ASSERT_GE(c, 0) << name;
    std::vector<double> q(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) q[static_cast<size_t>(k)] = ik.data(k, c) * M_PI / 180.0;
    splines.emplace_back(t, q);
  }
  const int shoulder_column = reference.FindColumn("r_shoulder_elev_moment");
  const int elbow_column = reference.FindColumn("r_elbow_flex_moment");
  ASSERT_GE(shoulder_column, 0);
  ASSERT_GE(elbow_column, 0);

  // Inverse dynamics at every sample, the base held still at its weld: once with the spline's
  // derivatives, once with five-point central differences (a second estimate of q̇ and q̈, to tell
  // differentiation from dynamics).
  Workspace<double> ws(model);
  const double h = t[1] - t[0];
  auto moments = [&](int k, bool differences) {
    Eigen::VectorXd q = MakeNeutralConfiguration(model), v = Eigen::VectorXd::Zero(8),
                    a = Eigen::VectorXd::Zero(8);
    q.head<3>() = base_in_ground;
    for (int j = 0; j < 2; ++j) {
      const CubicSpline<double>& spline = splines[static_cast<size_t>(j)];
      const SplineSample<double> s = spline.Eval(t[static_cast<size_t>(k)]);
      q[kRootNq + j] = s.value;
      v[kRootNv + j] = s.d1;
      a[kRootNv + j] = s.d2;
      if (differences) {
        double y[5];
        for (int i = 0; i < 5; ++i) y[i] = spline.Eval(t[static_cast<size_t>(k + i - 2)]).value;
        v[kRootNv + j] = (y[0] - 8 * y[1] + 8 * y[3] - y[4]) / (12 * h);
        a[kRootNv + j] = (-y[0] + 16 * y[1] - 30 * y[2] + 16 * y[3] - y[4]) / (12 * h * h);
      }
    }
    return Eigen::Vector2d(CalcInverseDynamics(model, ws, q, v, a).segment<2>(kRootNv));
  };

  // Away from the ends (5 samples each side, where the spline's natural end conditions and
  // OpenSim's GCV splines differ most), sample by sample.
  std::vector<double> errors;
  double worst_unexplained = 0.0, peak = 0.0;
  for (int k = 5; k < n - 5; ++k) {
    EXPECT_NEAR(reference.time_s[k], ik.time_s[k], 1e-6);
    const Eigen::Vector2d ours = moments(k, false);
    const Eigen::Vector2d second = moments(k, true);
    const Eigen::Vector2d opensim(reference.data(k, shoulder_column),
                                  reference.data(k, elbow_column));
    for (int j = 0; j < 2; ++j) {
      const double error = std::abs(ours[j] - opensim[j]);
      errors.push_back(error);
      // What two differentiations of the same samples disagree by is not a dynamics error.
      worst_unexplained = std::max(worst_unexplained, error - std::abs(ours[j] - second[j]));
      peak = std::max(peak, std::abs(opensim[j]));
    }
  }
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  RecordProperty("median_Nm", std::to_string(median));
  RecordProperty("max_Nm", std::to_string(errors.back()));
  RecordProperty("worst_unexplained_Nm", std::to_string(worst_unexplained));
  RecordProperty("peak_Nm", std::to_string(peak));
  // Measured: median 0.8 mN·m, largest 24 mN·m (1 % of the 2.3 N·m peak) where the samples'
  // accelerations are noisy. OpenSim holds its own ID result to 10 mN·m against its standard
  // (testID.cpp, expected.md): the median must be well inside that, and every larger difference
  // must be one that a second differentiation of the same coordinates reproduces.
  EXPECT_LT(median, 2e-3);
  EXPECT_LT(errors.back(), 0.03);
  EXPECT_LT(worst_unexplained, 5e-3);
}

}  // namespace
}  // namespace acro::dynamics
