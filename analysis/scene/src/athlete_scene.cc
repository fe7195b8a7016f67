#include "acro/scene/athlete_scene.h"

#include <stdexcept>
#include <string>

#include "acro/athlete/standard_human.h"
#include "acro/dynamics/kinematics.h"

namespace acro::analysis {

AthleteScene::AthleteScene(const AthleteBody& body, BodyMesh mesh, const Motion& motion)
    : AthleteScene(body, std::move(mesh), motion, MakeStandardHumanModel(body)) {}

AthleteScene::AthleteScene(const AthleteBody& body,
                           BodyMesh mesh,
                           const Motion& motion,
                           const dynamics::Model<double>& model)
    : model_(model), ws_(model_), mesh_(std::move(mesh)), q_(motion.q) {
  if (q_.rows() != model_.nq()) {
    throw std::invalid_argument("the motion has " + std::to_string(q_.rows()) +
                                " coordinates, the athlete's model " + std::to_string(model_.nq()));
  }
  if (mesh_.segment_names.size() != body.segments.size())
    throw std::invalid_argument("the mesh's segments are not the body's");
  // The model's segment frames are parallel to H at the body's configuration, with their origins
  // at the proximal joints (MakeStandardHumanModel), and the mesh was made in that configuration:
  // a vertex in segment g's frame is v_H − J_g.
  const Eigen::Index V = mesh_.vertices_H.cols();
  for (int k = 0; k < 2; ++k) {
    v_B_[k].resize(3, V);
    for (Eigen::Index i = 0; i < V; ++i) {
      const int g = mesh_.skin_segment(k, i);
      v_B_[k].col(i) = g < 0 ? Eigen::Vector3d::Zero()
                             : Eigen::Vector3d(mesh_.vertices_H.col(i) -
                                               body.segments[static_cast<size_t>(g)].p_HoJ_H);
    }
  }
  for (const BodySegment& s : body.segments) end_B_.push_back(s.p_HoE_H - s.p_HoJ_H);
  for (size_t g = 0; g < body.segments.size(); ++g) {
    if (model_.FindSegment(body.segments[g].name) != static_cast<int>(g))
      throw std::invalid_argument("segment " + body.segments[g].name +
                                  " is not where the model has it");
  }
}

void AthleteScene::Pose(int frame, AthletePose* out) {
  PoseConfiguration(q_.col(frame), out);
}

void AthleteScene::PoseConfiguration(const Eigen::VectorXd& q, AthletePose* out) {
  if (q.size() != model_.nq())
    throw std::invalid_argument("a configuration of " + std::to_string(q.size()) +
                                " numbers, the model has " + std::to_string(model_.nq()));
  dynamics::CalcForwardKinematics<double>(model_, ws_, q);
  const Eigen::Index V = mesh_.vertices_H.cols();
  if (out->mesh.triangles.cols() != mesh_.triangles.cols()) {
    out->mesh.name = "athlete";
    out->mesh.triangles = mesh_.triangles;
    out->mesh.colour = {0.85f, 0.65f, 0.5f, 1.0f};
    out->skeleton.name = "skeleton";
    out->skeleton.colour = {0.1f, 0.1f, 0.1f, 1.0f};
    out->skeleton.segment_sides.clear();
    for (int g = 0; g < model_.num_segments(); ++g)
      out->skeleton.segment_sides.push_back(SideOfName(model_.segment(g).name));
  }
  out->mesh.vertices_W.resize(3, V);
  for (Eigen::Index i = 0; i < V; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 2; ++k) {
      const int g = mesh_.skin_segment(k, i);
      const double w = mesh_.skin_weight(k, i);
      if (g < 0 || w == 0.0) continue;
      const auto& X = ws_.X_WB[static_cast<size_t>(g)];
      sum += w * (X.translation() + X.rotation() * v_B_[k].col(i));
    }
    out->mesh.vertices_W.col(i) = sum;
  }
  const int S = model_.num_segments();
  out->skeleton.points_W.resize(3, 2 * S);
  for (int g = 0; g < S; ++g) {
    const auto& X = ws_.X_WB[static_cast<size_t>(g)];
    out->skeleton.points_W.col(2 * g) = X.translation();
    out->skeleton.points_W.col(2 * g + 1) =
        X.translation() + X.rotation() * end_B_[static_cast<size_t>(g)];
  }
  out->com_W = dynamics::CalcCenterOfMassPosition<double>(model_, ws_);
}

Eigen::Matrix3Xd AthleteScene::CalcComPath() {
  Eigen::Matrix3Xd path(3, q_.cols());
  for (Eigen::Index f = 0; f < q_.cols(); ++f) {
    dynamics::CalcForwardKinematics<double>(model_, ws_, q_.col(f));
    path.col(f) = dynamics::CalcCenterOfMassPosition<double>(model_, ws_);
  }
  return path;
}

}  // namespace acro::analysis
