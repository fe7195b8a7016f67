// The athlete posed by a motion: the mesh where the model's segments put it (a second computation:
// the posed mesh's own mass properties, integrated over its polyhedra, against the model's centre
// of mass), and rigid where it should be.

#include "acro/scene/athlete_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include <Eigen/Geometry>

#include "acro/athlete/de_leva.h"
#include "acro/athlete/inertial_properties.h"
#include "acro/dynamics/configuration.h"
#include "acro/scene/trial_scene.h"

namespace acro::analysis {
namespace {

Motion TwoFrames(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Motion m;
  m.q.resize(a.size(), 2);
  m.q.col(0) = a;
  m.q.col(1) = b;
  m.time_s = Eigen::Vector2d(0.0, 0.01);
  m.rate_hz = 100;
  return m;
}

TEST(AthleteScene, ReferenceConfigurationPlacesTheMeshAtTheRoot) {
  const AthleteBody body = MakeDeLevaBody(1.70, 60.0, Sex::kFemale);
  BodyMeshOptions options;
  options.skin_blend_m = 0.0;
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body, options);
  const int nq = 7 + 32;
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(nq);
  q0.head<3>() = Eigen::Vector3d(1.0, -2.0, 3.5);
  dynamics::SetRootQuaternion<double>(Eigen::Quaterniond::Identity(), q0);
  AthleteScene scene(body, mesh, TwoFrames(q0, q0));
  AthletePose pose;
  scene.Pose(0, &pose);
  ASSERT_EQ(pose.mesh.vertices_W.cols(), mesh.vertices_H.cols());
  // The pelvis' joint is H's origin: every vertex is moved by the root's position only.
  const Eigen::Matrix3Xd expected = mesh.vertices_H.colwise() + q0.head<3>();
  EXPECT_LT((pose.mesh.vertices_W - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(pose.mesh.triangles, mesh.triangles);
  EXPECT_EQ(pose.skeleton.num_segments(), 15);
  // Coloured by side: the six limb segments of each side, the pelvis, thorax and head between.
  ASSERT_EQ(pose.skeleton.segment_sides.size(), 15u);
  const auto count = [&](BodySide side) {
    return std::count(pose.skeleton.segment_sides.begin(), pose.skeleton.segment_sides.end(), side);
  };
  EXPECT_EQ(count(BodySide::kLeft), 6);
  EXPECT_EQ(count(BodySide::kRight), 6);
  EXPECT_EQ(count(BodySide::kCentre), 3);
  EXPECT_LT((pose.com_W - (body.total.p_HoCm_H + q0.head<3>())).norm(), 1e-9);
}

// A tumbling, twisted configuration: the posed ellipsoids' own centre of mass (integration over
// the polyhedra) is the model's, and a vertex that follows one segment keeps its distance to that
// segment's joint.
TEST(AthleteScene, PosedMeshCarriesTheModelsCentreOfMass) {
  const AthleteBody body = MakeDeLevaBody(1.62, 55.0, Sex::kFemale);
  BodyMeshOptions options;
  options.skin_blend_m =
      0.0;  // rigid parts: their mass properties must follow the segments exactly
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body, options);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(39);
  q.head<3>() = Eigen::Vector3d(0.3, 0.1, 4.2);
  dynamics::SetRootQuaternion<double>(
      Eigen::Quaterniond(Eigen::AngleAxisd(2.4, Eigen::Vector3d(0.3, 1.0, 0.2).normalized())), q);
  for (int i = 7; i < 39; ++i) q[i] = angle(rng);
  AthleteScene scene(body, mesh, TwoFrames(q, q));
  AthletePose pose;
  scene.Pose(1, &pose);
  BodyMesh posed = mesh;
  posed.vertices_H = pose.mesh.vertices_W;
  const std::vector<InertialProperties> parts = CalcMeshPartInertia(posed);
  const InertialProperties whole = CombineInertia(parts);
  EXPECT_LT((whole.p_HoCm_H - pose.com_W).norm(), 1e-9)
      << whole.p_HoCm_H.transpose() << " vs " << pose.com_W.transpose();
  // The path of the centre of mass has one point per frame.
  EXPECT_EQ(scene.CalcComPath().cols(), 2);
  // Distances to the proximal joint are kept by single-segment vertices.
  int checked = 0;
  for (Eigen::Index i = 0; i < mesh.vertices_H.cols(); i += 37) {
    const int g = mesh.skin_segment(0, i);
    if (mesh.skin_weight(0, i) != 1.0) continue;
    const double rest = (mesh.vertices_H.col(i) - body.segments[size_t(g)].p_HoJ_H).norm();
    const double posed_distance =
        (pose.mesh.vertices_W.col(i) - pose.skeleton.points_W.col(2 * g)).norm();
    EXPECT_NEAR(posed_distance, rest, 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

TEST(AthleteScene, MismatchedMotionIsRefused) {
  const AthleteBody body = MakeDeLevaBody(1.70, 60.0, Sex::kMale);
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body);
  Motion m;
  m.q = Eigen::MatrixXd::Zero(10, 3);
  EXPECT_THROW(AthleteScene(body, mesh, m), std::invalid_argument);
}

// Sides from names as the vendors write them: model segments, OpenPose/COCO keypoints, Plug-in
// Gait markers, words; spine names that begin with L or R are not sides.
TEST(BodySide, SideOfNameReadsEveryNaming) {
  for (const char* left :
       {"l_thigh", "LKnee", "LASI", "left_knee", "LeftHip", "LEFT_ANKLE", "L.Hip"})
    EXPECT_EQ(SideOfName(left), BodySide::kLeft) << left;
  for (const char* right : {"r_foot", "RBigToe", "RHEE", "right_wrist", "RightShoulder"})
    EXPECT_EQ(SideOfName(right), BodySide::kRight) << right;
  for (const char* centre : {"pelvis", "Neck", "Nose", "Lumbar", "L5", "Root", "CLAV", "head", "R"})
    EXPECT_EQ(SideOfName(centre), BodySide::kCentre) << centre;
  const Rgba trunk{0.9f, 0.9f, 0.9f, 0.5f};
  EXPECT_EQ(SideColour(BodySide::kCentre, trunk).g, trunk.g);
  EXPECT_GT(SideColour(BodySide::kLeft, trunk).r, 0.9f);   // red
  EXPECT_GT(SideColour(BodySide::kRight, trunk).g, 0.8f);  // green
  EXPECT_EQ(SideColour(BodySide::kRight, trunk).a, trunk.a);
}

// Keypoints joined by their names, each link on its side: the legs of each side, the hips across
// and the neck to the nose between.
TEST(BodySide, KeypointLinksTakeTheirEndsSide) {
  const std::vector<std::string> names = {
      "RHip", "RKnee", "RAnkle", "LHip", "LKnee", "LAnkle", "Neck", "Nose"};
  const std::vector<std::pair<int, int>> links = KeypointLinks(names);
  const std::vector<BodySide> sides = KeypointLinkSides(names, links);
  ASSERT_EQ(sides.size(), links.size());
  std::map<std::pair<std::string, std::string>, BodySide> by_name;
  for (size_t k = 0; k < links.size(); ++k)
    by_name[{names[size_t(links[k].first)], names[size_t(links[k].second)]}] = sides[k];
  EXPECT_EQ(by_name.size(), 6u);
  EXPECT_EQ((by_name[{"RHip", "RKnee"}]), BodySide::kRight);
  EXPECT_EQ((by_name[{"RKnee", "RAnkle"}]), BodySide::kRight);
  EXPECT_EQ((by_name[{"LHip", "LKnee"}]), BodySide::kLeft);
  EXPECT_EQ((by_name[{"LKnee", "LAnkle"}]), BodySide::kLeft);
  EXPECT_EQ((by_name[{"RHip", "LHip"}]), BodySide::kCentre);
  EXPECT_EQ((by_name[{"Neck", "Nose"}]), BodySide::kCentre);
}

}  // namespace
}  // namespace acro::analysis
