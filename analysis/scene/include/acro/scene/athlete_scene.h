#pragma once

// The athlete of a motion, posed frame by frame: the body mesh skinned onto the segments' world
// poses, the skeleton (each segment's proximal joint to its distal end), the centre of mass and
// its path. Built once per trial; Pose() reuses the caller's buffers, so a renderer updates its
// actors per frame without allocating.

#include <vector>

#include <Eigen/Core>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/body_mesh.h"
#include "acro/athlete/motion.h"
#include "acro/dynamics/model.h"
#include "acro/dynamics/workspace.h"
#include "acro/scene/scene.h"

namespace acro::analysis {

/// One frame of the athlete.
struct AthletePose {
  SceneMesh mesh;       ///< the body mesh in W (triangles set once)
  SceneLines skeleton;  ///< per segment: proximal joint → distal end
  Eigen::Vector3d com_W = Eigen::Vector3d::Zero();
};

class AthleteScene {
 public:
  /// `body` is the athlete the motion was reconstructed (or designed) for, `mesh` its mesh in the
  /// same configuration (MakeBodyMesh or MakeEllipsoidBodyMesh of that body), `motion` q(t) of the
  /// standard human model of that body. Throws std::invalid_argument when the three disagree (the
  /// motion's coordinates, the mesh's segments).
  AthleteScene(const AthleteBody& body, BodyMesh mesh, const Motion& motion);
  /// The same posed by `model` — the model the motion was reconstructed with when the
  /// reconstruction scaled the body's (ReconstructionResult::model): the skeleton and the COM are
  /// that model's exactly; the mesh keeps the body's shape about each scaled joint.
  AthleteScene(const AthleteBody& body,
               BodyMesh mesh,
               const Motion& motion,
               const dynamics::Model<double>& model);

  int num_frames() const { return static_cast<int>(q_.cols()); }
  const BodyMesh& mesh() const { return mesh_; }

  /// Frame `frame` of the motion into `out` (allocates only on the first call with `out`).
  void Pose(int frame, AthletePose* out);
  /// Any configuration of the model (nq numbers), e.g. a designed skill's.
  void PoseConfiguration(const Eigen::VectorXd& q, AthletePose* out);

  /// The centre of mass over every frame (3 × frames, W): its path.
  Eigen::Matrix3Xd CalcComPath();

 private:
  dynamics::Model<double> model_;
  dynamics::Workspace<double> ws_;
  BodyMesh mesh_;
  Eigen::MatrixXd q_;
  /// Per vertex and skin slot (2): the vertex in that segment's frame B (parallel to H at the
  /// body's configuration, origin at its proximal joint).
  Eigen::Matrix3Xd v_B_[2];
  /// Per segment: its distal end in its frame B.
  std::vector<Eigen::Vector3d> end_B_;
};

}  // namespace acro::analysis
